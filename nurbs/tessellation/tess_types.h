#pragma once
/// \file tess_types.h
/// The data passed between the stages of the trimmed NURBS tessellation of Balázs, Guthe and Klein
/// (WSCG 2004; ../shared/papers/balazs-trimmed-nurbs-tessellation.txt). One face goes through:
///   §4 trim curves -> 3D Bézier curves (trim_bezier3d.h)      -> TrimCurve3
///   §5 trim loops  -> polylines within gamma * eps (trim_polyline.h) -> LoopPolyline
///   §5 surface     -> kd-tree (or quadtree) cells within (1 - ...) eps (surface_cells.h) -> Cell
///   §6 cells + loops -> half-edge graph -> material polygons (half_edge_trim.h)
///   §7 polygons    -> triangles in (u, v) (triangulate.h)
///   §8 (u, v)      -> surface points, coherent evaluation (coherent_eval.h) -> FaceMesh
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <vector>

#include "nurbs/knot_vector.h"

namespace nurbs::tess {

/// How the surface error of a cell is measured (§5 "NURBS Surfaces").
enum class SurfaceError {
  Conservative,  ///< control points vs the bilinear approximation, plus the twist term: guaranteed
  Approximate,   ///< surface points at the control points' parameters instead: fewer triangles
};
/// How the surface domain is subdivided (§5): the paper's kd-tree, or the quadtree of [Kah02]; or,
/// beyond the paper, the knot-aligned tensor grid of Krishnamurthy et al. §2.2 whose every cell's
/// Filip bound K_e meets the cells' share of eps (nurbs/distance/certified_grid.h): chosen per face
/// in one pass with no recursion, so several times faster than the kd-tree on B-rep faces at small
/// eps, for somewhat more cells. K_e holds for any triangle inside the cell (surface_cells.h), so
/// the guarantee is the kd-tree's.
enum class Subdivision { KdTree, Quadtree, Grid };
/// The proven bound of a Conservative cell (beyond the paper: the paper's control-net test alone,
/// or also Filip's bound from the cell's second-derivative hull, the smaller of the two kept).
enum class CellBound {
  ControlNet,  ///< §5: bilinear_factor ε_bilin + twist/4 (+ the rational term)
  Filip,       ///< min(that, K_e of the cell: (M1 h_u² + 2 M2 h_u h_v + M3 h_v²) / 8, any triangle)
};
/// How a trim curve that is not flat enough is split (§5 "Trimming Loops").
enum class CurveSplit { Midpoint, Arbitrary };

/// A trim loop of one face approximated by a closed polyline (last point joins the first, not repeated).
/// uv[i] is in the face's parameter plane; xyz[i] = S(uv[i]) exactly (a point of the 3D trim curve).
/// Orientation as in trimmed_surface.h: outer loops counter-clockwise, holes clockwise.
struct LoopPolyline {
  std::vector<glm::dvec2> uv;
  std::vector<glm::dvec3> xyz;
  bool outer = true;
  /// Per vertex i, the B-rep edge (Curve::edge, -1 none) of the segment from vertex i to i + 1; empty
  /// when not recorded (TrimApproxOptions::edges). The watertight step matches vertices only with
  /// segments of their own edges (watertight.h).
  std::vector<int> edge;
};

/// A leaf of the surface subdivision: an axis-aligned rectangle of the parameter plane with the two
/// terms of §5's error: `bilinear` = ε_bilin (control points, or surface points in Approximate mode,
/// against the bilinear approximation S~) and `twist` = |P00 - Pm0 - P0n + Pmn|. The paper's
/// ε_conservative = bilinear + twist / 4 bounds the cell's own two triangles; a triangle with other
/// vertices inside the cell (trim points, T-junction points) is within 2 * bilinear + twist / 4 of
/// the surface over it (polynomial patches; see surface_cells.h for rational ones).
struct Cell {
  Interval u, v;
  double bilinear = 0.0;
  double twist = 0.0;
  /// CellBound::Filip: the cell's Filip bound K_e (surface_cells.h), +inf when not computed (the
  /// control-net test sufficed, another mode) or not valid (a C0 knot line crosses the cell).
  double filip = std::numeric_limits<double>::infinity();
  [[nodiscard]] double error() const { return bilinear + 0.25 * twist; }
};

/// Triangles of one face. Vertices carry (u, v), the surface point and the unit surface normal
/// (oriented like Su x Sv, flipped when the face is reversed). Triangles are counter-clockwise seen
/// from the normal side. `trim_vertex[i]` is true for vertices that lie on a trim polyline.
struct FaceMesh {
  std::vector<glm::dvec2> uv;
  std::vector<glm::dvec3> position;
  std::vector<glm::dvec3> normal;
  std::vector<bool> trim_vertex;
  std::vector<glm::ivec3> triangles;
};

}  // namespace nurbs::tess
