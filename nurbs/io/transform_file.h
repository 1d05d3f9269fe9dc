#pragma once
/// \file transform_file.h
/// A 4 x 4 placement matrix in a file (`inspect --transform`): the JSON that `inspect --json`
/// prints (its alignment.matrix), any JSON object with a "matrix", a bare JSON array of four rows of
/// four numbers, or sixteen numbers as text (row by row; spaces, tabs, commas, newlines; lines
/// starting with '#' skipped). Rows are the matrix's rows: p' = M (x, y, z, 1).
#include <filesystem>
#include <glm/mat4x4.hpp>
#include <string>

namespace nurbs::io {

/// The matrix in `text`; `name` is the file named in errors. Throws ReadError naming what is wrong
/// (not sixteen numbers, a number that is not finite, no matrix in the JSON).
[[nodiscard]] glm::dmat4 parse_transform(const std::string& text, const std::string& name);

/// parse_transform of the file at `path` (ReadError for a file that cannot be read).
[[nodiscard]] glm::dmat4 read_transform_file(const std::filesystem::path& path);

}  // namespace nurbs::io
