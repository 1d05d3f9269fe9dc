#pragma once
/// \file curve_utils.h
/// Small curve helpers the readers need before the NURBS core exists: reversal, a de Boor point
/// evaluation (for orientation tests only), and 2D/3D conversion. Not a general NURBS library.
#include "nurbs/curve.h"

#include <glm/mat4x4.hpp>

namespace nurbs::io {

/// The same curve traversed backwards: knots k -> a + b - k (a, b the end knots) in reverse order,
/// points and weights reversed. The parameter interval is unchanged.
template <int D>
Curve<D> reversed(const Curve<D>& c) {
  Curve<D> r;
  r.degree = c.degree;
  const double sum = c.knots.front() + c.knots.back();
  r.knots.assign(c.knots.rbegin(), c.knots.rend());
  for (double& k : r.knots) k = sum - k;
  r.points.assign(c.points.rbegin(), c.points.rend());
  r.weights.assign(c.weights.rbegin(), c.weights.rend());
  return r;
}

/// Point of a 2D curve at parameter t (clamped to the domain), by de Boor's algorithm in
/// homogeneous coordinates (The NURBS Book, A2.1 + A4.1). Assumes a structurally valid curve.
glm::dvec2 curve_point(const Curve2& c, double t);

/// The (x, y) of a 3D curve: how IGES parameter-space curves (z = 0) become trim curves.
Curve2 to_2d(const Curve3& c);

/// A 2D curve lifted to z = 0 (for writing trim curves as IGES 126).
Curve3 to_3d(const Curve2& c);

/// Applies an affine map to every control point (rational curves stay exact: weights unchanged).
void transform_points(Curve3& c, const glm::dmat4& m);

/// Degree-1 segment from a to b on the parameter interval [0, 1].
Curve3 line_segment(const glm::dvec3& a, const glm::dvec3& b);

}  // namespace nurbs::io
