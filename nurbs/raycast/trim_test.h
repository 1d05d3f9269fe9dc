#pragma once
/// \file trim_test.h
/// Lemasson et al. §3.1 "Trimming curves" and §3.4 "Trimming": trim loops become piecewise cubic
/// Bézier curves in (u, v), and a point is classified by its projection on the nearest curve.
///
/// Conversion (ours; the paper gives no method): each Bézier segment of a trim curve is split at
/// its inflection points (sign changes of c' x c'', located by sampling and bisection), then each
/// piece is replaced by its cubic Hermite interpolant (ends and end derivatives), bisected until the
/// sampled distance to the exact curve is <= tolerance. Polynomial pieces of degree <= 3 are
/// reproduced exactly. Loops are re-oriented so that material is on the left (outer CCW, holes CW);
/// a face without outer loops gets its domain rectangle as one.
///
/// Test (§3.4): the nearest cubic by three chords per cubic (c(0) c(1/3) c(2/3) c(1)), t0 from the
/// nearest chord, three Newton steps of Eq. 5 (Schneider 1990), then the side by the sign of the
/// cross product of p_c - p with c'(t_p). With material on the left, p is material when
/// (p_c - p) x c' > 0 (the paper states < 0: its loops run the other way). Dead angles: when the
/// projection ends at a junction, both tangents decide: at a convex corner of the material
/// (left turn, c'_a(1) x c'_b(0) > 0) p is material only if left of both; at a concave one if left
/// of either. In the dead angle itself this is the paper's rule (outside at a convex corner, inside
/// at a concave one).
#include <array>
#include <glm/vec2.hpp>
#include <vector>

#include "nurbs/knot_vector.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::ray {

struct TrimCubic {
  std::array<glm::dvec2, 4> p{};  ///< Bézier control points in the face's (u, v)
  int next = -1;                  ///< index of the following cubic in the same loop (loops are closed)
  int prev = -1;
};

struct TrimCubics {
  std::vector<TrimCubic> cubics;
  Interval domain_u, domain_v;
  double max_error = 0.0;  ///< largest sampled distance to the exact trim curves
};

/// Piecewise cubic Bézier trim loops of a face within `tolerance` (parameter units).
[[nodiscard]] TrimCubics trim_cubics(const TrimmedSurface& face, double tolerance);

/// §3.4: is (u, v) material? Outside the domain is never material.
[[nodiscard]] bool inside_trim(const TrimCubics& trim, glm::dvec2 uv, int newton_iterations = 3);

}  // namespace nurbs::ray
