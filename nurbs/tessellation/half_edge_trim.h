#pragma once
/// \file half_edge_trim.h
/// §6 of Balázs, Guthe and Klein (WSCG 2004), after Kahlesz et al. [Kah02]: the leaves of the surface
/// subdivision and the trim polylines are merged into one directed graph of half-edges in the (u, v)
/// plane, which is then traversed to extract the material polygons (input of §7, triangulate.h).
#include <glm/vec2.hpp>
#include <vector>

#include "nurbs/tessellation/tess_types.h"

namespace nurbs::tess {

/// Counters of the trimming stage (for tests and reports).
struct TrimStats {
  int graph_vertices = 0;
  int graph_edges = 0;          ///< undirected edges after merging collinear overlaps
  int trim_edges = 0;           ///< edges carrying a trim polyline (net direction != 0)
  int paper_bridges = 0;        ///< §6 hole bridges from a cell's upper-left / lower-right corner
  int fallback_bridges = 0;     ///< bridges added after a traversal found a hole the §6 rule missed
  int traversal_rounds = 0;     ///< 1 unless fallback bridges were needed
  int inconsistent_edges = 0;   ///< directed edges met against their direction (bad loop orientation)
  int dropped_cycles = 0;       ///< zero-area or unresolved-hole cycles left out of the output
  int clipped_loops = 0;        ///< loops with a vertex outside R (clipped to R)
  int snapped_coordinates = 0;  ///< loop coordinates moved onto a cell line by the snapping tolerance
  int cut_cells = 0;            ///< cells cut under holes no bridge could join (step 7)
  int unresolved_holes = 0;     ///< holes left unjoined after the cuts (their area is not removed)
};

/// Material polygons of one face in (u, v). Vertices are shared between polygons (crack-free).
struct TrimmedPolygons {
  std::vector<glm::dvec2> vertices;
  std::vector<bool> on_trim;               ///< vertex lies on a trim polyline
  std::vector<std::vector<int>> polygons;  ///< counter-clockwise, simple, indices into `vertices`
  std::vector<bool> has_trim_edge;         ///< polygon has a trim or bridge edge: may be non-convex (§7)
  TrimStats stats;
};

/// Options of trim_cells.
struct TrimOptions {
  /// Snapping tolerance relative to max(width, height) of R: a loop coordinate this close to a cell
  /// line (or to R's boundary) is moved onto it, and a crossing point this close to a cell corner
  /// becomes that corner. 1e-12 is ~4500 ulps of a coordinate of size 1: far above the rounding of
  /// one segment/line intersection, far below any geometric feature of a tessellation.
  double snap_relative = 1e-12;
};

/// Builds the half-edge graph of §6 and traverses it. `cells` exactly tile R = their bounding box
/// (T-junctions allowed; shared coordinates bit-identical). `loops`: closed polylines (uv, outer);
/// outer loops counter-clockwise, holes clockwise. Material is what lies left of the loops: the
/// traversal starts on trim half-edges and floods across undirected cell edges, so a clockwise hole
/// with no loop around it leaves all of R around it material. No loop flagged outer at all means R's
/// boundary is the outer loop (untrimmed faces, faces with holes only).
///
/// Steps: (1) loop coordinates within the snapping tolerance of a cell line are moved onto it; (2) a
/// loop with a vertex outside R is clipped to R (Sutherland–Hodgman against R's four sides, which
/// keeps the winding number of every point of R; clipped points lie exactly on R's boundary); (3)
/// vertices: cell corners, loop vertices, crossings of loop segments with cell edges (a crossing
/// within the tolerance of a vertex on that line becomes that vertex); (4) edges: each cell side
/// split at every vertex on it (the paper's "rectangles with additional points inserted along the
/// edges"), each loop segment split at its crossings as directed half-edges; coincident pieces
/// (a loop running along a cell edge or along R's boundary) merge into one edge whose net trim count
/// gives its direction; (5) §6 hole bridges: a clockwise loop strictly inside one cell is joined to the
/// cell's upper-left and lower-right corners (nearest loop vertex that the corner sees, the bridge
/// crossing nothing: passing within the snapping tolerance of an edge or vertex counts as
/// crossing); (6) the traversal (half_edge_trim_graph.h); holes it finds unconnected (several holes
/// in a cell, corners cut off by another loop, a hole touching a cell edge) get two fallback
/// bridges and the traversal is repeated; (7) holes still unjoined after that (no vertex of the polygon
/// around them visible, e.g. a row of holes in one cell) have the cells under them cut at the middle
/// of their u range, and the graph is built again from step 1. Loops are assumed not to cross each
/// other or themselves (they may touch); areas are computed about a local origin so slivers keep
/// their sign.
[[nodiscard]] TrimmedPolygons trim_cells(const std::vector<Cell>& cells, const std::vector<LoopPolyline>& loops,
                                         const TrimOptions& options = {});

}  // namespace nurbs::tess
