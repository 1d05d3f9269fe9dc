#pragma once
/// \file read_error.h
/// The one exception type of every reader in nurbs/io: the message names the file, where in it
/// (line number and/or IGES directory entry), and what is wrong.
#include <stdexcept>
#include <string>
#include <string_view>

namespace nurbs::io {

/// `text` with every byte below 0x20 and DEL written as \xNN, so that bytes quoted from a bad file
/// cannot move the cursor, clear the terminal or split a message; '\n' is kept when `keep_newlines`
/// (a message of several lines).
[[nodiscard]] inline std::string printable(std::string_view text, bool keep_newlines = false) {
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto b = static_cast<unsigned char>(c);
    if ((b >= 0x20 && b != 0x7f) || (keep_newlines && c == '\n')) {
      out += c;
    } else {
      out += "\\x";
      out += hex[b >> 4];
      out += hex[b & 15];
    }
  }
  return out;
}

/// Thrown by the IGES and .bpt readers for malformed or unsupported input. what() is
/// "FILE: WHERE: PROBLEM", e.g. "bad.igs: line 123: parameter record of entity D57 (type 128)
/// truncated"; WHERE is left out when the problem concerns the whole file. Control bytes in any
/// part (quoted from the file) are escaped (printable).
class ReadError : public std::runtime_error {
 public:
  ReadError(const std::string& file, const std::string& where, const std::string& problem)
      : std::runtime_error(printable(file + ": " + (where.empty() ? "" : where + ": ") + problem)) {}
};

}  // namespace nurbs::io
