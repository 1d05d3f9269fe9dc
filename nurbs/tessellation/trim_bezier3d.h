#pragma once
/// \file trim_bezier3d.h
/// §4 "Conversion of trimming" of Balázs, Guthe, Klein (WSCG 2004): every 2D trim curve c(t) of a
/// face becomes a sequence of 3D Bézier curves that reproduce S(c(t)) exactly (up to rounding).
///
/// 1. The trim curve is split into its Bézier segments, and each segment is cut where it crosses an
///    interior u or v knot line of the surface (Bernstein root isolation + bisection), so that each
///    piece lies on one Bézier patch. The domain edges are cut lines too: IGES trims overshoot the
///    domain by 1e-9..1e-4, and a piece beyond an edge, say u < u_min, gets x := u_min in all its
///    control points, which is exactly the clamped curve (u_min, v(t)) that direct evaluation with
///    clamped (u, v) sees. (Clamping control points instead would be wrong: a trim circle inside the
///    domain can have control points far outside it.)
/// 2. Lifting (homogeneous form). With the trim piece c = (X/W, Y/W) (X, Y, W polynomials of degree
///    d2d in Bernstein form; W = 1 when polynomial) and the patch S^w(u, v) = sum B_i(s) B_j(r) P^w_ij
///    (P^w = (w x, w y, w z, w), s = (u - u0)/(u1 - u0), r likewise), every factor B_i(s(t)) W^du is
///    C(du,i) U0^i U1^(du-i) with U0 = (X - u0 W)/(u1 - u0), U1 = (u1 W - X)/(u1 - u0) of degree d2d.
///    Hence Q(t) = W(t)^(du + dv) S^w(c(t)) is a 4D polynomial of degree d3d = d2d (du + dv); its
///    weight Q.w = W^(du+dv) w_S(c(t)) > 0 and Q.xyz / Q.w = S(c(t)). Q is found either by the paper's
///    collocation (d3d + 1 equally spaced samples, Bernstein matrix solved by SVD) or exactly by
///    Bernstein products (the same formula evaluated symbolically), which is the fallback.
/// 3. Lossless degree reduction (Farin's forward/backward formulas, blended as in the paper),
///    repeated while the reduced curve, degree-elevated back, reproduces the control points within a
///    tiny relative tolerance (the sup-norm distance of two Bézier curves of one degree is at most
///    the largest control point difference, so that test bounds the loss).
#include <vector>

#include "nurbs/bezier_extraction.h"
#include "nurbs/homogeneous.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

/// One piece of a trim curve on one Bézier patch of the surface, with its 3D image.
struct TrimCurve3 {
  Curve2 uv;              ///< the 2D Bézier piece (degree d2d, maybe rational) on [range.min, range.max]
  HomogeneousCurve xyz;   ///< 3D Bézier curve in homogeneous 4D form (w x, w y, w z, w), same parameter range
  Interval range;         ///< parameter interval of the piece in the source trim curve
  int lifted_degree = 0;  ///< d2d (du + dv), before the degree reduction
  int patch = -1;         ///< index into extract_bezier_patches(surface)
  bool composed = false;  ///< true when lifted exactly by Bernstein products instead of collocation
  double error = 0.0;     ///< measured max |xyz(t) - S(uv(t))| at off-sample parameters (model units)
};

/// How a piece is lifted to 3D.
enum class LiftMethod {
  Auto,         ///< collocation up to max_degree and when it verifies, else composition
  Collocation,  ///< the paper's SVD of the Bernstein collocation matrix, always
  Composition,  ///< exact Bernstein-product composition, always
};

struct LiftOptions {
  int max_degree = 20;                   ///< paper's cap on the collocation degree (§4)
  LiftMethod method = LiftMethod::Auto;  ///< see LiftMethod
  bool reduce = true;                    ///< run the lossless degree reduction
  /// Relative tolerance of the off-sample check of a lifted piece (times the patch's control net
  /// size) and of each degree reduction step (times max |P_i| of the homogeneous control points).
  /// Measured collocation error / model size on random surfaces: ~1e-14 at d3d = 12, 3e-12 at 20,
  /// 7e-10 at 30, 2e-8 at 42 (equally spaced Bernstein collocation is ill-conditioned); the exact
  /// composition stays near 1e-15 at every degree, so Auto falls back to it above the cap or when
  /// the check fails.
  double rel_tol = 1e-10;
  int check_samples = 16;  ///< off-sample parameters (plus both ends) of each check by lift_error
};

/// Parameters in (seg.range.min, seg.range.max), sorted, where the Bézier segment crosses one of the
/// lines u = u_lines[k] or v = v_lines[k] (odd-multiplicity roots of X - k W; touching roots are not
/// needed and may or may not be reported).
[[nodiscard]] std::vector<double> knot_line_crossings(const BezierSegment<2>& seg, const std::vector<double>& u_lines,
                                                      const std::vector<double>& v_lines);

/// Q(t) of the file comment by collocation at d3d + 1 equally spaced parameters, SVD solve (§4).
/// `piece` is a 2D Bézier curve (knots {a x (p+1), b x (p+1)}), `patch` its Bézier patch.
[[nodiscard]] HomogeneousCurve lift_by_collocation(const BezierPatch& patch, const Curve2& piece);

/// Q(t) exactly by Bernstein products: sum_ij C(du,i) C(dv,j) U0^i U1^(du-i) V0^j V1^(dv-j) P^w_ij.
[[nodiscard]] HomogeneousCurve lift_by_composition(const BezierPatch& patch, const Curve2& piece);

/// Repeated lossless degree reduction of a homogeneous Bézier curve (Farin, as in §4); stops at
/// degree 1 or when a step would move the curve by more than rel_tol * max |P_i| (4D).
[[nodiscard]] HomogeneousCurve reduce_degree_lossless(const HomogeneousCurve& bezier, double rel_tol);

/// Degree elevation by one of a homogeneous Bézier curve (Farin), used by the reduction check.
[[nodiscard]] HomogeneousCurve elevate_bezier(const HomogeneousCurve& bezier);

/// Point of a homogeneous Bézier curve at t in its knot range (de Casteljau, projected to 3D).
[[nodiscard]] glm::dvec3 bezier_point3(const HomogeneousCurve& bezier, double t);

/// The 2D point of a trim piece at t, clamped into the surface's domain.
[[nodiscard]] glm::dvec2 piece_uv(const Surface& surface, const Curve2& piece, double t);

/// Max over `samples` parameters that avoid the collocation nodes of |xyz(t) - S(uv(t))| (model
/// units): the check of a lifted piece against direct surface evaluation (tests, and §4's fallback).
[[nodiscard]] double lift_error(const Surface& surface, const TrimCurve3& piece, int samples = 64);

/// One trim curve (any NURBS Curve2 of the face) -> its pieces, in parameter order (steps 1-3).
/// `patches` = extract_bezier_patches(surface).
[[nodiscard]] std::vector<TrimCurve3> convert_trim_curve(const Surface& surface,
                                                         const std::vector<BezierPatch>& patches, const Curve2& curve,
                                                         const LiftOptions& opt = {});

/// The four boundary iso-curves of the surface's domain as degree-1 trim curves, counter-clockwise
/// from (u0, v0): the outer loop of a face without trim loops.
[[nodiscard]] TrimLoop domain_loop(const Surface& surface);

}  // namespace nurbs::tess
