// The CPU side of the batched point projection (point_batch.h): the twin of the GPU pass (the same
// pyramid built from the read-back samples, the same descent in double) and the best-first search
// of points whose closest triangle point is trimmed (§5.3).
#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <queue>
#include <utility>

#include "nurbs/surface_eval.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/refine.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();

/// Point-box minimum distance (Eqs. 9-12) of a box stored as float corners; +inf for an empty box.
double box_distance(const glm::dvec3& q, const float* lo, const float* hi) {
  if (lo[0] > hi[0]) return kInf;
  const glm::dvec3 l(lo[0], lo[1], lo[2]), h(hi[0], hi[1], hi[2]);
  return glm::length(glm::max(glm::max(l - q, q - h), glm::dvec3(0.0)));
}

}  // namespace

bool PointBatch::pyramid_cell(const Atlas& at, size_t a, int x, int y) const {
  const int w = m_.atlases[a].plan.width, h = m_.atlases[a].plan.height;
  if (x + 1 >= w || y + 1 >= h) return false;
  const auto at_texel = [&](int k) { return size_t(y + (k >> 1)) * size_t(w) + size_t(x + (k & 1)); };
  const float slot = at.slot_of[at_texel(0)];
  bool cell = slot >= 0.0f, material = false;
  for (int k = 1; k < 4; ++k) cell = cell && at.slot_of[at_texel(k)] == slot;
  for (int k = 0; k < 4 && cell; ++k) material = material || at.mask[at_texel(k)] > 0.5f;
  return cell && (material || at.crossed[at_texel(0)] > 0.5f);  // or a trim edge crosses the cell
}

glm::dvec3 PointBatch::float_sample(const Atlas& at, size_t a, int x, int y) const {
  const float* s = &at.samples[4 * (size_t(y) * size_t(m_.atlases[a].plan.width) + size_t(x))];
  return glm::dvec3(glm::vec3(s[0], s[1], s[2]) - glm::vec3(m_.centre));
}

double PointBatch::node_distance(const Atlas& at, const glm::dvec3& q, int level, int x, int y) const {
  if (boxes_ == PointBoxes::Aabb) {
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

void PointBatch::build_cpu_pyramid(Atlas& at) {
  if (!at.cpu_lo.empty()) return;
  const size_t a = size_t(&at - atlases_.data());
  const AtlasPlan& plan = m_.atlases[a].plan;
  const int w = plan.width, h = plan.height, w0 = at.w0, h0 = at.h0;
  const glm::vec3 o(m_.centre);
  // Level 0: aabb_leaf.frag (TRIM_CROSSED) in float (the same boxes, bit for bit), empty outside the
  // cells and in cells with no material sample that no trim edge crosses.
  std::vector<float> lo(size_t(w0) * size_t(h0) * 3, kInfF), hi(lo.size(), -kInfF);
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      if (!pyramid_cell(at, a, x, y)) continue;
      const auto at_texel = [&](int k) { return size_t(y + (k >> 1)) * size_t(w) + size_t(x + (k & 1)); };
      float* l = &lo[(size_t(y) * size_t(w0) + size_t(x)) * 3];
      float* u = &hi[(size_t(y) * size_t(w0) + size_t(x)) * 3];
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) {
          const float v = at.samples[4 * at_texel(k) + size_t(c)] - o[c];
          l[c] = std::min(l[c], v), u[c] = std::max(u[c], v);
        }
    }
  at.cpu_lo.push_back(std::move(lo));
  at.cpu_hi.push_back(std::move(hi));
  // Levels 1..: the 2x2 merge of aabb_merge.frag.
  for (int l = 1; l < at.levels; ++l) {
    const int fw = at.level_width(l - 1), fh = at.level_height(l - 1);
    const int lw = at.level_width(l), lh = at.level_height(l);
    std::vector<float> nlo(size_t(lw) * size_t(lh) * 3, kInfF), nhi(nlo.size(), -kInfF);
    for (int y = 0; y < lh; ++y)
      for (int x = 0; x < lw; ++x)
        for (int k = 0; k < 4; ++k) {
          const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
          if (cx >= fw || cy >= fh) continue;
          for (int c = 0; c < 3; ++c) {
            const size_t src = (size_t(cy) * size_t(fw) + size_t(cx)) * 3 + size_t(c);
            const size_t dst = (size_t(y) * size_t(lw) + size_t(x)) * 3 + size_t(c);
            nlo[dst] = std::min(nlo[dst], at.cpu_lo.back()[src]);
            nhi[dst] = std::max(nhi[dst], at.cpu_hi.back()[src]);
          }
        }
    at.cpu_lo.push_back(std::move(nlo));
    at.cpu_hi.push_back(std::move(nhi));
  }
}

