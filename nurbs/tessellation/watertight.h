#pragma once
/// \file watertight.h
/// Beyond the paper: a watertight mesh across faces. Balázs, Guthe and Klein (WSCG 2004)
/// approximate each face's trim loops on their own (§5), so the two faces of a B-rep edge get
/// different polyline vertices along it and the merged mesh has cracks (up to eps) and open edges.
/// Three steps close them:
///   0. share_edge_polylines, between §5 and §6: where the file gives its topology, each B-rep
///      edge is meshed once, as BRepMesh does: the edge's second face takes the first's polyline
///      along it (same xyz bit for bit), so a closed shell meshes closed by construction;
///   1. share_boundary_vertices, between §5 and §6: every loop vertex of a face lying on a loop
///      segment of another face is inserted into that segment (same xyz bit for bit), or made
///      identical to the other loop's vertex it coincides with; both sides of an edge then carry
///      the same 3D vertices.
///   2. close_t_junctions, after §8 and the merge of the faces: vertices that the §6 trimming adds
///      on one side only (a cell line crossing a trim segment) still leave T-junctions; a boundary
///      triangle is split at every other-side vertex lying on its open edge.
#include <vector>

#include "nurbs/tessellation/tess_types.h"
#include "nurbs/triangle_mesh.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

/// Figures of the two steps (each function adds to them, so one object can collect both).
struct WatertightStats {
  int edge_shared = 0;    ///< loop vertices a face took from the other face of their B-rep edge
  int inserted = 0;       ///< loop vertices inserted into another face's loop segment
  int merged = 0;         ///< loop vertices made identical to a vertex of another face's loop
  int faces_touched = 0;  ///< faces whose loops changed
  int splits = 0;         ///< triangles split by close_t_junctions (one more triangle each)
  int collapsed = 0;      ///< triangles removed by close_t_junctions (two corners welded together)
  int filled = 0;         ///< sliver holes close_t_junctions closed (one triangle each)
  double fill_width = 0;  ///< the widest of them: its height over its longest edge
  double seconds = 0.0;   ///< wall time of the calls
};

/// Meshes each B-rep edge once. `loops[f]` as for share_boundary_vertices, with their edges
/// (LoopPolyline::edge); each loop is first turned so that its vertex 0 starts a run of one edge.
/// For every edge that runs along exactly two stretches of loops (two faces, or a periodic face's
/// seam twice), the stretch with more segments is the master; the other's vertices between its two
/// ends are replaced by the master's (xyz copied, in the order the other runs: the way along which
/// the points a third and two thirds along lie nearer). Each replaced vertex's uv on its own face is
/// where its chain holds the same share of its 3D length, improved by 4 Newton steps of
/// project_point while they stay in the band of that chord and keep the chain's order (else all
/// take the chain's points). The ends stay: share_boundary_vertices makes the corners one (master
/// vertices within `tolerance` of an end, or within a tenth of the edge's length on an edge shorter
/// than that, are not taken). A pair farther apart than twice (`tolerance` + both faces' edge
/// gaps) at their ends or a third or two thirds along is not taken, nor one whose taken points lie
/// farther than `tolerance` + both gaps from the face's surface at their uv (the move
/// share_boundary_vertices allows a boundary vertex). Returns the vertices replaced.
int share_edge_polylines(const std::vector<TrimmedSurface>& faces, std::vector<std::vector<LoopPolyline>>& loops,
                         double tolerance, WatertightStats* stats = nullptr);

