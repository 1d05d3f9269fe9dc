#pragma once
/// \file triangulate_detail.h
/// Internal helpers shared by triangulate.cpp and triangulate_monotone.cpp (§7 of Balázs, Guthe,
/// Klein 2004). Not part of the public API.
#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/tessellation/triangulate.h"

namespace nurbs::tess::detail {

/// Sweep order of [Gar78] with ties broken like a slightly rotated line: p comes before q when it has
/// the larger v, or the same v and the smaller u. The first vertex in this order is the "upper left".
[[nodiscard]] inline bool above(glm::dvec2 p, glm::dvec2 q) { return p.y > q.y || (p.y == q.y && p.x < q.x); }

/// Twice the signed area of triangle (a, b, c): > 0 counter-clockwise.
[[nodiscard]] inline double ccw(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Sign of ccw(a, b, c), or 0 when the double determinant is within its rounding bound (Shewchuk's
/// first-stage error bound 3.33e-16 * (|left| + |right|)): the sign is then unknown in double, the
/// triangle a sliver whose orientation is given by the algorithm's topology, not by arithmetic.
[[nodiscard]] inline int orient_sign(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x), det = l - r;
  const double bound = 3.3306690738754716e-16 * (std::abs(l) + std::abs(r));
  return det > bound ? 1 : (det < -bound ? -1 : 0);
}

/// Appends triangle (a, b, c), which the caller's construction makes counter-clockwise.
void emit_triangle(const std::vector<glm::dvec2>& v, int a, int b, int c, std::vector<glm::ivec3>& out,
                   TriangulationStats* stats);

/// Flips each zero-area triangle of out[first..] (collinear points) with its neighbour across the long
/// edge when that gives two proper triangles; counts the slivers left (orient_sign == 0) in `stats`.
void remove_degenerate(const std::vector<glm::dvec2>& v, std::vector<glm::ivec3>& out, std::size_t first,
                       TriangulationStats* stats);

}  // namespace nurbs::tess::detail
