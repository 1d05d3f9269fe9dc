#pragma once
/// \file validate.h
/// Validation of curves and surfaces: an explicit call returning everything that is wrong, so
/// readers can report it and evaluation code can assume valid input.
#include <string>
#include <vector>

#include "nurbs/curve.h"
#include "nurbs/surface.h"

namespace nurbs {

/// Problems of a curve, empty when valid: the knot vector (validate_knots, prefixed "knots: "),
/// weights count equal to points count when rational, every weight finite and > 0, every control
/// point coordinate finite.
template <int D>
[[nodiscard]] std::vector<std::string> validate(const Curve<D>& curve);

/// Problems of a surface, empty when valid: both knot vectors ("knots_u: ", "knots_v: "),
/// points.size() == count_u * count_v, weights (if any) of the same size, finite and > 0, finite points.
[[nodiscard]] std::vector<std::string> validate(const Surface& surface);

/// The largest ratio of a curve's or surface's largest weight to its smallest that validate_magnitude
/// accepts. The rational bounds (Filip's K, the tessellation's cell bounds) grow with this ratio and
/// lose their digits with it: a sphere patch with one weight 1e8 times the others gets a
/// "guaranteed" mesh 10x off its surface after 1.7 million triangles, and one at 1e9 takes minutes.
/// Two orders of magnitude below that, 1e6 still meets eps (in 2.6 s on that patch at 1e-3).
inline constexpr double kMaxWeightRatio = 1e6;

/// Problems of magnitude, empty when every control point coordinate and knot lies in [-limit, limit],
/// every weight in [1 / limit, limit], and the largest weight at most kMaxWeightRatio times the
/// smallest. Valid geometry beyond such a limit (1e300 coordinates) overflows later, in box
/// diagonals, squared distances and derivative bounds; readers refuse it up front. At most one
/// message per kind (the first offender), so the cost stays linear.
template <int D>
[[nodiscard]] std::vector<std::string> validate_magnitude(const Curve<D>& curve, double limit);
[[nodiscard]] std::vector<std::string> validate_magnitude(const Surface& surface, double limit);

}  // namespace nurbs
