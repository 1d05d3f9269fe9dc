#pragma once
/// \file bezier_eval.h
/// First-order evaluation of a surface from its Bézier form, for the many Newton steps of ray
/// casting: the surface refined to Bézier patches once (bezier_extraction.h), then per call the
/// patch of (u, v) by a binary search of the span breaks, the Bernstein values and derivatives of
/// degrees p and q (no divisions), and the tensor contraction of its homogeneous control points
/// with the rational quotient rule (The NURBS Book A4.4, first order), its loops unrolled for
/// degrees 1 to 3 in each direction. The same S, Su, Sv as surface_tangents (surface_eval.h) up to
/// rounding.
#include <glm/vec4.hpp>
#include <vector>

#include "nurbs/surface.h"
#include "nurbs/surface_eval.h"

namespace nurbs {

class BezierForm {
 public:
  /// Degrees above this are left to surface_tangents.
  static constexpr int kMaxDegree = 15;

  BezierForm() = default;
  /// Refines `s` (valid) to Bézier form unless its degree exceeds kMaxDegree or the refined net
  /// would hold more than `max_points` control points: empty() then.
  explicit BezierForm(const Surface& s, size_t max_points = size_t(1) << 20);

  [[nodiscard]] bool empty() const { return net_.empty(); }
  /// S, Su, Sv at (u, v) clamped to the domain; at a knot, the patch on its right (as find_span).
  [[nodiscard]] SurfaceTangents tangents(double u, double v) const;

 private:
  int p_ = 0, q_ = 0;
  std::vector<double> bu_, bv_;  ///< the patches' parameter breaks, increasing
  std::vector<glm::dvec4> net_;  ///< patch (a, b)'s (w P, w) at (b nu + a) (p+1)(q+1) + j (p+1) + i
};

}  // namespace nurbs
