// Files of points (nurbs/io/point_cloud.h): PLY in its three encodings, .npy, text with and without a
// header, read by content; the message of each malformed file; clouds larger than the reader's block.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

#include "nurbs/io/point_cloud.h"
#include "nurbs/io/read_error.h"

namespace {

using nurbs::io::PointCloud;

PointCloud read(const std::string& bytes, double limit = 1e6) {
  std::istringstream in(bytes);
  return nurbs::io::read_point_cloud(in, "scan", limit);
}

std::string error_of(const std::string& bytes, double limit = 1e6) {
  try {
    (void)read(bytes, limit);
  } catch (const nurbs::io::ReadError& e) {
    return e.what();
  }
  return "no error";
}

/// `v` appended in little (or big) endian byte order.
template <class T>
void put(std::string& out, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

/// An .npy file of `rows` x `columns` values k * 0.5 (row-major index k), its header as NumPy writes it.
template <class T>
std::string npy(const std::string& descr, int rows, int columns, bool fortran = false, bool big = false) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': (" +
                     std::to_string(rows) + ", " + std::to_string(columns) + "), }";
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  put<uint16_t>(out, uint16_t(dict.size()));
  out += dict;
  for (int a = 0; a < (fortran ? columns : rows); ++a)
    for (int b = 0; b < (fortran ? rows : columns); ++b) {
      const int k = fortran ? b * columns + a : a * columns + b;
      put<T>(out, T(k * 0.5), big);
    }
  return out;
}

}  // namespace

TEST_CASE("point cloud: PLY ascii keeps normals and colours, skips other properties and elements") {
  const PointCloud c = read(
      "ply\r\nformat ascii 1.0\r\ncomment scanner X\r\nelement vertex 2\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nproperty float quality\r\nproperty float nx\r\nproperty float ny\r\nproperty float nz\r\n"
      "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\nelement face 1\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n"
      "1 2 3 0.5 0 0 1 255 0 10\r\n4 5 6 0.7 1 0 0 1 2 3\r\n3 0 1 1\r\n");
  CHECK(c.format == "ply ascii");
  REQUIRE(c.points.size() == 2);
  CHECK(c.points[1] == glm::dvec3(4, 5, 6));
  REQUIRE(c.normals.size() == 2);
  CHECK(c.normals[0] == glm::dvec3(0, 0, 1));
  REQUIRE(c.colors.size() == 2);
  CHECK(c.colors[0] == glm::u8vec3(255, 0, 10));
}

TEST_CASE("point cloud: binary PLY in either byte order, lists skipped before the vertices") {
  for (const bool big : {false, true}) {
    CAPTURE(big);
    std::string f = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 2\n"
                    "property double x\nproperty double y\nproperty double z\nproperty short extra\n"
                    "property float red\nproperty float green\nproperty float blue\nend_header\n";
    put<uint8_t>(f, 3);
    for (int i : {0, 1, 1}) put<int32_t>(f, i, big);
    for (int v = 0; v < 2; ++v) {
      for (double x : {1.5 + v, -2.0, 1e-3}) put<double>(f, x, big);
      put<int16_t>(f, -7, big);
      for (float x : {1.0f, 0.5f, 0.0f}) put<float>(f, x, big);
    }
    const PointCloud c = read(f);
    CHECK(c.format == (big ? "ply binary big endian" : "ply binary little endian"));
    REQUIRE(c.points.size() == 2);
    CHECK(c.points[1] == glm::dvec3(2.5, -2.0, 1e-3));
    CHECK(c.normals.empty());
    REQUIRE(c.colors.size() == 2);
    CHECK(c.colors[0] == glm::u8vec3(255, 128, 0));  // float colours are 0-1
  }
}

TEST_CASE("point cloud: .npy of float32 and float64, either byte order, C and Fortran order") {
  const PointCloud a = read(npy<double>("<f8", 4, 3));
  CHECK(a.format == "npy float64");
  REQUIRE(a.points.size() == 4);
  CHECK(a.points[3] == glm::dvec3(4.5, 5.0, 5.5));
  const PointCloud b = read(npy<float>(">f4", 3, 5, false, true));  // five columns: the first three read
  CHECK(b.format == "npy float32");
  REQUIRE(b.points.size() == 3);
  CHECK(b.points[2] == glm::dvec3(5.0, 5.5, 6.0));
  const PointCloud c = read(npy<double>("<f8", 3, 4, true));
  REQUIRE(c.points.size() == 3);
  CHECK(c.points[1] == glm::dvec3(2.0, 2.5, 3.0));
  CHECK(error_of(npy<double>("<f8", 3, 2)) == "scan: byte 10: the array's shape (3,2) is not N x 3 (or more columns)");
  CHECK(error_of(npy<int32_t>("<i4", 3, 3)) == "scan: byte 10: the array's type '<i4' is not float32 or float64");
  const std::string whole = npy<double>("<f8", 4, 3);
  const size_t data = whole.size() - 4 * 3 * 8;  // where the rows start
  CHECK(error_of(whole.substr(0, data + 2 * 3 * 8 + 5)) ==
        "scan: byte " + std::to_string(data + 2 * 3 * 8) + ": row 2 of 4: the file ends");
}

