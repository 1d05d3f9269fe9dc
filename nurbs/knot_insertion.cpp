#include "nurbs/knot_insertion.h"

#include <algorithm>

#include "nurbs/knot_vector.h"

namespace nurbs {

namespace {

/// A5.1 proper: u in span k (U[k] <= u < U[k+1]) with multiplicity s, inserted r times, r + s <= p.
/// Also valid at u = U[p] (the alphas only read knots U[k-p+1 ..], all of them past the first).
HomogeneousCurve insert_in_span(const HomogeneousCurve& c, double u, int k, int s, int r) {
  const int p = c.degree;
  const int np = static_cast<int>(c.points.size()) - 1;
  const auto& UP = c.knots;
  const auto& Pw = c.points;
  const int mp = np + p + 1;
  HomogeneousCurve out{p, std::vector<double>(static_cast<size_t>(mp + r) + 1),
                       std::vector<glm::dvec4>(static_cast<size_t>(np + r) + 1)};
  auto& UQ = out.knots;
  auto& Qw = out.points;
  auto at = [](auto& v, int i) -> auto& { return v[static_cast<size_t>(i)]; };
  for (int i = 0; i <= k; ++i) at(UQ, i) = at(UP, i);
  for (int i = 1; i <= r; ++i) at(UQ, k + i) = u;
  for (int i = k + 1; i <= mp; ++i) at(UQ, i + r) = at(UP, i);
  // Unaffected control points before and after the p - s + 1 that get blended.
  for (int i = 0; i <= k - p; ++i) at(Qw, i) = at(Pw, i);
  for (int i = k - s; i <= np; ++i) at(Qw, i + r) = at(Pw, i);
  std::vector<glm::dvec4> Rw(static_cast<size_t>(p - s) + 1);
  for (int i = 0; i <= p - s; ++i) at(Rw, i) = at(Pw, k - p + i);
  int L = k - p + 1;
  for (int j = 1; j <= r; ++j) {
    L = k - p + j;
    for (int i = 0; i <= p - j - s; ++i) {
      const double alpha = (u - at(UP, L + i)) / (at(UP, i + k + 1) - at(UP, L + i));
      at(Rw, i) = alpha * at(Rw, i + 1) + (1.0 - alpha) * at(Rw, i);
    }
    at(Qw, L) = at(Rw, 0);
    at(Qw, k + r - j - s) = at(Rw, p - j - s);
  }
  for (int i = L + 1; i < k - s; ++i) at(Qw, i) = at(Rw, i - L);
  return out;
}

/// Clamps the start only (the end is clamped by reversing).
HomogeneousCurve clamp_start(const HomogeneousCurve& c) {
  const int p = c.degree;
  const int count = static_cast<int>(c.points.size());
  const double umin = c.knots[static_cast<size_t>(p)];
  const int s = knot_multiplicity(c.knots, umin);
  HomogeneousCurve h = s < p ? insert_in_span(c, umin, find_span(c.knots, p, count, umin), s, p - s) : c;
  // u_min now has multiplicity >= p from index `first`; basis functions first-1 .. are the live ones.
  const auto first = std::find(h.knots.begin(), h.knots.end(), umin) - h.knots.begin();
  const auto drop = std::max<std::ptrdiff_t>(first - 1, 0);
  h.knots.erase(h.knots.begin(), h.knots.begin() + drop);
  h.points.erase(h.points.begin(), h.points.begin() + drop);
  h.knots.front() = umin;
  return h;
}

}  // namespace

HomogeneousCurve insert_knot(const HomogeneousCurve& c, double u, int times) {
  const int p = c.degree;
  const int count = static_cast<int>(c.points.size());
  const Interval dom = knot_domain(c.knots, p, count);
  if (!(u > dom.min && u < dom.max) || times <= 0) return c;
  const int s = knot_multiplicity(c.knots, u);
  const int r = std::min(times, p - s);
  if (r <= 0) return c;
  return insert_in_span(c, u, find_span(c.knots, p, count, u), s, r);
}

HomogeneousCurve clamp_curve(const HomogeneousCurve& c) {
  if (is_clamped(c.knots, c.degree)) return c;
  // Clamp the end as the start of the mirrored curve u -> -u (a fixed mirror: reversed() pivots on
  // the knot range, which clamp_start changes).
  auto mirror = [](HomogeneousCurve h) {
    std::reverse(h.knots.begin(), h.knots.end());
    std::reverse(h.points.begin(), h.points.end());
    for (double& k : h.knots) k = -k;
    return h;
  };
  return mirror(clamp_start(mirror(clamp_start(c))));
}

Surface insert_knot_u(const Surface& s, double u, int times) {
  return apply_to_rows(s, [u, times](const HomogeneousCurve& h) { return insert_knot(h, u, times); });
}

Surface insert_knot_v(const Surface& s, double v, int times) {
  return apply_to_columns(s, [v, times](const HomogeneousCurve& h) { return insert_knot(h, v, times); });
}

Surface clamp_surface(const Surface& s) {
  if (is_clamped(s.knots_u, s.degree_u) && is_clamped(s.knots_v, s.degree_v)) return s;
  return apply_to_columns(apply_to_rows(s, clamp_curve), clamp_curve);
}

}  // namespace nurbs
