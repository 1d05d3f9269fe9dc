#pragma once
/// \file homogeneous.h
/// Homogeneous (4D, weight-premultiplied) form of curves and surface rows/columns: P^w = (w x, w y,
/// w z, w) (The NURBS Book §4.2). Knot insertion, degree elevation and Bézier extraction are linear
/// maps on P^w, so one implementation serves polynomial and rational, 2D and 3D geometry.
#include "nurbs/curve.h"
#include "nurbs/surface.h"

#include <glm/vec4.hpp>
#include <vector>

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

/// The same curve traversed backwards: parameter u -> a + b - u over its knot range [a, b],
/// control points and knots reversed. Used to clamp curve ends and to orient trim loops.
[[nodiscard]] HomogeneousCurve reversed(const HomogeneousCurve& h);
template <int D>
[[nodiscard]] Curve<D> reversed(const Curve<D>& c) {
  return from_homogeneous<D>(reversed(to_homogeneous(c)), c.rational());
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

}  // namespace nurbs
