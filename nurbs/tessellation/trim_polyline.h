#pragma once
/// \file trim_polyline.h
/// §5 "Trimming Loops" of Balázs, Guthe, Klein (WSCG 2004): the 3D trim curves of a face (§4,
/// trim_bezier3d.h) approximated by closed polylines whose 3D Hausdorff distance to the curves is at
/// most eps: gamma * eps for the subdivision of each 3D Bézier piece (ε_line bound), (1 - gamma) * eps
/// for the line simplification of each loop (less the share of the thinning of polyline trim curves
/// before §4, trim_thinning.h, where there are such curves); then the crossing correction (loop_repair.h).
///
/// ε_line (two-sided Hausdorff distance between a Bézier curve and its chord P_0 P_n). Let
/// e_i = P_i - (P_0 + λ_i (P_n - P_0)) with λ_i the clamped projection parameter of the paper, so
/// e_0 = e_n = 0. With μ(t) = sum_i B_i(t) λ_i in [0, 1], C(t) - (P_0 + μ(t)(P_n - P_0)) = sum_i B_i(t) e_i,
/// so |C(t) - chord point| <= (1 - (1-t)^n - t^n) max |e_i| <= (1 - 2^(1-n)) max |e_i| for a polynomial
/// curve of degree n (the paper's factor 1 - 1/2^(n-2) with n counting control points). μ runs
/// continuously from 0 to 1, so every chord point is such a partner too: the bound is two-sided.
/// For a rational curve the same argument holds on the projected control points P_i = P^w_i / w_i
/// with the rational basis w_i B_i / sum w_j B_j (positive weights: a partition of unity), but its
/// end functions can be arbitrarily small, so the factor is dropped (bound = max |e_i|). Beyond the
/// paper, a rational quadratic (every circle and conic edge of a CAD model) gets its exact value:
/// in standard form (w = w_1 / sqrt(w_0 w_2)) its farthest point from the chord's line is the
/// shoulder point, w / (1 + w) of the way from the chord's midpoint to P_1, so the distance is
/// w / (1 + w) h with h the distance of P_1 from the line (a circle arc: 1/2 and less, where the hull
/// bound gave h). It is the two-sided distance to the chord segment when P_1 projects inside it (the
/// curve, in the triangle P_0 P_1 P_2, then projects inside too, and covers the whole chord).
/// Vertices are exact curve points: uv = c(t) from the 2D piece (clamped into the domain),
/// xyz = S(uv); they differ from the lifted 3D curve by its lift error (checked <= LiftOptions::rel_tol
/// times the patch size, measured <= 4e-9 mm on the shared models).
#include <optional>
#include <vector>

#include "nurbs/tessellation/tess_types.h"
#include "nurbs/tessellation/trim_bezier3d.h"

