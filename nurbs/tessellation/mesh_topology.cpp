#include "nurbs/tessellation/mesh_topology.h"

#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace nurbs::tess {
namespace {

struct KeyHash {
  size_t operator()(const std::tuple<long long, long long, long long>& k) const {
    // Unsigned: the products wrap (cell indices reach 1e13 for a fine weld on a large model).
    return size_t(uint64_t(std::get<0>(k)) * 73856093u ^ uint64_t(std::get<1>(k)) * 19349663u ^
                  uint64_t(std::get<2>(k)) * 83492791u);
  }
};

}  // namespace

EdgeCounts count_edges(const TriangleMesh& mesh, double weld_tolerance) {
  EdgeCounts r;
  const double h = weld_tolerance > 0 ? weld_tolerance : 1e-300;
  std::unordered_map<std::tuple<long long, long long, long long>, std::vector<int>, KeyHash> grid;
  std::vector<int> id(mesh.positions.size(), -1);
  std::vector<glm::dvec3> welded;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3& p = mesh.positions[i];
    const long long x = (long long)std::floor(p.x / h), y = (long long)std::floor(p.y / h),
                    z = (long long)std::floor(p.z / h);
    int found = -1;
    for (long long dx = -1; dx <= 1 && found < 0; ++dx)
      for (long long dy = -1; dy <= 1 && found < 0; ++dy)
        for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({x + dx, y + dy, z + dz});
          if (it == grid.end()) continue;
          for (int w : it->second)
            if (glm::length(welded[size_t(w)] - p) <= weld_tolerance) {
              found = w;
              break;
            }
        }
    if (found < 0) {
      found = int(welded.size());
      welded.push_back(p);
      grid[{x, y, z}].push_back(found);
    }
    id[i] = found;
  }
  r.welded_vertices = (long long)welded.size();
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
