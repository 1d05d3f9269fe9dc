#include "nurbs/tessellation/mesh_topology.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <map>
#include <unordered_map>
#include <vector>

namespace nurbs::tess {

std::vector<int> weld_vertices(const std::vector<glm::dvec3>& positions, double tol) {
  struct KeyHash {
    // Unsigned: the products wrap (cell indices reach 1e13 for a fine weld on a large model).
    size_t operator()(const std::array<long long, 3>& k) const {
      return size_t(uint64_t(k[0]) * 73856093u ^ uint64_t(k[1]) * 19349663u ^ uint64_t(k[2]) * 83492791u);
    }
  };
  const double h = tol > 0 ? tol : 1e-300;
  std::unordered_map<std::array<long long, 3>, std::vector<int>, KeyHash> grid;
  std::vector<int> id(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3& p = positions[i];
    const std::array<long long, 3> c{(long long)std::floor(p.x / h), (long long)std::floor(p.y / h),
                                     (long long)std::floor(p.z / h)};
    int found = -1;
    for (int k = 0; k < 27 && found < 0; ++k) {
      const auto it = grid.find({c[0] + k % 3 - 1, c[1] + k / 3 % 3 - 1, c[2] + k / 9 - 1});
      if (it != grid.end())
        for (int w : it->second)
          if (glm::length(positions[size_t(w)] - p) <= tol) {
            found = w;
            break;
          }
    }
    if (found < 0) grid[c].push_back(found = int(i));
    id[i] = found;
  }
  return id;
}

namespace {

/// Edge counts with vertex i taken as vertex id[i].
EdgeCounts count_edges_of(const TriangleMesh& mesh, const std::vector<int>& id) {
  EdgeCounts r;
  for (size_t i = 0; i < id.size(); ++i) r.welded_vertices += id[i] == int(i) ? 1 : 0;
  std::map<std::pair<int, int>, std::pair<int, size_t>> uses;  // edge -> (triangles, the first one)
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    const glm::ivec3& t = mesh.triangles[k];
    const int v[3] = {id[size_t(t.x)], id[size_t(t.y)], id[size_t(t.z)]};
    for (int e = 0; e < 3; ++e) {
      const int a = v[e], b = v[(e + 1) % 3];
      if (a == b) continue;  // collapsed by the weld
      ++uses.try_emplace({std::min(a, b), std::max(a, b)}, 0, k).first->second.first;
    }
  }
  r.edges = (long long)uses.size();
  for (const auto& [edge, use] : uses) {
    if (use.first == 1) {
      ++r.open;
      ++r.open_by_face[use.second < mesh.triangle_face.size() ? mesh.triangle_face[use.second] : -1];
    }
    if (use.first >= 3) ++r.nonmanifold;
  }
  return r;
}

}  // namespace

EdgeCounts count_edges(const TriangleMesh& mesh, double weld_tolerance) {
  return count_edges_of(mesh, weld_vertices(mesh.positions, weld_tolerance));
}

EdgeCounts count_edges_as_indexed(const TriangleMesh& mesh) {
  std::vector<int> id(mesh.positions.size());
  for (size_t i = 0; i < id.size(); ++i) id[i] = int(i);
  return count_edges_of(mesh, id);
}

TriangleMesh weld_mesh(const TriangleMesh& m, double tol, long long* collapsed) {
  const std::vector<int> id = weld_vertices(m.positions, tol);
  TriangleMesh out;
  out.values_name = m.values_name;
  std::vector<int> index(m.positions.size(), -1);
  for (size_t i = 0; i < id.size(); ++i) {
    if (id[i] != int(i)) continue;  // a representative: the first of its group
    index[i] = int(out.positions.size());
    out.positions.push_back(m.positions[i]);
    if (!m.normals.empty()) out.normals.emplace_back(0.0);
    if (!m.uv.empty()) out.uv.push_back(m.uv[i]);
    if (!m.vertex_face.empty()) out.vertex_face.push_back(m.vertex_face[i]);
    if (!m.colors.empty()) out.colors.push_back(m.colors[i]);
    if (!m.values.empty()) out.values.push_back(m.values[i]);
  }
  if (!m.normals.empty()) {  // the group's normals averaged (a crease's vertex gets their mean)
    for (size_t i = 0; i < id.size(); ++i) out.normals[size_t(index[size_t(id[i])])] += m.normals[i];
    for (size_t i = 0; i < id.size(); ++i)
      if (id[i] == int(i)) {
        glm::dvec3& n = out.normals[size_t(index[i])];
        const double len = glm::length(n);
        n = len > 0.0 ? n / len : m.normals[i];
      }
  }
  long long dropped = 0;
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    const glm::ivec3 t = m.triangles[k];
    const glm::ivec3 w(index[size_t(id[size_t(t.x)])], index[size_t(id[size_t(t.y)])], index[size_t(id[size_t(t.z)])]);
    if (w.x == w.y || w.y == w.z || w.z == w.x) {
      ++dropped;
      continue;
    }
    out.triangles.push_back(w);
    if (!m.triangle_face.empty()) out.triangle_face.push_back(m.triangle_face[k]);
  }
  if (collapsed) *collapsed = dropped;
  return out;
}

}  // namespace nurbs::tess
