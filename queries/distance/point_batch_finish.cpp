// Step 3 of the batched point projection (point_batch_finish.h): per point in double, from the
// atlases' best cells to the answer, its trim test, the search again and the refinement.
#include "queries/distance/point_batch_finish.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <queue>

#include "nurbs/surface_eval.h"
#include "queries/distance/cell_triangles.h"
#include "queries/distance/refine.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

PointDistance BatchFinish::cell_result(const glm::dvec3& p, size_t a, int x, int y, bool trim_edge, int triangle) const {
  glm::dvec3 corner[4];
  const FaceCell cell = g_.cell_corners(a, x, y, corner);
  const auto f = size_t(cell.face);
  const int i = cell.i, j = cell.j;
  const nurbs::ParamGrid& g = g_.m.grids[f].grid;
  // The cell's two triangles (cell_triangles.h), with their corners' parameters.
  const CellTriangles tri =
      cell_triangles(corner, g.u[size_t(i)], g.u[size_t(i) + 1], g.v[size_t(j)], g.v[size_t(j) + 1]);
  PointDistance r;
  r.distance = kInf;
  for (int t = 0; t < 2; ++t) {
    if (triangle >= 0 && t != triangle) continue;
    glm::dvec3 w;
    const glm::dvec3 c = closest_on_triangle(p, tri.p[t][0], tri.p[t][1], tri.p[t][2], w);
    const double d = glm::length(c - p);
    if (d < r.distance) r.distance = d, r.point = c, r.uv = tri.uv_at(t, w);
  }
  r.found = true;
  r.face = cell.face;
  if (trim_edge && !g_.m.faces[f].loops.empty())
    for (int c = 0; c < 4; ++c)
      if (!g_.trim_edges[f].is_material({g.u[size_t(i + (c & 1))], g.v[size_t(j + (c >> 1))]})) r.on_trim_edge = true;
  const double k = g_.model_bound + 2.0 * g_.slack(p);
  r.bound = k;
  r.point_bound = std::sqrt(4 * k * r.distance + k * k);
  return r;
}

bool BatchFinish::material(const PointDistance& r) const {
  const auto f = size_t(r.face);
  return g_.m.faces[f].loops.empty() || g_.trim_edges[f].is_material(r.uv);
}

PointDistance BatchFinish::finish(const glm::dvec3& p, const std::vector<BatchCell>& best, long long& fallbacks,
                                 long long& trimmed, double within) const {
  size_t win = best.size();
  long long tested = 0;
  for (size_t a = 0; a < best.size(); ++a) {
    tested += best[a].tested;
    if (best[a].x >= 0 && (win == best.size() || best[a].distance < best[win].distance)) win = a;
  }
  PointDistance r;
  if (win < best.size()) r = cell_result(p, win, best[win].x, best[win].y);
  if (r.found && !material(r)) {  // §5.3: the closest triangle point lies in a trimmed region
    ++trimmed;
    if (trim_on_gpu_) r = material_cell(p, win, best[win].x, best[win].y);
    if (!trim_on_gpu_ || !r.found) {  // (or the float pass judged a point within rounding of a trim edge)
      ++fallbacks;
      r = search_material(p, within);
    }
  }
  r.candidates = tested;
  if (g_.m.search == Search::CoarseToFine) return refine(p, r, within, g_.m.tolerance);
  if (refine_to_ > 0.0 && r.found && r.bound > refine_to_) return refine(p, r, within, refine_to_);
  return r;
}

PointDistance BatchFinish::search_material(const glm::dvec3& p, double within) const {
  // Best first over every atlas's pyramid, in double; a triangle point in a trimmed region is
  // discarded and the search goes on, as the faithful path does.
  struct Node {
    double d;
    size_t a;
    int level, x, y;
    bool operator>(const Node& o) const { return d > o.d; }
  };
  const glm::dvec3 q(glm::vec3(p - g_.m.centre));
  const double eps = g_.slack(p);
  std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
  auto box = [&](size_t a, int level, int x, int y) { return g_.node_distance(g_.atlases[a], q, level, x, y); };
  for (size_t a = 0; a < g_.atlases.size(); ++a) {
    const int top = g_.atlases[a].levels - 1;
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
    const BatchAtlas& at = g_.atlases[n.a];
    for (int k = 0; k < 4; ++k) {
      const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
      if (cx < at.level_width(n.level - 1) && cy < at.level_height(n.level - 1))
        open.push({box(n.a, n.level - 1, cx, cy), n.a, n.level - 1, cx, cy});
    }
  }
  return any ? best : PointDistance{};
}

