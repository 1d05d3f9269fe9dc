#pragma once
/// \file curve_ends.h
/// End points of trim curves and the straight (u, v) segments that the trim repairs insert
/// (trim_surface_gaps.h, trim_seams.h).
#include "nurbs/curve_eval.h"

namespace nurbs {

/// C at the start / end of its domain.
[[nodiscard]] inline glm::dvec2 start_point(const Curve2& c) { return curve_point(c, curve_domain(c).min); }
[[nodiscard]] inline glm::dvec2 end_point(const Curve2& c) { return curve_point(c, curve_domain(c).max); }

/// The segment a -> b as a degree-1 curve over [0, 1].
[[nodiscard]] inline Curve2 segment_curve(glm::dvec2 a, glm::dvec2 b) {
  Curve2 c;
  c.degree = 1;
  c.knots = {0.0, 0.0, 1.0, 1.0};
  c.points = {a, b};
  return c;
}

}  // namespace nurbs
