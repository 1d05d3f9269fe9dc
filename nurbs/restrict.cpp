#include "nurbs/restrict.h"

#include <algorithm>

#include "nurbs/knot_insertion.h"

namespace nurbs {

HomogeneousCurve restrict_curve(const HomogeneousCurve& curve, double a, double b) {
  HomogeneousCurve h = clamp_curve(curve);
  const int p = h.degree;
  const size_t n = h.points.size();
  a = std::max(a, h.knots[size_t(p)]);
  b = std::min(b, h.knots[n]);
  // Cut at b: with b of multiplicity >= p, the piece [start, b] is points 0..j-1 and knots
  // U[0 .. j+p-1] followed by b, where U[j] is the first copy of b.
  if (b < h.knots[n]) {
    h = insert_knot(h, b, p);
    const size_t j = size_t(std::lower_bound(h.knots.begin(), h.knots.end(), b) - h.knots.begin());
    h.points.resize(j);
    h.knots.resize(j + size_t(p));
    h.knots.push_back(b);
  }
  // Cut at a: with a of multiplicity >= p ending at U[k+p-1], the piece [a, end] is points k-1..
  // and knots a followed by U[k ..].
  if (a > h.knots[size_t(p)]) {
    h = insert_knot(h, a, p);
    const size_t ub = size_t(std::upper_bound(h.knots.begin(), h.knots.end(), a) - h.knots.begin());
    const size_t k = ub - size_t(p);
    h.points.erase(h.points.begin(), h.points.begin() + std::ptrdiff_t(k - 1));
    h.knots.erase(h.knots.begin(), h.knots.begin() + std::ptrdiff_t(k));
    h.knots.insert(h.knots.begin(), a);
  }
  return h;
}

Surface restrict_surface(const Surface& s, Interval u, Interval v) {
  const Surface su = apply_to_rows(s, [&](const HomogeneousCurve& row) { return restrict_curve(row, u.min, u.max); });
  return apply_to_columns(su, [&](const HomogeneousCurve& col) { return restrict_curve(col, v.min, v.max); });
}

}  // namespace nurbs