namespace nurbs::tess {

/// Times approximate_trim_loops approximates a face's loops again at a quarter of the tolerance
/// while that removes crossings of the polylines (down to eps / 256).
inline constexpr int kCrossingRefinements = 4;

struct TrimApproxOptions {
  double eps = 0.1;     ///< absolute 3D tolerance of the loops, model units
  double gamma = 0.75;  ///< share of eps for the curve subdivision; the rest for the simplification
  CurveSplit split = CurveSplit::Midpoint;
  bool simplify = true;  ///< run the loop simplification with (1 - gamma) eps (less the thinning's share)
  /// Beyond the paper (trim_thinning.h): dense degree-1 trim curves are thinned in (u, v) before §4
  /// within `thinning` x (1 - gamma) x eps in space, taken from the simplification's share; 0 lifts
  /// every segment as the paper does.
  double thinning = 0.25;
  bool repair = true;    ///< run the crossing correction (loop_repair.h)
  int max_degree = 20;   ///< highest lifted degree solved by collocation (§4); above: exact composition
  LiftMethod lift = LiftMethod::Auto;
  /// Beyond the paper (rectangle_face.h): the polyline to use for the face's outer loop instead of
  /// approximating it (its parameter rectangle's corners); holes are approximated as usual.
  std::optional<LoopPolyline> outer_polyline;
  /// Beyond the paper (watertight.h): record each segment's B-rep edge in LoopPolyline::edge, and
  /// keep the vertices where the edge changes (the B-rep vertices) through the simplification.
  bool edges = false;
};

/// Figures of the paper's Table 2. approximate_trim_loops adds to them (sums; maxima for the max fields),
/// so one object can collect a whole model.
struct TrimApproxStats {
  size_t faces = 0;
  size_t curve_pieces = 0;      ///< 3D Bézier pieces after the knot-line cuts
  size_t composed_pieces = 0;   ///< pieces lifted by exact composition (degree cap or failed check)
  int lifted_degree_max = 0;    ///< max d2d (du + dv)
  int reduced_degree_max = 0;   ///< max degree after the lossless reduction
  double lift_error_max = 0.0;  ///< max measured |lifted - S(c(t))|, model units
  size_t edges_before = 0;      ///< polyline edges after the subdivision
  size_t edges_after = 0;       ///< after simplification and crossing correction
  size_t crossings_fixed = 0;
  /// Faces whose loops were approximated again at a finer eps because their polylines crossed where
  /// their curves do not (approximate_trim_loops)
  size_t crossing_refined_faces = 0;
  size_t thinned_points = 0;           ///< points of polyline trim curves dropped before §4 (trim_thinning.h)
  size_t rectangle_faces = 0;          ///< faces whose outer loop is their parameter rectangle (outer_polyline)
  double seconds_conversion = 0.0;     ///< §4
  double seconds_approximation = 0.0;  ///< §5 (subdivision, simplification, repair)
};

/// a += b: sums, maxima for the max fields (several faces' figures into one).
void add(TrimApproxStats& a, const TrimApproxStats& b);

/// ε_line of a homogeneous 3D Bézier curve (file comment); `farthest` receives the index i of the
/// largest |e_i| (the paper's arbitrary split point i / n).
[[nodiscard]] double line_error_bound(const HomogeneousCurve& bezier, int* farthest = nullptr);

/// Recursive subdivision of one piece until ε_line <= tol (midpoint, or at i / n of the farthest
/// control point). Appends the polyline's vertices except the piece's end point.
void approximate_piece(const Surface& surface, const TrimCurve3& piece, double tol, CurveSplit split,
                       std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& xyz);

/// Douglas-Peucker on a closed loop keeping a subset of its vertices. A chain v_a..v_b is replaced
/// by the edge v_a v_b only when every inner vertex is within `tol` of the SEGMENT v_a v_b in 3D and
/// within `tol_uv` of the uv segment. Two-sided Hausdorff <= tol for each replaced chain: chain ->
/// segment because the segment is convex and each chain edge joins two points within tol of it;
/// segment -> chain because the chain's projection parameter runs continuously from 0 to 1, so each
/// segment point is the foot of some chain point, which is within tol of its foot. The uv test
/// only keeps more vertices (it protects the uv shape where S degenerates, e.g. at a pole).
/// Where loop.edge is given, the vertices at which it changes are kept too (each kept chain then
/// lies along one edge, whose number the kept edge carries). Returns the number of vertices removed.
size_t simplify_loop(LoopPolyline& loop, double tol, double tol_uv);

/// The loops approximate_trim_loops approximates, in its output order: the face's loops, then the
/// domain rectangle (domain_loop, counter-clockwise, outer) when none of them is an outer loop (no
/// loops = untrimmed face; only holes = holes in the whole domain).
[[nodiscard]] std::vector<TrimLoop> loops_to_approximate(const TrimmedSurface& face);

/// Main entry (§4 + §5): loops_to_approximate(face) as closed polylines within opt.eps of the 3D
/// trim curves S(c(t)). Not covered by that bound: curves of a loop that join with gaps keep them as
/// straight edges, and vertices inserted at crossings (input errors) are S(uv) of the crossing.
/// Polylines that cross where their curves do not (loops closer than the chord error) are
/// approximated again at eps / 4, up to kCrossingRefinements times, while that removes crossings.
[[nodiscard]] std::vector<LoopPolyline> approximate_trim_loops(const TrimmedSurface& face, const TrimApproxOptions& opt,
                                                               TrimApproxStats* stats = nullptr);

}  // namespace nurbs::tess
