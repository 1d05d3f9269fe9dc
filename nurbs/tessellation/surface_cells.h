#pragma once
/// \file surface_cells.h
/// §5 "NURBS Surfaces" of Balázs, Guthe and Klein (WSCG 2004): the untrimmed surface is covered by
/// axis-aligned parameter cells, each flat enough that its two corner triangles stay within eps of
/// the surface. The paper's kd-tree (split at the parameter of the worst control point, across the
/// direction of Fig. 3) and the quadtree of [Kah02] (midpoint split in both directions) share one
/// error measure:
///   ε_bilin = max_ij |P_ij - S~(g_i, g_j)|,  twist = |P_00 - P_m0 - P_0n + P_mn|,
/// where S~ is the bilinear interpolant of the corner control points of the node's own (restricted,
/// clamped) net and g_i, g_j are its Greville abscissae normalised to [0, 1].
///
/// Why Greville and not the paper's i/m: a node may hold several knot spans (the whole surface at
/// the root; we do not pre-split at knots, so a plane is one cell). Linear precision of B-splines,
/// Σ_i N_i(u) g_i = u, makes S~ = Σ B_ij S~(g_i, g_j) for the bilinear S~, hence
///   S(u, v) - S~(u, v) = Σ B_ij (P_ij - S~(g_ij))  and  |S - S~| <= ε_bilin
/// (convex combination). For a Bézier node g_i = i/m, the paper's formula. A point of the cell's
/// triangle T over (a, b) differs from S~ by |twist| |ab - L(a, b)| <= twist/4 (L = the linear
/// interpolant of ab on the triangle), giving the paper's ε_conservative = ε_bilin + twist/4 for
/// the two corner triangles. For any triangle with vertices q_k inside the cell: Σλ_k S(q_k) minus
/// S(Σλ_k q_k) is <= 2 ε_bilin + twist · |cov_λ(a, b)| <= 2 ε_bilin + twist/4 (a, b in [0, 1] have
/// variance <= 1/4), the bound with bilinear_factor = 2.
///
/// Rational surfaces: S = Σ β_ij P_ij with β_ij = w_ij B_ij / Σ w B, and the identity above fails
/// (a rational line with equal-spaced collinear points is not parametrised linearly). With
/// σ(u, v) = Σ β_ij g_ij (in the cell, maps each cell edge onto itself, hence onto the cell):
///   |S(u, v) - S~(σ(u, v))| <= ε_bilin + twist · |cov_β(a, b)| <= ε_bilin + twist/4.
/// So the bound holds as a distance between point sets, not at equal parameters: every surface
/// point of the cell is within ε_bilin + twist/2 of T (at T(σ)), and every point T(a, b) is within
/// the same of S(u, v) for some (u, v) with σ(u, v) = (a, b) (σ is onto). For any triangle inside
/// the cell: 2 ε_bilin + 3 twist/4 (each vertex to S~(σ_k): ε + t/4; the triangle to S~ of the
/// mean σ: t/4; back to the surface: ε + t/4). proven_cell_bound() adds that rational extra term.
///
/// Beyond the paper (CellBound::Filip, the default): Filip's bound from the cell's own Bézier
/// pieces (nurbs/distance/filip_bound.h, Euclidean norms M1..M3 of S_uu, S_uv, S_vv over the cell, rational
/// or not), K_e = (M1 h_u² + 2 M2 h_u h_v + M3 h_v²) / 8 with h the cell's widths, holds for ANY
/// triangle with vertices on the surface inside the cell, at equal parameters: for x in the
/// triangle with barycentrics λ_k, S(x) - Σλ_k S(x_k) = -Σλ_k R_k with Taylor remainders
/// |R_k| <= Q(x_k - x) / 2, Q(d) = M1 d_u² + 2 M2 |d_u d_v| + M3 d_v² <= a d_u² + b d_v²
/// (a = M1 + M2 h_v/h_u, b = M3 + M2 h_u/h_v: 2|d_u d_v| <= (h_v/h_u) d_u² + (h_u/h_v) d_v²); in
/// the metric diag(a, b), Σλ_k |x_k - x|² <= R² for the radius R of any ball holding the triangle,
/// and the cell's circumscribed ball has R² = (a h_u² + b h_v²)/4: |S(x) - T(x)| <= (a h_u² +
/// b h_v²)/8 = K_e. It needs S in C¹ across the cell (a knot of multiplicity >= degree inside it
/// voids it: then +inf). The cell keeps the smaller of this and the control-net bound; Filip's is
/// computed only where the control-net test fails. It is 4/3 of the true error on a parabola where
/// the paper's any-triangle bound is 8/3 of it, so cells may be about twice as large.
#include <optional>
#include <vector>

