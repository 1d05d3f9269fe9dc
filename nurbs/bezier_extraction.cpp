#include "nurbs/bezier_extraction.h"

#include <algorithm>

#include "nurbs/knot_insertion.h"

namespace nurbs {

HomogeneousCurve refine_to_bezier(const HomogeneousCurve& curve) {
  const HomogeneousCurve h = clamp_curve(curve);
  const int p = h.degree;
  const std::vector<double>& U = h.knots;
  const auto& P = h.points;
  const int m = static_cast<int>(U.size()) - 1;  // U[0 .. m], m = n + p + 1
  // The Bézier segments in one sweep (The NURBS Book A5.6, DecomposeCurve): each interior knot is
  // raised to multiplicity p in place, O(n p^2), instead of one whole-curve insertion per knot.
  HomogeneousCurve out;
  out.degree = p;
  std::vector<glm::dvec4> seg(P.begin(), P.begin() + p + 1), next(static_cast<size_t>(p + 1));
  std::vector<double> alphas(static_cast<size_t>(std::max(p, 1)));
  out.points.push_back(seg[0]);
  out.knots.assign(static_cast<size_t>(p + 1), U[static_cast<size_t>(p)]);
  int a = p, b = p + 1;
  while (b < m) {
    const int i = b;
    while (b < m && U[static_cast<size_t>(b + 1)] == U[static_cast<size_t>(b)]) ++b;
    const int mult = b - i + 1;
    if (mult < p) {
      const double numer = U[static_cast<size_t>(b)] - U[static_cast<size_t>(a)];
      for (int j = p; j > mult; --j)
        alphas[static_cast<size_t>(j - mult - 1)] = numer / (U[static_cast<size_t>(a + j)] - U[static_cast<size_t>(a)]);
      const int r = p - mult;
      for (int j = 1; j <= r; ++j) {
        const int save = r - j, first = mult + j;
        for (int k = p; k >= first; --k) {
          const double alpha = alphas[static_cast<size_t>(k - first)];
          seg[static_cast<size_t>(k)] =
              alpha * seg[static_cast<size_t>(k)] + (1.0 - alpha) * seg[static_cast<size_t>(k - 1)];
        }
        if (b < m) next[static_cast<size_t>(save)] = seg[static_cast<size_t>(p)];
      }
    }
    // Segment done: its points after the shared first one; the knot between it and the next p times.
    out.points.insert(out.points.end(), seg.begin() + 1, seg.end());
    if (b < m) {
      out.knots.insert(out.knots.end(), static_cast<size_t>(p), U[static_cast<size_t>(b)]);
      for (int k = p - mult; k <= p; ++k) next[static_cast<size_t>(k)] = P[static_cast<size_t>(b - p + k)];
      seg.swap(next);
      a = b;
      ++b;
    }
  }
  out.knots.insert(out.knots.end(), static_cast<size_t>(p + 1), U[static_cast<size_t>(m - p)]);
  return out;
}

namespace {

/// The non-empty spans of a refined knot vector: values at indices p, 2p, ... up to the end.
std::vector<Interval> bezier_ranges(const HomogeneousCurve& refined) {
  std::vector<Interval> out;
  const int p = refined.degree;
  const int pieces = (static_cast<int>(refined.points.size()) - 1) / p;
  for (int i = 0; i < pieces; ++i) {
    out.push_back({refined.knots[static_cast<size_t>(p + i * p)], refined.knots[static_cast<size_t>(p + (i + 1) * p)]});
  }
  return out;
}

std::vector<double> bezier_knots(int p, Interval r) {
  std::vector<double> k(static_cast<size_t>(2 * (p + 1)), r.min);
  std::fill(k.begin() + p + 1, k.end(), r.max);
  return k;
}

}  // namespace

template <int D>
std::vector<BezierSegment<D>> extract_bezier_segments(const Curve<D>& curve) {
  const HomogeneousCurve h = refine_to_bezier(to_homogeneous(curve));
  const int p = h.degree;
  std::vector<BezierSegment<D>> out;
  const auto ranges = bezier_ranges(h);
  for (size_t i = 0; i < ranges.size(); ++i) {
    HomogeneousCurve seg{p, bezier_knots(p, ranges[i]),
                         std::vector<glm::dvec4>(h.points.begin() + static_cast<std::ptrdiff_t>(i) * p,
                                                 h.points.begin() + static_cast<std::ptrdiff_t>(i) * p + p + 1)};
    out.push_back({from_homogeneous<D>(seg, curve.rational()), ranges[i]});
  }
  return out;
}

template std::vector<BezierSegment<2>> extract_bezier_segments(const Curve<2>&);
template std::vector<BezierSegment<3>> extract_bezier_segments(const Curve<3>&);

Surface refine_surface_to_bezier(const Surface& s) {
  return apply_to_columns(apply_to_rows(s, refine_to_bezier), refine_to_bezier);
}

BezierPatch bezier_patch(const Surface& r, int a, int b, Interval range_u, Interval range_v) {
  const int p = r.degree_u, q = r.degree_v;
  BezierPatch patch;
  patch.range_u = range_u;
  patch.range_v = range_v;
  patch.index_u = a;
  patch.index_v = b;
  Surface& ps = patch.surface;
  ps.degree_u = p;
  ps.degree_v = q;
  ps.count_u = p + 1;
  ps.count_v = q + 1;
  ps.knots_u = bezier_knots(p, range_u);
  ps.knots_v = bezier_knots(q, range_v);
  ps.points.reserve(size_t(p + 1) * size_t(q + 1));
  for (int j = 0; j <= q; ++j) {
    for (int i = 0; i <= p; ++i) {
      ps.points.push_back(r.point(a * p + i, b * q + j));
      if (r.rational()) ps.weights.push_back(r.weight(a * p + i, b * q + j));
    }
  }
  return patch;
}

std::vector<BezierPatch> extract_bezier_patches(const Surface& s) {
  const Surface r = refine_surface_to_bezier(s);
  const int p = r.degree_u, q = r.degree_v;
  const auto ru = bezier_ranges({p, r.knots_u, std::vector<glm::dvec4>(static_cast<size_t>(r.count_u))});
  const auto rv = bezier_ranges({q, r.knots_v, std::vector<glm::dvec4>(static_cast<size_t>(r.count_v))});
  std::vector<BezierPatch> out;
  out.reserve(ru.size() * rv.size());
  for (size_t b = 0; b < rv.size(); ++b)
    for (size_t a = 0; a < ru.size(); ++a) out.push_back(bezier_patch(r, int(a), int(b), ru[a], rv[b]));
  return out;
}

}  // namespace nurbs
