#pragma once
/// \file conic_arcs.h
/// Exact rational quadratic NURBS for IGES circular arcs (100) and conic arcs (104). Both are
/// given in a plane z = const of their definition space and run counter-clockwise from start to
/// end (IGES 5.3 §4.3 and §4.5). Invalid input throws std::invalid_argument with the reason.
#include <array>
#include <glm/vec2.hpp>

#include "nurbs/curve.h"

namespace nurbs::io {

/// Circular arc around `centre` from `start` counter-clockwise to `end` (a full circle when they
/// coincide), in the plane z = `z`. Rational quadratic with at most 90° per segment, weights
/// cos(half segment angle) (The NURBS Book §7.5); knots are the angle in radians from 0 to the sweep.
Curve3 circle_arc(const glm::dvec2& centre, const glm::dvec2& start, const glm::dvec2& end, double z);

/// Conic arc of A x² + B xy + C y² + D x + E y + F = 0 (coefficients in that order) from `start` to
/// `end`, plane z = `z`. `form` is IGES 104's form: 1 ellipse, 2 hyperbola, 3 parabola, 0 = decide
/// from B² - 4AC. Ellipses map a unit-circle arc affinely (exact, any sweep); hyperbola and parabola
/// arcs are one rational Bézier segment whose middle point is the tangent intersection and whose
/// weight puts the curve's midpoint on the conic (The NURBS Book §7.3, Eq. 7.8).
Curve3 conic_arc(const std::array<double, 6>& coef, const glm::dvec2& start, const glm::dvec2& end, double z, int form);

}  // namespace nurbs::io
