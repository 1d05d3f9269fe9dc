#pragma once
/// \file curve.h
/// A (rational) B-spline curve in D dimensions. D = 2 for trim curves in the (u, v) parameter
/// plane, D = 3 for model-space curves. Plain data: validation is `validate()` in knot_vector.h /
/// validate.h, evaluation lives in curve_eval.h.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

namespace nurbs {

template <int D>
struct Curve {
  using Point = glm::vec<D, double>;
  int degree = 0;
  std::vector<double> knots;    ///< size = points.size() + degree + 1, non-decreasing
  std::vector<Point> points;    ///< Euclidean control points (not pre-multiplied by weights)
  std::vector<double> weights;  ///< empty = polynomial (all weights 1); else same size as points, > 0
  /// The B-rep edge a trim curve runs along: a model-wide index (IGES 508 edge uses name the same
  /// edge, a 504 list entry, on both faces), -1 when the file gives no topology. Not geometry:
  /// reversal and the readers' repairs keep it; curves they add (gap closers, seam sides) get -1.
  int edge = -1;

  [[nodiscard]] bool rational() const { return !weights.empty(); }
};

using Curve2 = Curve<2>;
using Curve3 = Curve<3>;

}  // namespace nurbs
