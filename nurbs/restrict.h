#pragma once
/// \file restrict.h
/// A curve or surface restricted to a sub-interval of its domain, exactly: knots inserted to
/// multiplicity p at the cut parameters (The NURBS Book §5.3, splitting by A5.1), the pieces
/// outside dropped. Parameters keep their values: the restricted curve at u equals the original at
/// u for u in [a, b]. IGES 126/128 declare such ranges (V(0), V(1) / U(0), U(1), V(0), V(1)).
#include "nurbs/curve.h"
#include "nurbs/homogeneous.h"
#include "nurbs/knot_vector.h"
#include "nurbs/surface.h"

namespace nurbs {

/// The curve on [a, b] intersected with its domain (clamped first if it was not). a < b.
[[nodiscard]] HomogeneousCurve restrict_curve(const HomogeneousCurve& curve, double a, double b);

template <int D>
[[nodiscard]] Curve<D> restrict_curve(const Curve<D>& curve, double a, double b) {
  Curve<D> out = from_homogeneous<D>(restrict_curve(to_homogeneous(curve), a, b), curve.rational());
  out.edge = curve.edge;
  return out;
}

/// The surface on [u.min, u.max] x [v.min, v.max] intersected with its domain.
[[nodiscard]] Surface restrict_surface(const Surface& s, Interval u, Interval v);

}  // namespace nurbs
