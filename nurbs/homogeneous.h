#pragma once
/// \file homogeneous.h
/// Homogeneous (4D, weight-premultiplied) form of curves and surface rows/columns: P^w = (w x, w y,
/// w z, w) (The NURBS Book §4.2). Knot insertion, degree elevation and Bézier extraction are linear
/// maps on P^w, so one implementation serves polynomial and rational, 2D and 3D geometry.
#include <glm/vec4.hpp>
#include <vector>

#include "nurbs/curve.h"
#include "nurbs/surface.h"

namespace nurbs {

/// A B-spline curve in homogeneous 4D space. Unused coordinates (z of 2D curves) are zero.
struct HomogeneousCurve {
  int degree = 0;
  std::vector<double> knots;
  std::vector<glm::dvec4> points;  ///< (w x, w y, w z, w)
};

/// Curve -> homogeneous curve (weight 1 when polynomial).
template <int D>
[[nodiscard]] HomogeneousCurve to_homogeneous(const Curve<D>& curve);

/// Homogeneous curve -> curve; `rational` false drops the weights (caller knows they are all 1).
template <int D>
[[nodiscard]] Curve<D> from_homogeneous(const HomogeneousCurve& h, bool rational);

/// Knots of the reversed parametrisation u -> a + b - u over the knot range [a, b], in order.
[[nodiscard]] std::vector<double> reversed_knots(const std::vector<double>& knots);

/// The same curve traversed backwards: parameter u -> a + b - u over its knot range [a, b],
/// control points (and weights) and knots reversed. Used to clamp curve ends and to orient trim
/// loops. The curve form copies points and weights exactly (no trip through P^w).
[[nodiscard]] HomogeneousCurve reversed(const HomogeneousCurve& h);
template <int D>
[[nodiscard]] Curve<D> reversed(const Curve<D>& c) {
  return {c.degree,
          reversed_knots(c.knots),
          {c.points.rbegin(), c.points.rend()},
          {c.weights.rbegin(), c.weights.rend()},
          c.edge};
}

/// Row j of the control net (points (0..count_u-1, j)) as a homogeneous curve along u.
[[nodiscard]] HomogeneousCurve surface_row(const Surface& s, int j);

/// Column i of the control net (points (i, 0..count_v-1)) as a homogeneous curve along v.
[[nodiscard]] HomogeneousCurve surface_column(const Surface& s, int i);

/// Reassembles a surface from rows that all share one knot vector along u (the result of applying a
/// curve algorithm to every row). `like` supplies the v data; `rational` keeps weights.
[[nodiscard]] Surface surface_from_rows(const std::vector<HomogeneousCurve>& rows, const Surface& like, bool rational);

/// Same from columns sharing one knot vector along v; `like` supplies the u data.
[[nodiscard]] Surface surface_from_columns(const std::vector<HomogeneousCurve>& cols, const Surface& like,
                                           bool rational);

/// A curve algorithm `op` (HomogeneousCurve -> HomogeneousCurve, the same knot vector out for every
/// input) applied to every row of the control net: the surface operation along u (The NURBS Book
/// ch. 5: surface knot insertion, refinement and degree elevation are the curve ones row by row).
template <typename Op>
[[nodiscard]] Surface apply_to_rows(const Surface& s, Op op) {
  std::vector<HomogeneousCurve> rows;
  rows.reserve(static_cast<size_t>(s.count_v));
  for (int j = 0; j < s.count_v; ++j) rows.push_back(op(surface_row(s, j)));
  return surface_from_rows(rows, s, s.rational());
}

/// Same for every column: the surface operation along v.
template <typename Op>
[[nodiscard]] Surface apply_to_columns(const Surface& s, Op op) {
  std::vector<HomogeneousCurve> cols;
  cols.reserve(static_cast<size_t>(s.count_u));
  for (int i = 0; i < s.count_u; ++i) cols.push_back(op(surface_column(s, i)));
  return surface_from_columns(cols, s, s.rational());
}

}  // namespace nurbs
