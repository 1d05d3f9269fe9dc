// Mesh import (nurbs/io/mesh_reader.h): round trips through the writer in all three formats,
// hand-written ASCII files, and truncated or garbled files with their exact messages.
#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "nurbs/io/mesh_reader.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/read_error.h"

using nurbs::TriangleMesh;
using nurbs::io::MeshFormat;

namespace {

/// A unit octahedron moved off the origin, with coordinates exact in float (STL and PLY store
/// floats), plus a per-face index and normals so that the PLY writer adds its extra properties.
TriangleMesh octahedron() {
  TriangleMesh m;
  m.positions = {{1.5, 0, 0}, {-0.5, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}, {0.5, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  m.normals.assign(6, glm::dvec3(0, 0, 1));
  m.triangle_face.assign(8, 3);
  return m;
}

std::string written(const TriangleMesh& m, MeshFormat f) {
  std::ostringstream out;
  nurbs::io::write_mesh(out, m, f);
  return out.str();
}

TriangleMesh parse(const std::string& text, MeshFormat f, const std::string& name = "m") {
  std::istringstream in(text);
  return nurbs::io::read_mesh(in, f, name);
}

/// The ReadError message of parsing `text`, or "no error".
std::string error_of(const std::string& text, MeshFormat f, const std::string& name) {
  try {
    (void)parse(text, f, name);
  } catch (const nurbs::io::ReadError& e) {
    return e.what();
  }
  return "no error";
}

/// Same triangles with the same corner positions (vertex numbering may differ: STL welds).
void check_same_geometry(const TriangleMesh& a, const TriangleMesh& b) {
  REQUIRE(a.triangles.size() == b.triangles.size());
  for (size_t k = 0; k < a.triangles.size(); ++k)
    for (int c = 0; c < 3; ++c)
      CHECK(a.positions[size_t(a.triangles[k][c])] == b.positions[size_t(b.triangles[k][c])]);  // exact in float
}

}  // namespace

TEST_CASE("mesh reader: round trip through the writer in every format") {
  const TriangleMesh m = octahedron();
  for (const MeshFormat f : {MeshFormat::Obj, MeshFormat::Ply, MeshFormat::Stl}) {
    CAPTURE(int(f));
    const TriangleMesh r = parse(written(m, f), f);
    CHECK(r.positions.size() == 6);  // STL repeats vertices per facet; the reader welds them
    check_same_geometry(m, r);
  }
}

TEST_CASE("mesh reader: the file reader picks the format by extension") {
  const auto dir = std::filesystem::temp_directory_path() / "nurbsgl_test_mesh_reader";
  std::filesystem::create_directories(dir);
  for (const char* ext : {".obj", ".PLY", ".stl"}) {
    const auto path = dir / (std::string("octahedron") + ext);
    nurbs::io::write_mesh_file(path, octahedron());
    check_same_geometry(octahedron(), nurbs::io::read_mesh_file(path));
  }
  CHECK_THROWS_WITH_AS(nurbs::io::read_mesh_file(dir / "missing.stl"),
                       ((dir / "missing.stl").string() + ": no such file").c_str(), nurbs::io::ReadError);
  std::ofstream(dir / "mesh.txt") << "v 0 0 0\n";
  CHECK_THROWS_WITH_AS(nurbs::io::read_mesh_file(dir / "mesh.txt"),
                       ((dir / "mesh.txt").string() + ": unknown mesh format '.txt' (use .obj, .ply or .stl)").c_str(),
                       nurbs::io::ReadError);
  std::filesystem::remove_all(dir);
}

TEST_CASE("mesh reader: hand-written ASCII files") {
  SUBCASE("STL, two solids, CRLF") {
    const std::string stl =
        "solid a\r\n facet normal 0 0 1\r\n  outer loop\r\n   vertex 0 0 0\r\n   vertex 1 0 0\r\n   vertex 0 1 +0\r\n"
        "  endloop\r\n endfacet\r\nendsolid a\r\nsolid b\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\n"
        "vertex 0 1 0\nendloop\nendfacet\nendsolid b\n";
    const TriangleMesh m = parse(stl, MeshFormat::Stl);
    CHECK(m.positions.size() == 4);
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[1] == glm::ivec3(1, 3, 2));
  }
  SUBCASE("PLY: a quad as a fan, extra properties and an element that is skipped") {
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment hand-written\nelement vertex 4\nproperty double x\nproperty double y\n"
        "property double z\nproperty uchar red\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
        "element face 1\nproperty list uchar uint vertex_indices\nproperty float quality\nend_header\n"
        "0 0 0 255\n2 0 0 0\n2 1 0 0\n0 1 0.5e1 7\n0 1\n4 0 1 2 3 0.5\n";
    const TriangleMesh m = parse(ply, MeshFormat::Ply);
    REQUIRE(m.positions.size() == 4);
    CHECK(m.positions[3] == glm::dvec3(0, 1, 5));
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[0] == glm::ivec3(0, 1, 2));
    CHECK(m.triangles[1] == glm::ivec3(0, 2, 3));
  }
  SUBCASE("OBJ: slashes, negative indices, a pentagon, comments and other records") {
    const std::string obj =
        "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nvt 0 0\nvn 0 0 1\nv 0 1 0\nv -1 0.5 0\n"
        "g part\ns off\nf 1/1/1 2/1/1 3//1\nf -3 -2 -1\nf 1/1 2 3 4 5\n";
    const TriangleMesh m = parse(obj, MeshFormat::Obj);
    CHECK(m.positions.size() == 5);
    REQUIRE(m.triangles.size() == 5);
    CHECK(m.triangles[0] == glm::ivec3(0, 1, 2));
    CHECK(m.triangles[1] == glm::ivec3(2, 3, 4));
    CHECK(m.triangles[4] == glm::ivec3(0, 3, 4));
  }
}

