#pragma once
/// \file surface_eval.h
/// Evaluation of (rational) tensor-product B-spline surfaces of any degree: point, first and
/// second partial derivatives, unit normal (The NURBS Book A3.6 on the homogeneous surface, then
/// A4.4 for the rational quotient rule). Inputs are assumed valid (validate.h); (u, v) outside the
/// domain are clamped to it.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "nurbs/knot_vector.h"
#include "nurbs/surface.h"

namespace nurbs {

/// Domain along u: [knots_u[p], knots_u[count_u]].
[[nodiscard]] Interval surface_domain_u(const Surface& s);
/// Domain along v: [knots_v[q], knots_v[count_v]].
[[nodiscard]] Interval surface_domain_v(const Surface& s);

/// S and its partial derivatives up to order 2, all wrt the surface's own parameters (u, v).
struct SurfaceDerivatives {
  glm::dvec3 s{0.0};
  glm::dvec3 su{0.0}, sv{0.0};
  glm::dvec3 suu{0.0}, suv{0.0}, svv{0.0};
};

/// S and its first partial derivatives wrt (u, v).
struct SurfaceTangents {
  glm::dvec3 s{0.0};
  glm::dvec3 su{0.0}, sv{0.0};
};

/// Point S(u, v) (A4.3).
[[nodiscard]] glm::dvec3 surface_point(const Surface& s, double u, double v);

/// S, Su, Sv, Suu, Suv, Svv at (u, v) (A3.6 homogeneous derivatives + A4.4 quotient rule).
[[nodiscard]] SurfaceDerivatives surface_derivatives(const Surface& s, double u, double v);

/// S, Su, Sv at (u, v): the same values as surface_derivatives, without the second order (a
/// Newton step's evaluation).
[[nodiscard]] SurfaceTangents surface_tangents(const Surface& s, double u, double v);

/// Unit normal normalize(Su x Sv). At a degenerate point (Su or Sv vanishing, e.g. the pole of a
/// sphere whose whole control row collapses) it takes the limit from inside the domain: +-Suv x Sv
/// when Su = 0, +-Su x Suv when Sv = 0 (sign: + on the first half of the domain, - on the second, as
/// Su(u, v0 + dv) ~ dv Suv). Returns (0, 0, 0) when that fails too.
[[nodiscard]] glm::dvec3 surface_normal(const Surface& s, double u, double v);
/// The same from derivatives already evaluated at (u, v) (surface_derivatives(s, u, v)).
[[nodiscard]] glm::dvec3 surface_normal(const Surface& s, const SurfaceDerivatives& d, double u, double v);

/// Upper bounds of |Su| (x) and |Sv| (y) over the whole domain, from the control net, knot span by
/// knot span (only the (p + 1) x (q + 1) points of a span act there): the derivative is a convex
/// combination of p (P[i+1] - P[i]) / (u[i+p+1] - u[i+1]) (Piegl and Tiller §3.3), and for a
/// rational surface Su = (A_u - S w_u) / w with A_u - S w_u a combination of
/// p (w[i+1] (P[i+1] - S) - w[i] (P[i] - S)) / span, bounded by 2 p w_max D / (w_min span), D the
/// diagonal of the span's points' box (S lies in their hull) and w their weights. Infinite for an
/// empty net, a weight not above 0, or a zero span between distinct points.
[[nodiscard]] glm::dvec2 speed_bounds(const Surface& s);

}  // namespace nurbs
