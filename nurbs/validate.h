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

/// Problems of magnitude, empty when every control point coordinate and knot lies in [-limit, limit]
/// and every weight in [1 / limit, limit]. Valid geometry beyond such a limit (1e300 coordinates)
/// overflows later, in box diagonals, squared distances and derivative bounds; readers refuse it up
/// front. At most one message per kind (the first offender), so the cost stays linear.
template <int D>
[[nodiscard]] std::vector<std::string> validate_magnitude(const Curve<D>& curve, double limit);
[[nodiscard]] std::vector<std::string> validate_magnitude(const Surface& surface, double limit);

}  // namespace nurbs
