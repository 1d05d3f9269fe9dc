#include "nurbs/tessellation/rectangle_face.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "nurbs/curve_eval.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/trim_polyline.h"

namespace nurbs::tess {
namespace {

/// The side of box [lo, hi] that holds every control point of c (0: u = lo.x, 1: u = hi.x,
/// 2: v = lo.y, 3: v = hi.y), with the other coordinate monotone; -1 when none does.
int side_of(const Curve2& c, glm::dvec2 lo, glm::dvec2 hi, double tol) {
  for (int s = 0; s < 4; ++s) {
    const int axis = s < 2 ? 0 : 1;
    const double at = s % 2 == 0 ? (axis == 0 ? lo.x : lo.y) : (axis == 0 ? hi.x : hi.y);
    bool on = true, up = true, down = true;
    for (size_t i = 0; i < c.points.size() && on; ++i) {
      on = std::abs(c.points[i][axis] - at) <= tol;
      if (i > 0) {
        const double d = c.points[i][1 - axis] - c.points[i - 1][1 - axis];
        up = up && d >= 0.0;
        down = down && d <= 0.0;
      }
    }
    if (on && (up || down)) return s;
  }
  return -1;
}

}  // namespace

std::optional<ParamRect> boundary_rectangle(const TrimmedSurface& face) {
  const std::vector<TrimLoop> loops = loops_to_approximate(face);
  const auto outer = [](const TrimLoop& l) { return l.outer; };
  const auto it = std::find_if(loops.begin(), loops.end(), outer);
  if (std::count_if(loops.begin(), loops.end(), outer) != 1 || it->curves.empty()) return std::nullopt;
  const TrimLoop& loop = *it;
  glm::dvec2 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (const Curve2& c : loop.curves) {
    if (c.points.empty() || c.knots.size() != c.points.size() + size_t(c.degree) + 1) return std::nullopt;
    for (const glm::dvec2& p : c.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  const glm::dvec2 size = hi - lo;
  if (!(size.x > 0.0 && size.y > 0.0) || !std::isfinite(size.x + size.y)) return std::nullopt;
  const double tol = 1e-12 * std::max(size.x, size.y);
  std::vector<glm::dvec2> ends;  // start and end of every curve, in loop order
  for (const Curve2& c : loop.curves) {
    if (side_of(c, lo, hi, tol) < 0) return std::nullopt;
    ends.push_back(curve_point(c, c.knots[size_t(c.degree)]));
    ends.push_back(curve_point(c, c.knots[c.points.size()]));
  }
  double area2 = 0.0;  // twice the signed area of the polygon of the curve ends
  for (size_t k = 0; k < ends.size(); k += 2) {
    const glm::dvec2 a = ends[k], b = ends[k + 1], next = ends[(k + 2) % ends.size()];
    if (glm::length(next - b) > 1e3 * tol) return std::nullopt;  // not joined end to start
    area2 += (a.x - lo.x) * (b.y - lo.y) - (b.x - lo.x) * (a.y - lo.y);
  }
  if (std::abs(0.5 * area2 - size.x * size.y) > 1e-9 * size.x * size.y) return std::nullopt;
  const Interval du = surface_domain_u(face.surface), dv = surface_domain_v(face.surface);
  ParamRect r{glm::max(lo, glm::dvec2(du.min, dv.min)), glm::min(hi, glm::dvec2(du.max, dv.max))};
  if (!(r.lo.x < r.hi.x && r.lo.y < r.hi.y)) return std::nullopt;
  return r;
}

LoopPolyline rectangle_polyline(const Surface& surface, const ParamRect& r) {
  LoopPolyline l;
  l.outer = true;
  l.uv = {r.lo, {r.hi.x, r.lo.y}, r.hi, {r.lo.x, r.hi.y}};
  for (const glm::dvec2& p : l.uv) l.xyz.push_back(surface_point(surface, p.x, p.y));
  return l;
}

}  // namespace nurbs::tess
