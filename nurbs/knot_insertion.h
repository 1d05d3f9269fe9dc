#pragma once
/// \file knot_insertion.h
/// Knot insertion (The NURBS Book §5.2, A5.1) for curves and surfaces, and clamping of unclamped
/// knot vectors by insertion. The geometry is unchanged; only the representation grows.
#include "nurbs/homogeneous.h"

namespace nurbs {

/// Inserts `u` into the knot vector `times` times (A5.1 on the homogeneous points). The count is
/// capped so the multiplicity of u does not exceed the degree; u outside the open domain
/// (u <= U[p] or u >= U[n+1]) leaves the curve unchanged (use clamp_curve for the ends).
[[nodiscard]] HomogeneousCurve insert_knot(const HomogeneousCurve& curve, double u, int times);

template <int D>
[[nodiscard]] Curve<D> insert_knot(const Curve<D>& curve, double u, int times) {
  return from_homogeneous<D>(insert_knot(to_homogeneous(curve), u, times), curve.rational());
}

/// Surface knot insertion along u (A5.3 is A5.1 applied to every row of the net) and along v
/// (every column). Same capping rules as the curve version.
[[nodiscard]] Surface insert_knot_u(const Surface& s, double u, int times);
[[nodiscard]] Surface insert_knot_v(const Surface& s, double v, int times);

/// Equivalent clamped curve over the same domain [U[p], U[n+1]]: inserts the domain ends up to
/// multiplicity p and drops the control points and knots outside the domain (the first and last
/// knot values do not affect the basis on the domain, so they are set to the domain ends).
/// Already clamped curves are returned unchanged.
[[nodiscard]] HomogeneousCurve clamp_curve(const HomogeneousCurve& curve);

/// clamp_curve applied to every row (along u) and every column (along v).
[[nodiscard]] Surface clamp_surface(const Surface& s);

}  // namespace nurbs
