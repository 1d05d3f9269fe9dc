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

/// Patch (a, b) of a surface refined to Bézier form (refine_surface_to_bezier), copied out, over
/// the knot rectangle range_u x range_v.
[[nodiscard]] BezierPatch bezier_patch(const Surface& refined, int a, int b, Interval range_u, Interval range_v);

/// The control net of one Bézier patch read in place: patch (a, b) of a surface refined to Bézier
/// form (refine_surface_to_bezier) is its points (a p .. a p + p, b q .. b q + q), with no copy; a
/// lone patch (a Bézier surface) is BezierNet::of(patch).
struct BezierNet {
  const Surface* s = nullptr;
  int i0 = 0, j0 = 0;  ///< the patch's first control point in s
  int p = 0, q = 0;    ///< degrees
  [[nodiscard]] static BezierNet of(const Surface& patch) { return {&patch, 0, 0, patch.degree_u, patch.degree_v}; }
  [[nodiscard]] static BezierNet in_refined(const Surface& refined, int a, int b) {
    return {&refined, a * refined.degree_u, b * refined.degree_v, refined.degree_u, refined.degree_v};
  }
  [[nodiscard]] const glm::dvec3& point(int i, int j) const { return s->point(i0 + i, j0 + j); }
  [[nodiscard]] double weight(int i, int j) const { return s->weight(i0 + i, j0 + j); }
};

}  // namespace nurbs
