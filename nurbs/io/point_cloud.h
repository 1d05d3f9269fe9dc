#pragma once
/// \file point_cloud.h
/// Point clouds as scanners and inspection programs write them, told apart by their content (never
/// the extension), read as a stream: a file of 10^7 points is never held whole, as text or bytes.
///  - PLY (`format ascii`, `binary_little_endian`, `binary_big_endian`): the element `vertex`,
///    properties x, y, z of any scalar type (char ... double, int8 ... float64); nx, ny, nz kept as
///    normals and red, green, blue (or r, g, b, diffuse_red ...) as colours when all three are there
///    (float colours in [0, 1] scaled to 0-255); every other property and element skipped, list
///    properties included (a mesh's faces).
///  - NumPy `.npy` (format 1.0 to 3.0): a two-dimensional array of float32 or float64, either byte
///    order, C or Fortran order, N rows of 3 or more columns; the first three are x, y, z.
///  - Text (XYZ, CSV, TXT, PTS): one point per line, numbers separated by spaces, tabs, commas or
///    semicolons. Blank lines and lines starting with '#' are skipped. The first line is a header
///    when it starts with "//" (CloudCompare's "//X,Y,Z,R,G,B") or holds words and no number:
///    it names the columns (x, y, z, nx, ny, nz, r, g, b, red, green, blue, any case; "normal_x" and
///    "Nx" alike) and the others are skipped. Without one the first three columns are x, y, z and
///    further columns are not read. A first line of a single whole number is a PTS point count,
///    skipped (never trusted).
/// Every coordinate must be finite and of magnitude at most `limit` (nurbs::coordinate_limit of the
/// model queried). Errors are ReadError (read_error.h): "NAME: line N: PROBLEM" in text and in a
/// PLY header, "NAME: byte B: PROBLEM" in binary data, naming the point ("vertex 12 of 100").
#include <filesystem>
#include <glm/ext/vector_uint3_sized.hpp>
#include <glm/vec3.hpp>
#include <istream>
#include <limits>
#include <string>
#include <vector>

namespace nurbs::io {

/// A point cloud as read.
struct PointCloud {
  std::vector<glm::dvec3> points;
  /// One per point when the file gives them (PLY nx ny nz; text columns named so), else empty.
  std::vector<glm::dvec3> normals;
  /// One per point, 0 to 255 per channel, when the file gives them, else empty.
  std::vector<glm::u8vec3> colors;
  /// What was read: "ply ascii", "ply binary little endian", "ply binary big endian", "npy float32",
  /// "npy float64", "text".
  std::string format;
};

/// The cloud in `in`, its format by its first bytes; `name` is the file named in errors. Throws
/// ReadError for malformed or truncated input, and "NAME: no points in the file" for none.
[[nodiscard]] PointCloud read_point_cloud(std::istream& in, const std::string& name,
                                          double limit = std::numeric_limits<double>::infinity());

/// read_point_cloud of the file at `path`; ReadError for a file that cannot be read (input_file.h).
[[nodiscard]] PointCloud read_point_cloud_file(const std::filesystem::path& path,
                                               double limit = std::numeric_limits<double>::infinity());

}  // namespace nurbs::io
