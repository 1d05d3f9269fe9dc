#pragma once
/// \file curve_eval.h
/// Evaluation of (rational) B-spline curves of any degree: points and derivatives
/// (The NURBS Book A3.2 on the homogeneous curve, then A4.2 for the rational quotient rule).
/// Inputs are assumed valid (see validate.h); parameters outside the domain are clamped to it.
#include <vector>

#include "nurbs/curve.h"
#include "nurbs/knot_vector.h"

namespace nurbs {

/// Parameter domain [U[p], U[n+1]] of the curve.
template <int D>
[[nodiscard]] Interval curve_domain(const Curve<D>& curve) {
  return knot_domain(curve.knots, curve.degree, static_cast<int>(curve.points.size()));
}

/// Point C(u) (A4.1: evaluate the homogeneous curve, divide by w).
template <int D>
[[nodiscard]] glm::vec<D, double> curve_point(const Curve<D>& curve, double u);

/// C(u) and its derivatives wrt u: result[k] = d^k C / du^k for k = 0..order (any order; the
/// queries use <= 2). Homogeneous derivatives by A3.2, Euclidean ones by A4.2:
/// C^(k) = (A^(k) - sum_{i=1..k} C(k,i) w^(i) C^(k-i)) / w.
template <int D>
[[nodiscard]] std::vector<glm::vec<D, double>> curve_derivatives(const Curve<D>& curve, double u, int order);

}  // namespace nurbs