TEST_CASE("mesh reader: binary PLY with double coordinates, ushort counts and a skipped list") {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nproperty list uchar float extra\nelement face 1\nproperty list ushort uint "
      "vertex_indices\nend_header\n";
  auto put = [&](auto value) { ply.append(reinterpret_cast<const char*>(&value), sizeof value); };
  const double xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0.25}};
  for (const auto& p : xyz) {
    for (double c : p) put(c);
    put(uint8_t(2)), put(1.0f), put(2.0f);  // a list property that is not ours: skipped
  }
  put(uint16_t(4));
  for (uint32_t i : {3u, 2u, 1u, 0u}) put(i);
  const TriangleMesh m = parse(ply, MeshFormat::Ply);
  REQUIRE(m.positions.size() == 4);
  CHECK(m.positions[3] == glm::dvec3(0, 1, 0.25));
  REQUIRE(m.triangles.size() == 2);
  CHECK(m.triangles[0] == glm::ivec3(3, 2, 1));
  CHECK(m.triangles[1] == glm::ivec3(3, 1, 0));
}

TEST_CASE("mesh reader: bad files name the file, where, and the problem") {
  const std::string stl = written(octahedron(), MeshFormat::Stl);  // 84 + 8 x 50 = 484 bytes
  const std::string ply = written(octahedron(), MeshFormat::Ply);
  struct Row {
    std::string text;
    MeshFormat format;
    std::string message;
  };
  const std::string ascii_ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n";
  const Row rows[] = {
      {stl.substr(0, 40), MeshFormat::Stl,
       "b.stl: byte 40: binary STL header needs 84 bytes, the file has 40 (truncated)"},
      {stl.substr(0, 474), MeshFormat::Stl, "b.stl: byte 474: facet 7 of 8: file ends (truncated)"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", MeshFormat::Stl,
       "b.stl: line 4: file ends inside a facet (truncated)"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 abc 0\n", MeshFormat::Stl,
       "b.stl: line 4: 'abc' is not a finite number"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n", MeshFormat::Stl,
       "b.stl: line 7: facet has 2 vertices, expected 3"},
      {"solid x\nvertex 0 0 0\n", MeshFormat::Stl, "b.stl: line 2: unexpected 'vertex'"},
      {"solid x\n", MeshFormat::Stl, "b.stl: line 1: file ends before 'endsolid' (truncated)"},
      {"PLY\n", MeshFormat::Ply, "b.ply: line 1: not a PLY file (no 'ply' magic)"},
      {"ply\nformat binary_big_endian 1.0\n", MeshFormat::Ply,
       "b.ply: line 2: format binary_big_endian is not supported"},
      {ply.substr(0, 60), MeshFormat::Ply, "b.ply: line 3: file ends before 'end_header' (truncated)"},
      {ply.substr(0, ply.size() - 20), MeshFormat::Ply,
       "b.ply: byte " + std::to_string(ply.size() - 20) + ": face 6 of 8: file ends (truncated)"},
      {ascii_ply + "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
       MeshFormat::Ply, "b.ply: line 13: face 0 of 1: vertex index 3 out of range (3 allowed)"},
      {ascii_ply + "property float z\nend_header\n0 0 0\n1 0 0\n0 1\n", MeshFormat::Ply,
       "b.ply: line 10: vertex 2 of 3: file ends (truncated)"},
      {ascii_ply + "property float z\nend_header\n0 0 0\n1 0 x\n", MeshFormat::Ply,
       "b.ply: line 9: vertex 1 of 3: 'x' is not a number"},
      {ascii_ply + "end_header\n", MeshFormat::Ply,
       "b.ply: header: element 'vertex' lacks one of the properties x, y, z"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", MeshFormat::Obj,
       "b.obj: line 4: vertex index 4 out of range (3 vertices so far)"},
      {"v 0 0 0\nf 0 1 1\n", MeshFormat::Obj, "b.obj: line 2: vertex index 0 (OBJ counts from 1)"},
      {"v 0 0 0\nf 1 1\n", MeshFormat::Obj, "b.obj: line 2: face has 2 vertices, expected at least 3"},
      {"v 0 nan 0\n", MeshFormat::Obj, "b.obj: line 1: 'nan' is not a finite number"},
      {"v 0 0\n", MeshFormat::Obj, "b.obj: line 1: 'v' needs 3 coordinates, got 2"},
      {"v 0 0 0\nf 1 a 1\n", MeshFormat::Obj, "b.obj: line 2: 'a' is not a vertex index"},
  };
  for (const Row& r : rows) {
    const char* ext = r.format == MeshFormat::Stl ? "b.stl" : r.format == MeshFormat::Ply ? "b.ply" : "b.obj";
    CHECK(error_of(r.text, r.format, ext) == r.message);
  }
}