BatchCell PointBatch::descend_cpu(size_t a, const glm::dvec3& p, double within) {
  Atlas& at = atlases_[a];
  if (boxes_ == PointBoxes::Aabb) build_cpu_pyramid(at);  // the oriented one exists from the start
  const glm::dvec3 q(glm::vec3(p - m_.centre));           // the GPU's float point
  const double eps = kFloatSlack * (glm::length(q) + double(float(radius_)));
  auto box = [&](int level, int x, int y) { return node_distance(at, q, level, x, y); };
  auto sample = [&](int x, int y) { return float_sample(at, a, x, y); };
  struct Node {
    int level, x, y;
    double d;
  };
  const int top = at.levels - 1;
  std::vector<Node> stack{{top, 0, 0, box(top, 0, 0)}};
  BatchCell best{within > 0.0 ? double(float(within)) : kInf, -1, -1, 0};  // the pass's float start
  while (!stack.empty()) {
    const Node n = stack.back();
    stack.pop_back();
    if (n.d > best.distance + eps) continue;
    const int cw = at.level_width(n.level - 1), ch = at.level_height(n.level - 1);
    double d[4];
    for (int k = 0; k < 4; ++k) {
      const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
      d[k] = cx < cw && cy < ch ? box(n.level - 1, cx, cy) : kInf;
    }
    if (n.level == 1) {  // the children are cells: their two triangles
      for (int k = 0; k < 4; ++k) {
        if (d[k] == kInf || d[k] > best.distance + eps) continue;  // empty cells too (point_batch.frag)
        const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
        const glm::dvec3 s[4] = {sample(cx, cy), sample(cx + 1, cy), sample(cx, cy + 1), sample(cx + 1, cy + 1)};
        const float header = at.trim_cell[size_t(cy) * size_t(m_.atlases[a].plan.width) + size_t(cx)];
        glm::dvec3 wts;
        double t = std::min(glm::length(closest_on_triangle(q, s[0], s[1], s[3], wts) - q),
                            glm::length(closest_on_triangle(q, s[0], s[3], s[2], wts) - q));
        if (trim_on_gpu_ && header > 0.0f && t < best.distance)  // no nearer
          t = trimmed_cell_distance(at, q, s, int(header) - 1);
        ++best.tested;
        if (t < best.distance) best.distance = t, best.x = cx, best.y = cy;
      }
      continue;
    }
    // The sorting network of point_batch.frag (same order on ties).
    int order[4] = {0, 1, 2, 3};
    double ds[4] = {d[0], d[1], d[2], d[3]};
    for (const auto& [i, j] : {std::pair{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}})
      if (ds[j] < ds[i]) std::swap(ds[i], ds[j]), std::swap(order[i], order[j]);
    for (int i = 3; i >= 0; --i)
      if (d[order[i]] < kInf && d[order[i]] <= best.distance + eps)
        stack.push_back({n.level - 1, 2 * n.x + (order[i] & 1), 2 * n.y + (order[i] >> 1), d[order[i]]});
  }
  return best;
}

PointDistance PointBatch::search_material(const glm::dvec3& p, double within) const {
  // Best first over every atlas's pyramid, in double; a triangle point in a trimmed region is
  // discarded and the search goes on, as the faithful path does.
  struct Node {
    double d;
    size_t a;
    int level, x, y;
    bool operator>(const Node& o) const { return d > o.d; }
  };
  const glm::dvec3 q(glm::vec3(p - m_.centre));
  const double eps = slack(p);
  std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
  auto box = [&](size_t a, int level, int x, int y) { return node_distance(atlases_[a], q, level, x, y); };
  for (size_t a = 0; a < atlases_.size(); ++a) {
    const int top = atlases_[a].levels - 1;
    open.push({box(a, top, 0, 0), a, top, 0, 0});
  }
  PointDistance best;
  best.distance = within > 0.0 ? within : kInf;  // nothing beyond `within` is wanted
  bool any = false;
  while (!open.empty() && open.top().d <= best.distance + eps) {
    const Node n = open.top();
    open.pop();
    if (!std::isfinite(n.d)) break;
    if (n.level == 0) {
      // The closer triangle's distance is a lower bound of the cell's material distance; a
      // triangle point in a trimmed region is discarded and the search goes on (material_cell).
      if (cell_result(p, n.a, n.x, n.y, false).distance >= best.distance) continue;
      const PointDistance r = material_cell(p, n.a, n.x, n.y);
      if (r.found && r.distance < best.distance) best = r, any = true;
      continue;
    }
    const Atlas& at = atlases_[n.a];
    for (int k = 0; k < 4; ++k) {
      const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
      if (cx < at.level_width(n.level - 1) && cy < at.level_height(n.level - 1))
        open.push({box(n.a, n.level - 1, cx, cy), n.a, n.level - 1, cx, cy});
    }
  }
  return any ? best : PointDistance{};
}

