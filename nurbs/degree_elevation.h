#pragma once
/// \file degree_elevation.h
/// Degree elevation (The NURBS Book §5.5, A5.9): the same geometry written with degree p + t; each
/// distinct interior knot gains multiplicity t, so the parametric continuity is preserved.
#include "nurbs/homogeneous.h"

namespace nurbs {

/// Raises the degree of a curve by t >= 0 (A5.9 on the homogeneous points: Bézier segments are
/// elevated with the coefficients C(p,j) C(t,i-j) / C(p+t,i) and the knots that extraction inserted
/// are removed again). Unclamped curves are clamped first (clamp_curve), so the result is clamped.
[[nodiscard]] HomogeneousCurve elevate_degree(const HomogeneousCurve& curve, int t);

template <int D>
[[nodiscard]] Curve<D> elevate_degree(const Curve<D>& curve, int t) {
  return from_homogeneous<D>(elevate_degree(to_homogeneous(curve), t), curve.rational());
}

/// Surface degree elevation along u (every row of the net) or v (every column) by t (§5.5: the
/// surface case is A5.9 applied to each row/column of the homogeneous net).
[[nodiscard]] Surface elevate_degree_u(const Surface& s, int t);
[[nodiscard]] Surface elevate_degree_v(const Surface& s, int t);

}  // namespace nurbs