/// Shares trim-loop vertices between faces. `loops[f]` are the closed polylines of face `faces[f]`
/// (world coordinates, xyz = S(uv) per vertex, as approximate_trim_loops returns them); changed in
/// place. `tolerance`: absolute 3D distance (the driver passes eps, the loop budget).
///
/// For each loop vertex p of face f and each face g, the nearest segment a-b of g's loops within
/// `tolerance` is taken, on each side of g's seam (segments whose (u, v) feet lie a whole domain
/// apart along one parameter at the same other one: the seam's two sides both take the vertex).
/// Where the loops carry B-rep edges (LoopPolyline::edge, from a B-rep file's 508 edge uses), a
/// segment of another edge than those of p's two segments is never taken: a sliver face narrower
/// than the tolerance (component8, the B-rep Ventilator) has two edges within it, whose vertices
/// distance alone would put on the wrong neighbour. Where the vertex and the
/// segment belong to the same B-rep edge, `tolerance` grows by both faces' edge gaps
/// (TrimmedSurface::edge_gap): the file's faces meet only that closely, and the edge is meshed once
/// all the same, so a shell the file states closed meshes closed. Unknown edges (-1: curves the
/// reader added to close gaps, files without topology) match by distance alone. Segments without
/// a known edge shorter than `tolerance` in 3D (degenerate edges at poles) are skipped; with one,
/// only degenerate ones (under 1e-6 of it): a small fillet's arc is still an edge its faces share.
/// Within the same face (g = f) only a segment whose foot is more than half the domain
/// away in u or v counts: that is the other side of a periodic face's seam (same 3D line, the
/// other end of the domain), never the vertex's own or neighbouring edges.
/// If p is within `tolerance` of a or b, the two vertices are merged: every vertex of such a group
/// takes the xyz of its member with the lowest (face, loop, index), so all sides hold the same
/// doubles (uv stays). Otherwise p is inserted into a-b, sorted by the foot parameter t of p on the
/// 3D segment, with xyz = p exactly (p's group's xyz when p was merged too) and uv from 4 Newton
/// steps of project_point started at lerp(uv_a, uv_b, t). Newton's uv is kept only when it stays
/// in the band of the uv chord (projection parameter in (0, 1), distance <= chord length / 4) and
/// the points inserted into one segment keep the order of t along the chord; otherwise the whole
/// segment's insertions take the lerp. Either way the new chain is a graph over the chord, so the
/// loop stays simple unless another part of it comes closer to the chord than that band.
/// S(uv) may differ from xyz by up to `tolerance`: the driver uses xyz for the mesh vertex.
/// Several insertions of one merged group into one segment count once.
/// Returns the number of inserted plus merged vertices. Throws std::invalid_argument when
/// loops.size() != faces.size().
int share_boundary_vertices(const std::vector<TrimmedSurface>& faces, std::vector<std::vector<LoopPolyline>>& loops,
                            double tolerance, WatertightStats* stats = nullptr);

/// Closes T-junctions of a merged mesh. Vertices within `weld_tolerance` are one point (grid
/// hashing); an edge used by one triangle is open. Triangles with two corners welded together are
/// removed first (they cover nothing, and their two other edges, being one edge counted twice,
/// would look closed and hide a junction on it). Each vertex of an open edge that lies on a face's
/// boundary edge a-b (one its own face's triangles use once: where bodies touch, an edge may be
/// used by more faces than two, and a junction on it is closed all the same; distance to the
/// segment <= weld_tolerance, farther than weld_tolerance from a and b) splits that edge's triangle
/// (a, b, c) into a fan (a, p1, c), (p1, p2, c), ..., (pk, b, c) with the points sorted along a-b;
/// a triangle with points on several edges is split edge after edge.
/// Each split point becomes a new vertex of the triangle's face: position copied bit for bit from
/// the point, uv, normal and color interpolated along a-b. Orientation, face ids and all existing
/// positions are kept. Returns the number of triangles added (one per split point).
/// Last, sliver holes: three open edges (each used once in the whole mesh) that close a triangle
/// no higher than `fill_width` over its longest edge, two of them on one face, are closed by that
/// triangle on that face (its corners are that face's vertices, orientation opposite the hole's
/// edges). Such a hole is a piece of a face the trimming lost beside a cell line that passes a
/// hair from a trim vertex; every point of the triangle lies within its height of an edge of the
/// mesh, so the mesh's bound grows by WatertightStats::fill_width.
int close_t_junctions(TriangleMesh& mesh, double weld_tolerance, WatertightStats* stats = nullptr,
                      double fill_width = 0.0);

}  // namespace nurbs::tess
