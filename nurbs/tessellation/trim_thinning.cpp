#include "nurbs/tessellation/trim_thinning.h"

#include <algorithm>

#include "nurbs/distance/filip_bound.h"
#include "nurbs/tessellation/douglas_peucker.h"

namespace nurbs::tess {

double uv_lipschitz(const std::vector<BezierPatch>& patches) {
  double l = 0.0;
  for (const BezierPatch& p : patches)
    l = std::max(l, first_derivative_bounds(BezierNet::of(p.surface), p.range_u.width(), p.range_v.width()).lipschitz());
  return l;
}

Curve2 thin_polyline(const Curve2& curve, double tol_uv, size_t* removed) {
  const size_t m = curve.points.size();
  if (curve.degree != 1 || curve.rational() || m < 3 || !(tol_uv > 0.0) || curve.knots.size() != m + 2) return curve;
  std::vector<bool> keep(m, false);
  keep.front() = keep.back() = true;
  douglas_peucker(keep, false, [&](size_t k, size_t a, size_t b) {
    return segment_distance(curve.points[k], curve.points[a], curve.points[b]) / tol_uv;
  });
  // Degree 1: point k sits at knot k + 1 (its Greville abscissa); the end knots are doubled.
  Curve2 out;
  out.degree = 1;
  out.edge = curve.edge;
  out.knots.push_back(curve.knots.front());
  for (size_t k = 0; k < m; ++k)
    if (keep[k]) out.points.push_back(curve.points[k]), out.knots.push_back(curve.knots[k + 1]);
  out.knots.push_back(curve.knots.back());
  if (removed) *removed += m - out.points.size();
  return out;
}

}  // namespace nurbs::tess