TEST_CASE("point cloud: text with a header naming the columns, in any order, with extra columns") {
  const PointCloud a = read("X,Y,Z,R,G,B\n1,2,3,255,0,0\n4,5,6,0,255,0\n");
  REQUIRE(a.points.size() == 2);
  CHECK(a.points[1] == glm::dvec3(4, 5, 6));
  REQUIRE(a.colors.size() == 2);
  CHECK(a.colors[1] == glm::u8vec3(0, 255, 0));
  const PointCloud b = read("//X Y Z Nx Ny Nz\n1 2 3 0 0 1\n");  // CloudCompare's ASCII export
  REQUIRE(b.normals.size() == 1);
  CHECK(b.normals[0] == glm::dvec3(0, 0, 1));
  const PointCloud c = read("# exported\nid;z;y;x;label\n7;3;2;1;edge\n8;6;5;4;hole\n");
  REQUIRE(c.points.size() == 2);
  CHECK(c.points[0] == glm::dvec3(1, 2, 3));
  CHECK(c.normals.empty());
  CHECK(c.colors.empty());
}

TEST_CASE("point cloud: text without a header: x y z first, further columns not read, a PTS count skipped") {
  const PointCloud a = read("2\n1 2 3 -0.1 120 120 120\r\n\n4\t5\t6 0.2 1 2 3\n");
  REQUIRE(a.points.size() == 2);
  CHECK(a.points[1] == glm::dvec3(4, 5, 6));
  CHECK(a.colors.empty());
  CHECK(read("+1 -2 3e2\n").points[0] == glm::dvec3(1, -2, 300));
}

TEST_CASE("point cloud: each malformed file names the file, the line or byte and the problem") {
  CHECK(error_of("1 2 3\n1 2\n") == "scan: line 2: '1 2' is not a point X,Y,Z of three finite numbers");
  CHECK(error_of("1 nan 3\n") == "scan: line 1: '1 nan 3' is not a point X,Y,Z of three finite numbers");
  CHECK(error_of("1 2 3\n1e50 0 0\n", 1e3) ==
        "scan: line 2: '1e50 0 0' lies beyond 1e+03, the coordinates double arithmetic carries for this model");
  CHECK(error_of("a,b,c\n1,2,3\n") == "scan: line 1: the header 'a,b,c' names no x, y and z columns");
  CHECK(error_of("x y z\n1 2 zz\n") == "scan: line 2: column 3 'zz' is not a number");
  CHECK(error_of("x y z\n1 2\n") == "scan: line 2: 2 columns, 3 expected: '1 2'");
  CHECK(error_of(" \n# nothing\n") == "scan: no points in the file");
  CHECK(error_of("ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n") ==
        "scan: line 5: the header has no end_header");
  CHECK(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n") ==
        "scan: the vertex element has no x, y, z");
  CHECK(error_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                 "end_header\n1 2 3\n4 5\n") == "scan: line 9: vertex 1 of 2: property 'z' is missing or not a number");
  std::string f =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n";
  const size_t header = f.size();
  for (float x : {1.0f, 2.0f, 3.0f, 4.0f}) put<float>(f, x);
  CHECK(error_of(f) == "scan: byte " + std::to_string(header + 12) + ": vertex 1 of 2: the file ends");
  for (float x : {5.0f, 1e30f}) put<float>(f, x);
  CHECK(error_of(f, 1e3) == "scan: byte " + std::to_string(header + 12) +
                                ": vertex 1 of 2: the point (4, 5, 1e+30) lies beyond 1e+03, the coordinates double "
                                "arithmetic carries for this model");
}

TEST_CASE("point cloud: clouds larger than the reader's block, text and binary") {
  constexpr int n = 400000;  // 4.8 MB of binary, about 9 MB of text: more than one 4 MiB block each
  std::string text, ply = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                          "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (int i = 0; i < n; ++i) {
    text += std::to_string(i) + " " + std::to_string(i % 7) + " -" + std::to_string(i % 3) + ".25\n";
    for (float x : {float(i), float(i % 7), -float(i % 3) - 0.25f}) put<float>(ply, x);
  }
  for (const std::string* f : {&text, &ply}) {
    const PointCloud c = read(*f);
    REQUIRE(c.points.size() == size_t(n));
    bool all = true;
    for (int i = 0; i < n; ++i) all = all && c.points[size_t(i)] == glm::dvec3(i, i % 7, -(i % 3) - 0.25);
    CHECK(all);
  }
}
