#pragma once
/// \file curve_utils.h
/// Small curve helpers of the readers and writers: 2D/3D conversion, affine maps of control points
/// and IGES 110 line segments. Evaluation and reversal are the core's (curve_eval.h, homogeneous.h).
#include <glm/mat4x4.hpp>

#include "nurbs/curve.h"

namespace nurbs::io {

/// The (x, y) of a 3D curve: how IGES parameter-space curves (z = 0) become trim curves.
Curve2 to_2d(const Curve3& c);

/// A 2D curve lifted to z = 0 (for writing trim curves as IGES 126).
Curve3 to_3d(const Curve2& c);

/// Applies an affine map to every control point (rational curves stay exact: weights unchanged).
void transform_points(Curve3& c, const glm::dmat4& m);

/// Degree-1 segment from a to b on the parameter interval [0, 1].
Curve3 line_segment(const glm::dvec3& a, const glm::dvec3& b);

}  // namespace nurbs::io
