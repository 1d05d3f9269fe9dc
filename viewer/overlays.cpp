#include "viewer/overlays.h"

#include <algorithm>

#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace viewer {

long long add_cell_boxes(const queries::PreparedModel& m, int level, long long max_boxes, const glm::vec3& color,
                         LineBatch& batch) {
  const int block = 1 << std::clamp(level, 0, 24);
  long long count = 0;
  for (const auto& g : m.grids)
    count += static_cast<long long>((g.grid.cells_u() + block - 1) / block) * ((g.grid.cells_v() + block - 1) / block);
  if (count > max_boxes) return -1;
  count = 0;
  for (size_t f = 0; f < m.faces.size() && f < m.grids.size(); ++f) {
    const nurbs::ParamGrid& g = m.grids[f].grid;
    const nurbs::Surface& s = m.faces[f].surface;
    const bool trimmed = f < m.trims.size() && !m.trims[f].loops.empty();
    const int nu = static_cast<int>(g.u.size()), nv = static_cast<int>(g.v.size());
    std::vector<glm::dvec3> p(static_cast<size_t>(nu) * nv);
    std::vector<char> material(p.size(), 1);
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const size_t k = static_cast<size_t>(j) * nu + i;
        p[k] = nurbs::surface_point(s, g.u[i], g.v[j]);
        if (trimmed) material[k] = nurbs::is_material(m.trims[f], {g.u[i], g.v[j]}) ? 1 : 0;
      }
    const double grow = m.grids[f].k;
    for (int bj = 0; bj < nv - 1; bj += block)
      for (int bi = 0; bi < nu - 1; bi += block) {
        glm::dvec3 lo(1e300), hi(-1e300);
        bool any = false;
        for (int j = bj; j <= std::min(bj + block, nv - 1); ++j)
          for (int i = bi; i <= std::min(bi + block, nu - 1); ++i) {
            const size_t k = static_cast<size_t>(j) * nu + i;
            lo = glm::min(lo, p[k]);
            hi = glm::max(hi, p[k]);
            any |= material[k] != 0;
          }
        if (!any) continue;
        batch.box(lo - grow, hi + grow, color);
        ++count;
      }
  }
  return count;
}

void add_voxels(const queries::VoxelGrid& grid, const glm::vec3& color, LineBatch& batch) {
  for (int v : grid.voxels) {
    const auto [lo, hi] = grid.box(v);
    batch.box(lo, hi, color);
  }
}

void add_face_boxes(const std::vector<nurbs::TrimmedSurface>& faces, const std::vector<char>& kept,
                    const glm::vec3& kept_color, const glm::vec3& culled_color, LineBatch& batch) {
  for (size_t f = 0; f < faces.size(); ++f) {
    const nurbs::Box b = nurbs::control_box(faces[f].surface);
    batch.box(b.min, b.max, f < kept.size() && kept[f] ? kept_color : culled_color);
  }
}

}  // namespace viewer
