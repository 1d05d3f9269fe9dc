#pragma once
/// \file read_error.h
/// The one exception type of every reader in nurbs/io: the message names the file, where in it
/// (line number and/or IGES directory entry), and what is wrong.
#include <stdexcept>
#include <string>

namespace nurbs::io {

/// Thrown by the IGES and .bpt readers for malformed or unsupported input. what() is
/// "FILE: WHERE: PROBLEM", e.g. "bad.igs: line 123: parameter record of entity D57 (type 128)
/// truncated"; WHERE is left out when the problem concerns the whole file.
class ReadError : public std::runtime_error {
 public:
  ReadError(const std::string& file, const std::string& where, const std::string& problem)
      : std::runtime_error(file + ": " + (where.empty() ? "" : where + ": ") + problem) {}
};

}  // namespace nurbs::io
