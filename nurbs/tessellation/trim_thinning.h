#pragma once
/// \file trim_thinning.h
/// Beyond the paper: trim curves written as dense polylines are thinned in (u, v) before §4 lifts
/// them. B-rep writers of other kernels often store a face's pcurves as degree-1 B-splines of
/// hundreds of points sampled along a nearly straight or gently curved (u, v) path (the Ventilator
/// B-rep: 1,282 such curves, 92 % of their inner points collinear within 1e-6 of the curve's length).
/// §4 lifts every segment to a 3D Bézier curve of its own, and §5's simplification then removes
/// almost all of the resulting vertices again; on such a model the lifting was three quarters of
/// the tessellation's time.
///
/// The bound. Douglas-Peucker on the control polygon keeps a subset of its vertices (the ends
/// always) such that every dropped vertex lies within tol_uv of the segment that replaces its
/// chain; the two polylines are then within tol_uv of each other both ways in (u, v) (the argument
/// of simplify_loop in trim_polyline.h). The surface maps (u, v) points tol_uv apart to points at
/// most L tol_uv apart, L = max over the surface's Bézier patches of sqrt(D_u^2 + D_v^2)
/// (first_derivative_bounds in filip_bound.h; clamping into the domain is 1-Lipschitz), so the
/// thinned curves' images are within delta = L tol_uv of the file's trim curves in space, both ways.
/// approximate_trim_loops charges delta to the loop budget (TrimApproxOptions::thinning).
#include <cstddef>
#include <vector>

#include "nurbs/bezier_extraction.h"
#include "nurbs/curve.h"

namespace nurbs::tess {

/// The Lipschitz constant L of the file comment for a surface's Bézier patches (its
/// extract_bezier_patches): ||S(a) - S(b)|| <= L ||a - b|| for a, b in the domain.
[[nodiscard]] double uv_lipschitz(const std::vector<BezierPatch>& patches);

/// A degree-1 polynomial curve with more than two points, Douglas-Peucker-thinned within tol_uv
/// (file comment): the kept points with their own parameters (so the parameter range and the
/// parameters of the kept points are unchanged). Any other curve is returned as it is. `removed`
/// (optional) is increased by the number of points dropped.
[[nodiscard]] Curve2 thin_polyline(const Curve2& curve, double tol_uv, size_t* removed = nullptr);

}  // namespace nurbs::tess
