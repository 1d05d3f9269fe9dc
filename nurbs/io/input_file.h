#pragma once
/// \file input_file.h
/// Input files read whole before they are parsed, so that a file that cannot be read (missing, a
/// directory, no permission, an I/O error) is named as such rather than surfacing as a stream
/// exception from inside a parser.
#include <filesystem>
#include <fstream>
#include <istream>
#include <string>

namespace nurbs::io {

/// The file at `path` opened for reading (binary). Throws ReadError (read_error.h) naming it: "no
/// such file", "is a directory, not a file", "cannot be read (REASON)".
[[nodiscard]] std::ifstream open_input_file(const std::filesystem::path& path);

/// The bytes of the file at `path`. Throws ReadError (read_error.h) naming it: "no such file",
/// "is a directory, not a file", "cannot be read (REASON)".
[[nodiscard]] std::string read_input_file(const std::filesystem::path& path);

/// The bytes left in `in` (standard input), or ReadError naming `name` when reading fails.
[[nodiscard]] std::string read_input_stream(std::istream& in, const std::string& name);

}  // namespace nurbs::io
