#include "nurbs/io/mesh_writer.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>

#include "nurbs/io/output_file.h"

namespace nurbs::io {
namespace {

static_assert(std::endian::native == std::endian::little, "the PLY and STL writers assume a little-endian host");

template <typename T>
void put(std::ostream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

void write_obj(std::ostream& out, const TriangleMesh& m) {
  out << "# nurbsgl tessellation\n";
  for (const glm::dvec3& p : m.positions) fmt::print(out, "v {} {} {}\n", p.x, p.y, p.z);
  for (const glm::dvec3& n : m.normals) fmt::print(out, "vn {} {} {}\n", n.x, n.y, n.z);
  for (const glm::dvec2& t : m.uv) fmt::print(out, "vt {} {}\n", t.x, t.y);
  const bool vn = !m.normals.empty(), vt = !m.uv.empty();
  int group = -2;
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    const int face = m.triangle_face.empty() ? -1 : m.triangle_face[k];
    if (face != group && face >= 0) fmt::print(out, "g face_{}\n", face);
    group = face;
    out << 'f';
    for (int c = 0; c < 3; ++c) {
      const int i = m.triangles[k][c] + 1;
      if (vn && vt)
        fmt::print(out, " {}/{}/{}", i, i, i);
      else if (vt)
        fmt::print(out, " {}/{}", i, i);
      else if (vn)
        fmt::print(out, " {}//{}", i, i);
      else
        fmt::print(out, " {}", i);
    }
    out << '\n';
  }
}

void write_ply(std::ostream& out, const TriangleMesh& m) {
  const bool normals = !m.normals.empty(), colors = !m.colors.empty(), faces = !m.triangle_face.empty();
  const bool values = !m.values.empty() && !m.values_name.empty();
  out << "ply\nformat binary_little_endian 1.0\n";
  fmt::print(out, "comment nurbsgl {}\n", values ? m.values_name + " samples" : std::string("tessellation"));
  fmt::print(out, "element vertex {}\n", m.positions.size());
  // Positions in double: a needle of a tessellation (an edge far shorter than a float step of
  // the coordinates) keeps its area; normals and values need no more than float.
  out << "property double x\nproperty double y\nproperty double z\n";
  if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  if (colors) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (values) fmt::print(out, "property float {}\n", m.values_name);
  fmt::print(out, "element face {}\n", m.triangles.size());
  out << "property list uchar int vertex_indices\n";
  if (faces) out << "property int face_id\n";
  out << "end_header\n";
  for (size_t i = 0; i < m.positions.size(); ++i) {
    for (int c = 0; c < 3; ++c) put(out, m.positions[i][c]);
    if (normals)
      for (int c = 0; c < 3; ++c) put(out, float(m.normals[i][c]));
    if (colors)
      for (int c = 0; c < 3; ++c) put(out, uint8_t(std::clamp(m.colors[i][c], 0.0, 1.0) * 255.0 + 0.5));
    if (values) put(out, float(m.values[i]));
  }
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    put(out, uint8_t(3));
    for (int c = 0; c < 3; ++c) put(out, int32_t(m.triangles[k][c]));
    if (faces) put(out, int32_t(m.triangle_face[k]));
  }
}

void write_stl(std::ostream& out, const TriangleMesh& m) {
  std::string header = "nurbsgl tessellation";
  header.resize(80, ' ');
  out.write(header.data(), 80);
  // STL holds float corners: a facet whose corners round to fewer than three points covers
  // nothing there (a needle of the tessellation) and is left out.
  const auto collapsed = [&](const glm::ivec3& t) {
    const glm::vec3 a(m.positions[size_t(t.x)]), b(m.positions[size_t(t.y)]), c(m.positions[size_t(t.z)]);
    return a == b || b == c || c == a;
  };
  const auto kept = std::count_if(m.triangles.begin(), m.triangles.end(), [&](const glm::ivec3& t) { return !collapsed(t); });
  put(out, uint32_t(kept));
  for (const glm::ivec3& t : m.triangles) {
    if (collapsed(t)) continue;
    const glm::dvec3 a = m.positions[size_t(t.x)], b = m.positions[size_t(t.y)], c = m.positions[size_t(t.z)];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    const glm::dvec3 u = len > 0 ? n / len : glm::dvec3(0.0);
    for (const glm::dvec3& v : {u, a, b, c})
      for (int k = 0; k < 3; ++k) put(out, float(v[k]));
    put(out, uint16_t(0));
  }
}

}  // namespace

MeshFormat mesh_format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  throw std::invalid_argument(path.string() + ": unknown mesh format '" + ext + "' (use .obj, .ply or .stl)");
}

void write_mesh(std::ostream& out, const TriangleMesh& mesh, MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      write_obj(out, mesh);
      break;
    case MeshFormat::Ply:
      write_ply(out, mesh);
      break;
    case MeshFormat::Stl:
      write_stl(out, mesh);
      break;
  }
}

void write_mesh_file(const std::filesystem::path& path, const TriangleMesh& mesh) {
  const MeshFormat format = mesh_format_of(path);
  write_file(path, [&](std::ostream& out) { write_mesh(out, mesh, format); });
}

}  // namespace nurbs::io