TEST_CASE("mesh reader: coordinates beyond the limit name the vertex and the value") {
  const auto error_with_limit = [](const std::string& text, MeshFormat f, const std::string& name) -> std::string {
    std::istringstream in(text);
    try {
      (void)nurbs::io::read_mesh(in, f, name, 1e3);
    } catch (const nurbs::io::ReadError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string beyond = "coordinate 1e+155 is beyond 1e+03, the range double arithmetic carries for this model";
  CHECK(error_with_limit("v 0 0 0\nv 1e155 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, "b.obj") ==
        "b.obj: line 2: vertex 2: " + beyond);
  CHECK(error_with_limit("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 -1e155 0\n",
                         MeshFormat::Stl, "b.stl") == "b.stl: line 5: vertex: coordinate -1e+155 is beyond 1e+03, "
                                                     "the range double arithmetic carries for this model");
  CHECK(error_with_limit("ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                         "property double z\nend_header\n0 0 0\n0 0 1e155\n",
                         MeshFormat::Ply, "b.ply") == "b.ply: line 9: vertex 1 of 2: " + beyond);
  TriangleMesh far = octahedron();
  far.positions[4].z = 2e3;  // a float: binary STL
  CHECK(error_with_limit(written(far, MeshFormat::Stl), MeshFormat::Stl, "b.stl") ==
        "b.stl: byte 120: facet 0 of 8: vertex 2: coordinate 2000 is beyond 1e+03, the range double arithmetic "
        "carries for this model");
  CHECK(parse("v 0 0 0\nv 1e155 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj).positions[1].x == 1e155);  // no limit
}

TEST_CASE("mesh reader: counts are not trusted before their bytes; fans of many or repeated corners") {
  // An element without properties and a count of 9e18 (it looped for ever): nothing to read.
  const std::string header = "ply\nformat ascii 1.0\nelement junk 9000000000000000000\nend_header\n";
  CHECK(parse(header, MeshFormat::Ply).triangles.empty());
  // A count whose items cannot fit in the bytes left is truncation, said before reading them.
  const std::string vertices = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
                               "property float y\nproperty float z\nend_header\n0123456789ab";
  CHECK(error_of(vertices, MeshFormat::Ply, "b.ply") ==
        "b.ply: byte 127: element 'vertex' has 1000000000000 items of at least 12 bytes, the file has 12 bytes left "
        "(truncated)");
  // A header whose last line has no newline: nothing left for the items (no wrapped byte count).
  CHECK(error_of("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "end_header",
                 MeshFormat::Ply, "b.ply") ==
        "b.ply: line 8: element 'vertex' has 3 items of at least 3 bytes, the file has 0 bytes left (truncated)");
  // A polygon of 150,000 corners: refused, naming its line.
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (int k = 0; k < 50000; ++k) obj += " 1 2 3";
  CHECK(error_of(obj + "\n", MeshFormat::Obj, "b.obj") == "b.obj: line 4: polygon has 150000 corners, more than 65536");
  // Triangles that name a vertex twice have no area: left out (a face of one repeated vertex adds none).
  const TriangleMesh m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 1 1 1\nf 1 2 2 3\n", MeshFormat::Obj);
  REQUIRE(m.triangles.size() == 1);
  CHECK(m.triangles[0] == glm::ivec3(0, 1, 2));
}

TEST_CASE("mesh reader: a folder is named as one; control bytes from the file are escaped") {
  const auto dir = std::filesystem::temp_directory_path() / "nurbsgl_test_mesh_reader_folder.stl";
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH_AS(nurbs::io::read_mesh_file(dir), (dir.string() + ": is a directory, not a file").c_str(),
                       nurbs::io::ReadError);
  std::filesystem::remove_all(dir);
  CHECK(error_of("v 0 \x01\x1b[2J 0\n", MeshFormat::Obj, "b.obj") ==
        "b.obj: line 1: '\\x01\\x1b[2J' is not a finite number");
}

TEST_CASE("mesh reader: every prefix and random byte damage give a mesh or a ReadError, never a crash") {
  std::mt19937 random(9);  // fixed seed: the same damaged files every run
  for (const MeshFormat f : {MeshFormat::Obj, MeshFormat::Ply, MeshFormat::Stl}) {
    const std::string full = written(octahedron(), f);
    for (size_t n = 0; n < full.size(); ++n) {
      const std::string message = error_of(full.substr(0, n), f, "t");
      CHECK((message == "no error" || message.rfind("t: ", 0) == 0));
    }
    for (int trial = 0; trial < 300; ++trial) {
      std::string damaged = full;
      for (int k = 0; k < 4; ++k) damaged[random() % damaged.size()] = char(random() % 256);
      const std::string message = error_of(damaged, f, "t");
      CHECK((message == "no error" || message.rfind("t: ", 0) == 0));
    }
  }
}