#include "nurbs/surface.h"
#include "nurbs/tessellation/tess_types.h"

namespace nurbs::tess {

/// Options of subdivide_surface (§5).
struct CellOptions {
  double eps_surface = 1e-3;  ///< absolute error bound, model units
  SurfaceError error = SurfaceError::Conservative;
  Subdivision subdivision = Subdivision::KdTree;
  /// The parameter rectangle to cover; empty = the surface domain. The paper passes the bounding
  /// box of the trim loop polylines. Clipped to the surface domain.
  std::optional<Interval> domain_u, domain_v;
  /// 1: the paper's test ε_bilin + twist/4 <= eps (the cell's own two triangles). 2: the bound for
  /// any triangle with vertices inside the cell (trim and T-junction vertices, §6-7).
  double bilinear_factor = 1.0;
  /// Conservative only: the paper's control-net test, or also Filip's bound (file comment).
  CellBound bound = CellBound::Filip;
  /// kd-tree with CellBound::Filip: a polynomial node the control-net test cannot end is halved
  /// across the direction that lowers its Filip bound most; a rational node is halved across the
  /// paper's direction (Fig. 3). False: the paper's cut at the worst control point for both. (The
  /// Filip direction did worse on rational nodes: the Ventilator's B-rep faces 24081 triangles
  /// against 21275 with the paper's cut, and 21041 with the paper's direction at the middle.)
  bool filip_split = true;
  /// Nodes at this depth become leaves even when too coarse (counted in CellStats::unconverged).
  /// Depth grows by one per split (binary for the kd-tree, four-way for the quadtree). kd-tree
  /// splits at the worst point can be uneven (fractions down to 1/8): a sphere at eps = 1e-3 of its
  /// radius reaches depth ~24 with cells of 1/200 of the domain, hence the generous default.
  int max_depth = 40;
  /// Safety net against eps <= 0 or absurd inputs: once this many nodes were visited, the nodes
  /// still open become leaves (counted in CellStats::unconverged); the leaves still tile.
  int max_nodes = 1 << 22;
};

/// Figures for the paper's Table 3.
struct CellStats {
  int nodes = 0;        ///< nodes visited (leaves included)
  int leaves = 0;       ///< cells returned
  int max_depth = 0;    ///< deepest leaf
  int unconverged = 0;  ///< leaves left above eps by max_depth or max_nodes
  double seconds = 0.0;
  /// Multiplier of twist added to the paper's bound by proven_cell_bound for this surface
  /// (0 polynomial; rational: bilinear_factor / 4; see the file comment).
  double rational_extra = 0.0;
};

/// The guaranteed error of a leaf. any_triangle false: the distance between the cell's two corner
/// triangles and the surface over the cell, ε_bilin + twist/4 (+ twist/4 rational). any_triangle
/// true: for every triangle with vertices in the cell, 2 ε_bilin + twist/4 (+ twist/2 rational).
/// Polynomial: at equal parameters. Rational: a two-sided set distance (file comment). Either is
/// capped by the cell's Filip bound (cell.filip, any triangle, at equal parameters) when computed.
/// Only for cells from SurfaceError::Conservative.
[[nodiscard]] double proven_cell_bound(const Cell& cell, bool rational, bool any_triangle);

/// The leaves of the §5 subdivision of `s` over the rectangle of `opt`: they partition it exactly
/// (the union is the rectangle, children share their split coordinate bit for bit), in depth-first
/// order. Each carries ε_bilin and twist of its own net (Conservative) or of the surface points at
/// the Greville parameters (Approximate). A node is a leaf when
///   Conservative: bilinear_factor ε_bilin + twist (1/4 + rational_extra) <= eps (proven), or
///                 with CellBound::Filip the cell's Filip bound <= eps (proven, any triangle),
///   Approximate:  bilinear_factor ε_bilin + twist/4 <= eps (the paper's estimate).
/// kd-tree split: the control (or surface) point (k, l) farthest from S~, at (g_k, g_l), across the
/// direction whose splitting chord S(g_k, v0)..S(g_k, v1) or S(u0, g_l)..S(u1, g_l) lies nearer
/// to S(g_k, g_l) (Fig. 3); split fractions are kept in [1/8, 7/8] against slivers. Our addition:
/// a node whose twist term dominates (twist/4 >= bilinear_factor ε_bilin) or whose worst point is
/// a corner is halved across its longer side in space, which halves the twist.
[[nodiscard]] std::vector<Cell> subdivide_surface(const Surface& s, const CellOptions& opt, CellStats* stats = nullptr);

}  // namespace nurbs::tess
