#pragma once
/// \file output_file.h
/// Output files written safely: each writer writes a temporary file beside the target and renames
/// it over the target only when the whole file is written, so a failure never leaves a partial file
/// or clobbers a good one; and a command checks its outputs before its work (check_writable).
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>

namespace nurbs::io {

/// An output file that cannot be written: what() is "FILE: PROBLEM".
class WriteError : public std::runtime_error {
 public:
  WriteError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + problem) {}
};

/// Calls `write` with a temporary path in `path`'s folder, then renames it to `path`. Throws
/// WriteError (the temporary removed, `path` untouched) when `write` throws or the rename fails.
void write_atomically(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);

/// write_atomically of a file that `write` fills as a stream (binary mode); a stream error is a
/// failed write.
void write_file(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// Throws WriteError unless a file can be created in `path`'s folder and `path` is not a folder.
/// Creates nothing that stays.
void check_writable(const std::filesystem::path& path);

}  // namespace nurbs::io
