#include "viewer/overlays.h"

#include <algorithm>
#include <limits>

#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace viewer {

std::optional<CellBlocks> cell_blocks(const queries::PreparedModel& m, int level, long long max_boxes) {
  const int block = 1 << std::clamp(level, 0, 24);
  long long count = 0;
  for (const auto& g : m.grids)
    count += static_cast<long long>((g.grid.cells_u() + block - 1) / block) * ((g.grid.cells_v() + block - 1) / block);
  if (count > max_boxes) return std::nullopt;
  CellBlocks out;
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
    // Cells (nu - 1) x (nv - 1), 1 where a trim edge crosses: not culled even with no material sample.
    const std::vector<uint8_t> crossed = trimmed ? queries::crossed_cells(m.trims[f], g) : std::vector<uint8_t>{};
    const double grow = m.grids[f].k;
    for (int bj = 0; bj < nv - 1; bj += block)
      for (int bi = 0; bi < nu - 1; bi += block) {
        glm::dvec3 lo(1e300), hi(-1e300);
        bool any_material = false, any_crossed = false;
        for (int j = bj; j <= std::min(bj + block, nv - 1); ++j)
          for (int i = bi; i <= std::min(bi + block, nu - 1); ++i) {
            const size_t k = static_cast<size_t>(j) * nu + i;
            lo = glm::min(lo, p[k]);
            hi = glm::max(hi, p[k]);
            any_material |= material[k] != 0;
            if (!crossed.empty() && i < nu - 1 && j < nv - 1 && j < bj + block && i < bi + block)
              any_crossed |= crossed[static_cast<size_t>(j) * (nu - 1) + i] != 0;
          }
        const nurbs::Box box{lo - grow, hi + grow};
        if (any_material || any_crossed) {
          out.kept.push_back(box);
          out.witness.push_back(any_material ? 1 : 0);
        } else {
          out.trimmed.push_back(box);
        }
      }
  }
  return out;
}

BlockPruning prune_blocks(const CellBlocks& a, const CellBlocks& b, const glm::dmat4& motion_b, long long max_pairs) {
  BlockPruning r;
  r.pairs = static_cast<long long>(a.kept.size()) * static_cast<long long>(b.kept.size());
  if (r.pairs > max_pairs) {
    r.too_many = true;
    return r;
  }
  std::vector<nurbs::Box> moved;  // B's blocks where B is: the boxes of their moved corners
  moved.reserve(b.kept.size());
  for (const nurbs::Box& x : b.kept) {
    nurbs::Box m{glm::dvec3(1e300), glm::dvec3(-1e300)};
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner(c & 1 ? x.max.x : x.min.x, c & 2 ? x.max.y : x.min.y, c & 4 ? x.max.z : x.min.z);
      const glm::dvec3 p(motion_b * glm::dvec4(corner, 1.0));
      m.min = glm::min(m.min, p);
      m.max = glm::max(m.max, p);
    }
    moved.push_back(m);
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> lower_a(a.kept.size(), kInf), lower_b(moved.size(), kInf);
  r.upper = kInf;
  for (size_t i = 0; i < a.kept.size(); ++i)
    for (size_t j = 0; j < moved.size(); ++j) {
      const auto [lower, upper] = queries::box_box_minmax(a.kept[i].min, a.kept[i].max, moved[j].min, moved[j].max);
      lower_a[i] = std::min(lower_a[i], lower);
      lower_b[j] = std::min(lower_b[j], lower);
      // The max distance bounds the clearance only when both blocks hold a surface point.
      if (a.witness[i] && b.witness[j]) r.upper = std::min(r.upper, upper);
    }
  const auto prune = [&](const std::vector<double>& lower, std::vector<char>& pruned, long long& kept) {
    pruned.resize(lower.size());
    for (size_t k = 0; k < lower.size(); ++k) {
      pruned[k] = lower[k] > r.upper ? 1 : 0;
      kept += pruned[k] ? 0 : 1;
    }
  };
  prune(lower_a, r.pruned_a, r.kept_a);
  prune(lower_b, r.pruned_b, r.kept_b);
  return r;
}

void add_boxes(const std::vector<nurbs::Box>& boxes, const std::vector<char>* flags, const glm::vec3& color,
               const glm::vec3& flagged_color, LineBatch& batch) {
  for (size_t k = 0; k < boxes.size(); ++k)
    batch.box(boxes[k].min, boxes[k].max, flags != nullptr && k < flags->size() && (*flags)[k] ? flagged_color : color);
}

long long add_cell_boxes(const queries::PreparedModel& m, int level, long long max_boxes, const glm::vec3& color,
                         LineBatch& batch) {
  const std::optional<CellBlocks> blocks = cell_blocks(m, level, max_boxes);
  if (!blocks) return -1;
  add_boxes(blocks->kept, nullptr, color, color, batch);
  return static_cast<long long>(blocks->kept.size());
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