void BatchFinish::refine_candidates(const glm::dvec3& p, double& upper, std::vector<FaceCell>& out) const {
  struct Node {
    double low;
    size_t a;
    int level, x, y;
    bool operator>(const Node& o) const { return low > o.low; }
  };
  const glm::dvec3 q(glm::vec3(p - g_.m.centre));  // the pass's float point, as descend_cpu
  const double eps = kFloatSlack * (glm::length(q) + double(float(g_.radius)));
  std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
  for (size_t a = 0; a < g_.atlases.size(); ++a) {
    const int top = g_.atlases[a].levels - 1;
    open.push({g_.node_distance(g_.atlases[a], q, top, 0, 0) - g_.grow_max - eps, a, top, 0, 0});
  }
  struct Found {
    double low;
    FaceCell cell;
  };
  std::vector<Found> found;
  while (!open.empty() && open.top().low <= upper) {
    const Node n = open.top();
    open.pop();
    const BatchAtlas& at = g_.atlases[n.a];
    if (n.level > 0) {  // the children: inner boxes grown by the largest growth, cells by their face's
      for (int k = 0; k < 4; ++k) {
        const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
        if (cx >= at.level_width(n.level - 1) || cy >= at.level_height(n.level - 1)) continue;
        const double d = g_.node_distance(at, q, n.level - 1, cx, cy);
        if (!std::isfinite(d)) continue;
        double grow = g_.grow_max;
        if (n.level == 1) {
          const AtlasPlan& plan = g_.m.atlases[n.a].plan;
          grow = g_.grow[size_t(plan.slots[size_t(at.slot_of[size_t(cy) * size_t(plan.width) + size_t(cx)])].face)];
        }
        if (d - grow - eps <= upper) open.push({d - grow - eps, n.a, n.level - 1, cx, cy});
      }
      continue;
    }
    glm::dvec3 corner[4];
    const FaceCell c = g_.cell_corners(n.a, n.x, n.y, corner);
    found.push_back({n.low, c});
    // A material corner bounds the distance from above: its surface point lies within the float
    // budget of its sample (corner: model coordinates).
    const nurbs::ParamGrid& g = g_.m.grids[size_t(c.face)].grid;
    for (int k = 0; k < 4; ++k) {
      const glm::dvec2 uv(g.u[size_t(c.i + (k & 1))], g.v[size_t(c.j + (k >> 1))]);
      if (!g_.m.faces[size_t(c.face)].loops.empty() && !g_.trim_edges[size_t(c.face)].is_material(uv)) continue;
      upper = std::min(upper, glm::length(corner[k] - p) + g_.budget[size_t(c.face)]);
    }
  }
  out.clear();
  for (const Found& f : found)
    if (f.low <= upper) out.push_back(f.cell);
}

PointDistance BatchFinish::refine(const glm::dvec3& p, const PointDistance& start, double within,
                                 double tolerance) const {
  // U: the surface at the descent's closest point, where that is material (it is, up to the
  // trim's rounding, when it lies on a trim piece); the candidates' material corners lower it.
  double upper = within > 0.0 ? within : kInf;
  if (start.found) {
    const auto f = size_t(start.face);
    if (g_.m.faces[f].loops.empty() || g_.trim_edges[f].is_material(start.uv))
      upper = std::min(upper, glm::length(nurbs::surface_point(g_.m.faces[f].surface, start.uv.x, start.uv.y) - p));
  }
  std::vector<FaceCell> cells;
  refine_candidates(p, upper, cells);
  PointDistance r;
  r.candidates = start.candidates;
  if (cells.empty()) return r;
  // Candidates per round capped: a point far from the model at a tolerance near the double floor
  // would split cells by the million on each thread; it stops unproven (meets_tolerance false).
  const Refined f = refine_point(g_.m, cells, p, tolerance, RefineLimits{1LL << 16});
  if (!f.found || (within > 0.0 && f.distance >= within)) return r;
  set_refined(r, f);
  r.upper = upper;
  return r;
}

}  // namespace queries