PointDistance PointBatch::query_cpu(const glm::dvec3& p, double within) {
  std::vector<BatchCell> best;
  for (size_t a = 0; a < atlases_.size(); ++a) best.push_back(descend_cpu(a, p, within));  // builds the pyramids
  long long fallbacks = 0, trimmed = 0;
  return finish(p, best, fallbacks, trimmed, within);
}

const std::vector<float>& PointBatch::cpu_level(size_t a, int level, bool hi) {
  build_cpu_pyramid(atlases_[a]);
  return (hi ? atlases_[a].cpu_hi : atlases_[a].cpu_lo)[size_t(level)];
}

void PointBatch::refine_candidates(const glm::dvec3& p, double& upper, std::vector<FaceCell>& out) const {
  struct Node {
    double low;
    size_t a;
    int level, x, y;
    bool operator>(const Node& o) const { return low > o.low; }
  };
  const glm::dvec3 q(glm::vec3(p - m_.centre));  // the pass's float point, as descend_cpu
  const double eps = kFloatSlack * (glm::length(q) + double(float(radius_)));
  std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
  for (size_t a = 0; a < atlases_.size(); ++a) {
    const int top = atlases_[a].levels - 1;
    open.push({node_distance(atlases_[a], q, top, 0, 0) - grow_max_ - eps, a, top, 0, 0});
  }
  struct Found {
    double low;
    FaceCell cell;
  };
  std::vector<Found> found;
  while (!open.empty() && open.top().low <= upper) {
    const Node n = open.top();
    open.pop();
    const Atlas& at = atlases_[n.a];
    if (n.level > 0) {  // the children: inner boxes grown by the largest growth, cells by their face's
      for (int k = 0; k < 4; ++k) {
        const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
        if (cx >= at.level_width(n.level - 1) || cy >= at.level_height(n.level - 1)) continue;
        const double d = node_distance(at, q, n.level - 1, cx, cy);
        if (!std::isfinite(d)) continue;
        double grow = grow_max_;
        if (n.level == 1) {
          const AtlasPlan& plan = m_.atlases[n.a].plan;
          grow = grow_[size_t(plan.slots[size_t(at.slot_of[size_t(cy) * size_t(plan.width) + size_t(cx)])].face)];
        }
        if (d - grow - eps <= upper) open.push({d - grow - eps, n.a, n.level - 1, cx, cy});
      }
      continue;
    }
    glm::dvec3 corner[4];
    const FaceCell c = cell_corners(n.a, n.x, n.y, corner);
    found.push_back({n.low, c});
    // A material corner bounds the distance from above: its surface point lies within the float
    // budget of its sample (corner: model coordinates).
    const nurbs::ParamGrid& g = m_.grids[size_t(c.face)].grid;
    for (int k = 0; k < 4; ++k) {
      const glm::dvec2 uv(g.u[size_t(c.i + (k & 1))], g.v[size_t(c.j + (k >> 1))]);
      if (!m_.faces[size_t(c.face)].loops.empty() && !trim_edges_[size_t(c.face)].is_material(uv)) continue;
      upper = std::min(upper, glm::length(corner[k] - p) + budget_[size_t(c.face)]);
    }
  }
  out.clear();
  for (const Found& f : found)
    if (f.low <= upper) out.push_back(f.cell);
}

PointDistance PointBatch::refine(const glm::dvec3& p, const PointDistance& start, double within,
                                 double tolerance) const {
  // U: the surface at the descent's closest point, where that is material (it is, up to the
  // trim's rounding, when it lies on a trim piece); the candidates' material corners lower it.
  double upper = within > 0.0 ? within : kInf;
  if (start.found) {
    const auto f = size_t(start.face);
    if (m_.faces[f].loops.empty() || trim_edges_[f].is_material(start.uv))
      upper = std::min(upper, glm::length(nurbs::surface_point(m_.faces[f].surface, start.uv.x, start.uv.y) - p));
  }
  std::vector<FaceCell> cells;
  refine_candidates(p, upper, cells);
  PointDistance r;
  r.candidates = start.candidates;
  if (cells.empty()) return r;
  // Candidates per round capped: a point far from the model at a tolerance near the double floor
  // would split cells by the million on each thread; it stops unproven (meets_tolerance false).
  const Refined f = refine_point(m_, cells, p, tolerance, RefineLimits{1LL << 16});
  if (!f.found || (within > 0.0 && f.distance >= within)) return r;
  set_refined(r, f);
  r.upper = upper;
  return r;
}

}  // namespace queries
