#pragma once
/// \file bezier_extraction.h
/// Bézier extraction: a curve becomes Bézier segments, a surface Bézier patches, by knot insertion
/// of every interior knot up to full multiplicity (The NURBS Book §5.3; the same result as the book's
/// decomposition A5.6/A5.7, computed here by repeated A5.1: each span of a knot vector whose
/// interior multiplicities all equal p is a Bézier piece). Unclamped inputs are clamped first.
/// Each piece keeps its parameter interval of the original curve/surface, so derivatives of the
/// piece wrt its own knots are derivatives wrt the original parameters.
#include <vector>

#include "nurbs/homogeneous.h"
#include "nurbs/knot_vector.h"

namespace nurbs {

/// One Bézier segment: degree p, p + 1 control points, knots {a x (p+1), b x (p+1)}.
template <int D>
struct BezierSegment {
  Curve<D> curve;
  Interval range;  ///< [a, b], a knot span of the source curve
};

/// One Bézier patch: (p+1) x (q+1) control points over the knot rectangle range_u x range_v.
struct BezierPatch {
  Surface surface;
  Interval range_u, range_v;
  int index_u = 0, index_v = 0;  ///< position of the patch among the non-empty spans
};

/// Homogeneous curve with every interior knot raised to multiplicity p and clamped ends
/// (points [i p .. i p + p] then form segment i).
[[nodiscard]] HomogeneousCurve refine_to_bezier(const HomogeneousCurve& curve);

/// Bézier segments of a valid curve, in parameter order, one per non-empty knot span.
template <int D>
[[nodiscard]] std::vector<BezierSegment<D>> extract_bezier_segments(const Curve<D>& curve);

/// Surface whose knot vectors both have full interior multiplicity and clamped ends.
[[nodiscard]] Surface refine_surface_to_bezier(const Surface& s);

/// Bézier patches of a valid surface, row-major with u fastest (patch (a, b) at b * spans_u + a).
[[nodiscard]] std::vector<BezierPatch> extract_bezier_patches(const Surface& s);

}  // namespace nurbs
