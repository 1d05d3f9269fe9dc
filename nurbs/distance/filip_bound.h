#pragma once
/// \file filip_bound.h
/// The Filip et al. deviation bound K of Krishnamurthy et al. §2.2, Eqs. (1)-(4): the distance,
/// coordinate by coordinate, between a C^1 surface and its piecewise linear interpolant on a uniform
/// (n+1) x (m+1) parameter grid. Used to grow grid-cell AABBs so they enclose the surface. Beside it,
/// a Euclidean K_e (KNorm::Euclidean, see "Euclidean form" below) bounds the distance itself, which
/// is what the paper's Theorems 1 and 2 need.
///
/// Units. M1, M2, M3 bound |d2x/du2| etc. with respect to the surface's own parameters (u, v), over
/// the whole domain [u0, u1] x [v0, v1]. For a grid of n x m cells the steps are h_u = (u1 - u0) / n,
/// h_v = (v1 - v0) / m, and
///     K = (1/8) (h_u^2 M1 + 2 h_u h_v M2 + h_v^2 M3),
/// which is Eq. (4) when the domain is the unit square (h_u = 1/n, h_v = 1/m).
///
/// Why it holds (Filip et al., the paper's ref. [28]; per coordinate f of S): for p in a grid triangle (or the bilinear
/// patch) with vertices v_i and barycentric weights l_i, Taylor's theorem with integral remainder
/// gives f(p) - L(p) = -1/2 sum l_i d_i^T H d_i with d_i = v_i - p, and sum l_i dx_i^2 <= h_u^2 / 4
/// (a variance of values in an interval of width h_u), sum l_i |dx_i dy_i| <= h_u h_v / 4 (Cauchy-
/// Schwarz). This needs f in C^1 with bounded piecewise-continuous second derivatives along segments
/// of the cell: a B-spline surface qualifies across knots of multiplicity < degree; across a knot
/// line where the surface is only C^0 it does not, which is why the bound is reported per cell and
/// is +infinity for cells that straddle a C^0 knot line (grids whose lines hit the knots are fine).
///
/// Second-derivative bounds (true upper bounds, per Bézier patch of the surface):
///  - Polynomial patch: S_uu is a Bézier patch with control net p(p-1)/du^2 (P_{i+2,j} - 2P_{i+1,j} +
///    P_{i,j}) (du = patch width in u), S_uv has net p q/(du dv) (4-point difference), S_vv likewise;
///    by the convex hull property each coordinate is bounded by the max |coordinate| of its net.
///  - Rational patch S = N / w, N = sum w_ij (P_ij - c) B_ij (translated by the centre c of the
///    control-point box, which changes no derivative), w = sum w_ij B_ij. Differentiating N = w S:
///      S_u  = (N_u - w_u S) / w
///      S_uu = (N_uu - 2 w_u S_u - w_uu S) / w
///      S_uv = (N_uv - w_u S_v - w_v S_u - w_uv S) / w
///      S_vv = (N_vv - 2 w_v S_v - w_vv S) / w
///    Per coordinate k, with |N_*^k| <= A_*^k and |w_*| <= W_* (max |.| of the difference nets of the
///    homogeneous numerator and of the weights, convex hull property), |S^k - c^k| <= R^k (half the
///    box extent: S lies in the convex hull of the P_ij since all w_ij > 0) and w >= w_min (smallest
///    patch weight, partition of unity):
///      |S_u^k|  <= D_u^k = (A_u^k + W_u R^k) / w_min                      (same for v)
///      |S_uu^k| <= (A_uu^k + 2 W_u D_u^k + W_uu R^k) / w_min
///      |S_uv^k| <= (A_uv^k + W_u D_v^k + W_v D_u^k + W_uv R^k) / w_min
///      |S_vv^k| <= (A_vv^k + 2 W_v D_v^k + W_vv R^k) / w_min
///    For weights all equal this reduces to the polynomial bound. Splitting the patches first
///    (`subdivisions`) tightens the rational bound (the nets converge to the derivatives).
///
/// Euclidean form. Eqs. (1)-(3) bound coordinates, so K bounds each coordinate of S - L, and the
/// vector S - L can be sqrt(3) K long (attained by S = (u, v, 0) + u (1 - u) (1, 1, 1) on one cell;
/// with the bulge along the normal, |d - d*| reaches sqrt(3) K too, see the tests). Theorem 1
/// (|d - d*| < K) and Theorem 2 (sqrt(4 K d + K^2)) take K as a bound on ||S - L||. The
/// argument above holds verbatim for the vector S: Taylor along p -> v_i with integral remainder,
///     L(p) - S(p) = sum l_i r_i,  r_i = int_0^1 (1 - t) (S_uu dx_i^2 + 2 S_uv dx_i dy_i + S_vv dy_i^2) dt,
/// (the first-order terms cancel since sum l_i d_i = 0), and ||int f|| <= int ||f|| with the triangle
/// inequality give ||r_i|| <= 1/2 (M1e dx_i^2 + 2 M2e |dx_i dy_i| + M3e dy_i^2) for M1e >= sup ||S_uu||,
/// M2e >= sup ||S_uv||, M3e >= sup ||S_vv|| (Euclidean norms); the same variance and Cauchy-Schwarz
/// steps then give ||S - L|| <= K_e = (1/8)(h_u^2 M1e + 2 h_u h_v M2e + h_v^2 M3e).
/// The M_e per patch: polynomial, the max over each difference net of the vector norm (the net's
/// convex hull holds the derivative, and the norm is convex); rational, the quotient-rule bound
/// above with norms (A_* = max norm over the homogeneous difference nets, R = max ||P_ij - c||,
/// D_u = (A_u + W_u R) / w_min, ...), capped by ||(M^x, M^y, M^z)||, the norm of the per-coordinate
/// bounds, which also bounds ||S_uu|| etc. and is smaller whenever the norm bound adds up vectors
/// that point along different axes.
/// How K and K_e compare. Pointwise max_k |x_k| <= ||x|| <= sqrt(3) max_k |x_k|, so for the exact
/// suprema M <= M_e <= sqrt(3) M. For the computed bounds:
///  - m*_norm >= m* always (each norm ingredient is >= the matching per-coordinate one; the code
///    also takes the max with m* so that rounding cannot break it);
///  - polynomial patches: m*_norm <= sqrt(3) m* (norm vs largest coordinate over the same nets);
///  - rational patches: the uncapped norm bound can exceed sqrt(3) m* (A_uu along x and W_uu R along y
///    give A_uu + W_uu R against max(A_uu, W_uu R); up to 1.89 m* seen on the random family of the
///    tests); the cap restores m*_norm <= sqrt(3) m*.
/// Maxima over sub-patches, patches and cells keep both inequalities, so K <= K_e <= sqrt(3) K for
/// every grid and cell (up to rounding of the sqrt(3) side). Note sqrt(3) K is itself a valid
/// Euclidean bound; K_e is never larger and is smaller where the curvature is not along (1, 1, 1).
#include <vector>

