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

EdgeCounts count_edges(const TriangleMesh& mesh, double weld_tolerance) {
  EdgeCounts r;
  const std::vector<int> id = weld_vertices(mesh.positions, weld_tolerance);
  for (size_t i = 0; i < id.size(); ++i) r.welded_vertices += id[i] == int(i) ? 1 : 0;
  std::map<std::pair<int, int>, int> uses;
  for (const glm::ivec3& t : mesh.triangles) {
    const int v[3] = {id[size_t(t.x)], id[size_t(t.y)], id[size_t(t.z)]};
    for (int e = 0; e < 3; ++e) {
      const int a = v[e], b = v[(e + 1) % 3];
      if (a == b) continue;  // collapsed by the weld
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  r.edges = (long long)uses.size();
  for (const auto& [edge, n] : uses) {
    if (n == 1) ++r.open;
    if (n >= 3) ++r.nonmanifold;
  }
  return r;
}

}  // namespace nurbs::tess
