// The model side of the batched point projection (point_batch_geometry.h): the bounds' per-face
// terms, the pyramid's cells and boxes as the pass reads them, a cell's corners.
#include "queries/distance/point_batch_geometry.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

#include "nurbs/model_ops.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Point-box minimum distance (Eqs. 9-12) of a box stored as float corners; +inf for an empty box.
double box_distance(const glm::dvec3& q, const float* lo, const float* hi) {
  if (lo[0] > hi[0]) return kInf;
  const glm::dvec3 l(lo[0], lo[1], lo[2]), h(hi[0], hi[1], hi[2]);
  return glm::length(glm::max(glm::max(l - q, q - h), glm::dvec3(0.0)));
}

}  // namespace

BatchGeometry::BatchGeometry(const PreparedModel& model, PointBoxes b) : m(model), boxes(b) {
  glm::dvec3 lo(kInf), hi(-kInf);
  double k = 0.0, largest_budget = 0.0;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    k = std::max(k, m.grids[f].k_e);
    largest_budget = std::max(largest_budget, float_budget(m.faces[f].surface));
    const nurbs::Box box = nurbs::control_box(m.faces[f].surface);
    lo = glm::min(lo, box.min);
    hi = glm::max(hi, box.max);
  }
  model_bound = k + largest_budget;
  budget.resize(m.faces.size()), grow.resize(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    budget[f] = float_budget(m.faces[f].surface);
    grow[f] = m.grids[f].k_e + budget[f];
  }
  grow_max = grow.empty() ? 0.0 : *std::max_element(grow.begin(), grow.end());
  trim_edges.resize(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f)
    if (!m.faces[f].loops.empty()) trim_edges[f] = TrimEdges(m.trims[f], m.grids[f].grid);
  radius = m.faces.empty() ? 0.0 : 0.5 * glm::length(hi - lo);
}

double BatchGeometry::slack(const glm::dvec3& p) const { return kFloatSlack * (glm::length(p - m.centre) + radius); }

FaceCell BatchGeometry::cell_corners(size_t a, int x, int y, glm::dvec3 corners[4]) const {
  const BatchAtlas& at = atlases[a];
  const AtlasPlan& plan = m.atlases[a].plan;
  const AtlasSlot& sl = plan.slots[size_t(at.slot_of[size_t(y) * size_t(plan.width) + size_t(x)])];
  for (int k = 0; k < 4; ++k) {
    const float* s = &at.samples[4 * (size_t(y + (k >> 1)) * size_t(plan.width) + size_t(x + (k & 1)))];
    corners[k] = glm::dvec3(s[0], s[1], s[2]);
  }
  return {sl.face, x - sl.x, y - sl.y};
}

bool BatchGeometry::pyramid_cell(const BatchAtlas& at, size_t a, int x, int y) const {
  const int w = m.atlases[a].plan.width, h = m.atlases[a].plan.height;
  if (x + 1 >= w || y + 1 >= h) return false;
  const auto at_texel = [&](int k) { return size_t(y + (k >> 1)) * size_t(w) + size_t(x + (k & 1)); };
  const float slot = at.slot_of[at_texel(0)];
  bool cell = slot >= 0.0f, material = false;
  for (int k = 1; k < 4; ++k) cell = cell && at.slot_of[at_texel(k)] == slot;
  for (int k = 0; k < 4 && cell; ++k) material = material || at.mask[at_texel(k)] > 0.5f;
  return cell && (material || at.crossed[at_texel(0)] > 0.5f);  // or a trim edge crosses the cell
}

glm::dvec3 BatchGeometry::float_sample(const BatchAtlas& at, size_t a, int x, int y) const {
  const float* s = &at.samples[4 * (size_t(y) * size_t(m.atlases[a].plan.width) + size_t(x))];
  return glm::dvec3(glm::vec3(s[0], s[1], s[2]) - glm::vec3(m.centre));
}

double BatchGeometry::node_distance(const BatchAtlas& at, const glm::dvec3& q, int level, int x, int y) const {
  if (boxes == PointBoxes::Aabb) {
    const size_t i = (size_t(y) * size_t(at.level_width(level)) + size_t(x)) * 3;
    return box_distance(q, &at.cpu_lo[size_t(level)][i], &at.cpu_hi[size_t(level)][i]);
  }
  const auto& l = at.cpu_obb[size_t(level)];
  const int32_t box = l.index[size_t(y) * size_t(at.level_width(level)) + size_t(x)];
  if (box < 0) return kInf;
  const size_t i = 4 * size_t(box);
  const float *c = &l.boxes[0][i], *t = &l.boxes[1][i], *n = &l.boxes[2][i];
  if (c[3] < 0.0f) return kInf;
  const glm::dvec3 a0(t[0], t[1], t[2]), a2(n[0], n[1], n[2]), d = q - glm::dvec3(c[0], c[1], c[2]);
  const glm::dvec3 local(std::abs(glm::dot(d, a0)), std::abs(glm::dot(d, glm::cross(a2, a0))),
                         std::abs(glm::dot(d, a2)));
  return glm::length(glm::max(local - glm::dvec3(c[3], t[3], n[3]), glm::dvec3(0.0)));
}

}  // namespace queries