#include "nurbs/bezier_extraction.h"
#include "nurbs/knot_vector.h"
#include "nurbs/surface.h"

namespace nurbs {

/// Which deviation bound: the paper's per-coordinate K (Eqs. 1-4) or the Euclidean K_e that bounds
/// ||S - L|| (see "Euclidean form" in the file comment).
enum class KNorm { Component, Euclidean };

/// Bounds of Eqs. (1)-(3): max over a region and over x, y, z of |S_uu|, |S_uv|, |S_vv|; and the
/// Euclidean-norm bounds M1e-M3e of the same derivatives (m*_norm >= m*, see the file comment).
struct SecondDerivativeBounds {
  double m1 = 0.0;       ///< |d2/du2|, Eq. (1)
  double m2 = 0.0;       ///< |d2/dudv|, Eq. (2)
  double m3 = 0.0;       ///< |d2/dv2|, Eq. (3)
  double m1_norm = 0.0;  ///< ||S_uu||
  double m2_norm = 0.0;  ///< ||S_uv||
  double m3_norm = 0.0;  ///< ||S_vv||
};

/// Field-wise max of two sets of bounds (bounds of the union of their regions).
[[nodiscard]] SecondDerivativeBounds max_of(const SecondDerivativeBounds& a, const SecondDerivativeBounds& b);

/// Bounds of one Bézier patch (degree p x q, (p+1) x (q+1) points, u fastest) over the parameter
/// rectangle of width du x dv (see the file comment for the polynomial and rational formulas).
[[nodiscard]] SecondDerivativeBounds bezier_patch_bounds(const Surface& patch, double du, double dv);
/// The same for a patch read in place (patch (a, b) of a refined surface): no copy of its net.
/// `exact_form` false skips the exact-form bound of rational patches (the quotient rule's alone:
/// still a bound, larger, at a fraction of the cost; for a caller that needs only a bound below a
/// target and tries the cheap one first).
[[nodiscard]] SecondDerivativeBounds bezier_patch_bounds(const BezierNet& patch, double du, double dv,
                                                         bool exact_form = true);

/// Bounds of the first derivatives' norms ||S_u||, ||S_v|| over one Bézier patch of width du x dv.
/// Polynomial: the max norm over the difference nets p/du (P_{i+1,j} - P_ij) (convex hull). Rational:
/// the quotient rule of the file comment with norms, D_u = (A_u + W_u R) / w_min. With them S is
/// Lipschitz in (u, v): ||S(a) - S(b)|| <= sqrt(D_u^2 + D_v^2) ||a - b|| on the patch (Cauchy-Schwarz).
struct FirstDerivativeBounds {
  double su = 0.0, sv = 0.0;
  [[nodiscard]] double lipschitz() const;
};
[[nodiscard]] FirstDerivativeBounds first_derivative_bounds(const BezierNet& patch, double du, double dv);

/// When adaptive_patch_bounds stops splitting (see there).
struct AdaptiveRefinement {
  int max_pieces = 64;    ///< at most this many sub-patches per Bézier patch (8 x 8 if uniform)
  double min_gain = 0.8;  ///< stop when splitting the worst piece lowers its score by less than 20 %
};

/// Bounds of one Bézier patch, refined adaptively ("tight rational bounds"): the piece
/// whose bound is largest (score: K_e of one cell the size of the patch) is split 2 x 2 while that
/// lowers its score by at least 1 - min_gain and the piece budget lasts; the result is the field-wise
/// max over the pieces, a true bound over the whole patch since each piece's is over the piece. The
/// difference nets of the pieces converge to the derivatives (quadratically in the piece size), so
/// the quotient-rule bound of rational patches, loose on a whole patch, becomes tight.
[[nodiscard]] SecondDerivativeBounds adaptive_patch_bounds(const BezierPatch& patch, const AdaptiveRefinement& rule);

/// Bounds of a whole surface: per Bézier patch, their maximum, and where the surface is C^1.
struct FilipBound {
  Interval domain_u, domain_v;
  std::vector<double> breaks_u, breaks_v;  ///< distinct knots in the domain, ends included
  /// patches[b * (breaks_u.size() - 1) + a] bounds the knot rectangle [breaks_u[a], breaks_u[a+1]] x
  /// [breaks_v[b], breaks_v[b+1]].
  std::vector<SecondDerivativeBounds> patches;
  SecondDerivativeBounds whole;  ///< max over patches: M1, M2, M3 of Eqs. (1)-(3), and M1e-M3e
  /// c1_u[a] for interior break a (1 .. size-2): the surface is C^1 across the line u = breaks_u[a]
  /// (index 0 and the last are unused and true). Checked exactly where the knot multiplicity reaches
  /// the degree (elsewhere C^1 holds by the knot multiplicity), by comparing the one-sided first
  /// derivatives at 2q + 2 points along the line (relative tolerance 1e-9).
  std::vector<bool> c1_u, c1_v;
  [[nodiscard]] bool c1() const;
  [[nodiscard]] size_t spans_u() const { return breaks_u.size() - 1; }
  [[nodiscard]] size_t spans_v() const { return breaks_v.size() - 1; }
  [[nodiscard]] const SecondDerivativeBounds& patch(size_t a, size_t b) const { return patches[b * spans_u() + a]; }
};

/// Computes the bounds of a valid surface: Bézier extraction, then per patch either
/// subdivisions x subdivisions equal sub-patches (subdivisions > 0) or, by default (0), the adaptive
/// refinement of adaptive_patch_bounds. On the shared IGES models the adaptive bound is within a
/// factor 4 of the sampled second derivatives on every face (see nurbsgl info --bounds).
/// Cost O(patches x pieces x (p+1)(q+1)).
[[nodiscard]] FilipBound filip_bound(const Surface& s, int subdivisions = 0);

/// The same table with sampled values instead of bounds: each patch's M's are the maxima of
/// |S_uu|, ... over (samples + 1)^2 points of the patch (edges included), evaluated on the NURBS
/// surface in double. A lower estimate of the true suprema, so bound / sampled >= 1 measures how
/// loose the bound is. samples <= 0 picks max(degree) + 3 per direction.
[[nodiscard]] FilipBound sampled_bound(const Surface& s, const FilipBound& b, int samples = 0);

/// K = (1/8)(h_u^2 M1 + 2 h_u h_v M2 + h_v^2 M3) for grid steps h_u, h_v (Eq. 4 in step form);
/// with KNorm::Euclidean, K_e from m1_norm-m3_norm.
[[nodiscard]] double filip_k(const SecondDerivativeBounds& m, double h_u, double h_v, KNorm norm = KNorm::Component);

/// K for the n x m cell grid over the whole domain (Eq. 4) from the whole-surface M1-M3; when the
/// surface is not C^1 everywhere, the max of filip_k_cell over the cells (+infinity if a cell
/// straddles a C^0 knot line). `norm` picks K or K_e.
[[nodiscard]] double filip_k_grid(const FilipBound& b, int n, int m, KNorm norm = KNorm::Component);

/// K for cell (i, j) of the n x m grid (i along u): Eq. (4) with the M's maxed over only the patches
/// the cell overlaps, which is tighter than the whole-surface K; +infinity when a non-C^1 knot line
/// passes through the cell's interior. `norm` picks K or K_e.
[[nodiscard]] double filip_k_cell(const FilipBound& b, int n, int m, int i, int j, KNorm norm = KNorm::Component);

/// The patches (knot spans) that the open interval (lo, hi) overlaps along one direction, and
/// whether a break where the surface is not C^1 lies strictly inside it. Breaks within 1e-12 of the
/// domain width of lo or hi count as on the edge (a grid line is the knot up to rounding).
struct PatchRange {
  size_t first = 0, last = 0;
  bool kink = false;
};
[[nodiscard]] PatchRange patch_range(const std::vector<double>& breaks, const std::vector<bool>& c1, Interval t);

/// K of one cell [u0, u1] x [v0, v1] (any rectangle in the domain): Eq. (4) with the steps
/// u1 - u0, v1 - v0 and the M's maxed over the patches it overlaps; +infinity when a non-C^1 knot
/// line passes through its interior (within 1e-12 of the domain width of an edge counts as on it).
[[nodiscard]] double filip_k_rect(const FilipBound& b, Interval u, Interval v, KNorm norm = KNorm::Component);

/// Smallest uniform grid (n x m cells, minimum n * m) whose whole-surface K (or K_e, by `norm`) <= tolerance,
/// n and m in [1, max_cells]. Returns the grid and its K; if even max_cells x max_cells is too
/// coarse, returns that grid with its (larger) K.
struct GridChoice {
  int n = 1, m = 1;
  double k = 0.0;
};
[[nodiscard]] GridChoice choose_grid(const FilipBound& b, double tolerance, int max_cells = 4096,
                                     KNorm norm = KNorm::Component);

}  // namespace nurbs
