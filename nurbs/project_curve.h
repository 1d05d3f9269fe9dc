#pragma once
/// \file project_curve.h
/// Model-space curves onto a surface, into its (u, v) plane: for trim curves a file gives only in
/// model space (IGES 142 with BPTR = 0, 508 edge uses with K = 0). Point inversion as in The NURBS
/// Book §6.1: a start from the nearest point of a coarse grid of the surface, then Newton's method
/// on f(u, v) = (S(u, v) - P) . Su = 0, g(u, v) = (S(u, v) - P) . Sv = 0 (eqs. 6.5-6.7), clamped to
/// the domain.
#include <optional>
#include <string>

#include "nurbs/curve.h"
#include "nurbs/surface.h"

namespace nurbs {

/// Parameters (u, v) of the point of `s` nearest to `p`, by Newton from `start` (at most 50 steps,
/// until a step is below 1e-13 of the larger domain width).
[[nodiscard]] glm::dvec2 closest_parameter(const Surface& s, glm::dvec3 p, glm::dvec2 start);

/// The same from the nearest sample of a (8 (n_u - p) + 1) x (8 (n_v - q) + 1) grid (at most 257 each).
[[nodiscard]] glm::dvec2 closest_parameter(const Surface& s, glm::dvec3 p);

/// A projected curve, or why there is none.
struct ProjectedCurve {
  std::optional<Curve2> curve;  ///< degree 1 through the projected samples, knots = curve parameters
  double distance = 0.0;        ///< largest distance of a sample of the curve from the surface
  std::string problem;          ///< set when `curve` is empty
};

/// `c` in the (u, v) plane of `s` as a degree-1 Curve2: samples at 16 parameters per knot span,
/// each chord halved while the surface point of its (u, v) midpoint lies more than `tolerance`
/// (model units) from the curve's midpoint (at most 2^12 pieces per sample interval). Each sample
/// starts Newton from the previous one (continuity). Fails when a sample is more than `tolerance`
/// from the surface: then `c` is no curve on `s`.
[[nodiscard]] ProjectedCurve project_curve(const Surface& s, const Curve3& c, double tolerance);

}  // namespace nurbs
