#pragma once
/// \file tessellate.h
/// The whole pipeline of Balázs, Guthe and Klein (WSCG 2004) §3 for a model: per face, trim curves to
/// 3D Bézier curves (§4), trim loops to polylines (§5), the surface to kd-tree or quadtree cells (§5),
/// the cells cut by the loops in a half-edge graph (§6), the polygons triangulated (§7), the vertices
/// evaluated coherently (§8). Faces run in parallel; the output does not depend on the thread count.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "nurbs/tessellation/tess_types.h"
#include "nurbs/tessellation/trim_polyline.h"
#include "nurbs/triangle_mesh.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

/// Guaranteed: the trim loops within loop_share x eps (default 0.45; §5, γ of it for the curves), the
/// cells' proven bound for any triangle inside them (2 ε_bilin + twist/4, or Filip's, surface_cells.h)
/// within the rest, so that trimmed and T-junction triangles keep the bound too. Approximate: the
/// paper's approximate error, eps for the loops and eps for the surface (fewer triangles, no guarantee).
enum class TessMode { Guaranteed, Approximate };

/// Smallest eps relative to the model size that a tessellation is asked for: the triangle count grows
/// as 1/eps on curved faces (the generated sphere: 0.12 million triangles at 1e-4, 1.05 million at
/// 1e-5, 4.2 million and 1.4 GB at 1e-6), so a smaller eps asks for work that cannot fit.
inline constexpr double kMinRelativeEps = 1e-6;

struct TessellateOptions {
  double eps = 1e-3;  ///< absolute, model units
  TessMode mode = TessMode::Guaranteed;
  Subdivision subdivision = Subdivision::KdTree;
  CellBound cell_bound = CellBound::Filip;  ///< guaranteed mode: the cells' proven bound (surface_cells.h)
  CurveSplit split = CurveSplit::Midpoint;
  double gamma = 0.75;  ///< §5: share of the loop budget for the curves, the rest for simplification
  /// Guaranteed mode: share of eps for the trim loops, the rest (1 - loop_share) for the cells.
  /// 0.45: loops measure well under their bound, cells near theirs, so the cells get a little more
  /// (the trimmed 100x105: 10620 triangles at 1/2, 8032 at 0.45, same measured deviation 0.45 eps).
  double loop_share = 0.45;
  bool simplify = true;  ///< §5 loop simplification
  /// Beyond the paper (trim_thinning.h): dense polyline trim curves thinned in (u, v) before §4,
  /// within a quarter of the simplification's share of the loop budget; false lifts every segment.
  bool thin_polylines = true;
  /// §8: evaluate the vertices coherently (basis functions and inner sums reused between vertices
  /// sharing v or a u span: the paper's Table 3 "time³" column); false: plain direct evaluation of
  /// Eq. 1 per vertex (the "time" column). The same mesh either way, up to roundoff.
  bool coherent_evaluation = true;
  int threads = 0;       ///< 0 = all hardware threads
  /// Beyond the paper: faces sharing an edge in space get the same boundary vertices (the loops are
  /// matched across faces, the trimming's crossing points put on the loops' 3D chords and T-junctions
  /// split), so the mesh has no cracks and a closed model no open edges (watertight.h).
  bool watertight = false;
  /// Beyond the paper (rectangle_face.h): a face bounded by its own parameter rectangle gets no loop
  /// polyline; its cells' outer edges are its boundary. Not in watertight mode (the neighbours'
  /// shared boundary vertices would not lie on those edges).
  bool rectangle_faces = true;
  /// Vertices closer than this are one point (open-edge count, watertight T-junctions); the result's
  /// weld_tolerance is the larger of this and 1e-9 x the largest face's control box. The CLI passes
  /// the file's stated resolution (Model::resolution), capped at eps / 10.
  double weld = 0.0;
  /// Beyond the paper: the most §5 cells (about two triangles each) the whole model may need; 0 for
  /// no limit. Estimated before any face is subdivided, from the faces' cells at 256 and 64 times eps
  /// (cells grow as 1/eps on doubly curved faces, 1/sqrt(eps) on singly curved ones: the two
  /// passes tell which, for 2 % of the work); above the limit tessellate throws WorkLimitError.
  /// 2^21 cells: some 4 million triangles, a minute and 1.5 GB (the generated sphere at 1e-6 of its
  /// size needs more: it ran 90 s into the per-face node limit and a mesh 4.2 off its surface).
  long long max_cells = 1LL << 21;
  /// §5's safety net per face (CellOptions::max_nodes): the nodes one face's subdivision may visit.
  int max_face_nodes = 1 << 22;
};

/// Thrown by tessellate, before the work, when the cells eps asks for exceed max_cells.
struct WorkLimitError : std::runtime_error {
  WorkLimitError(const std::string& what, long long estimate, double least_eps)
      : std::runtime_error(what), estimated_cells(estimate), least_eps(least_eps) {}
  long long estimated_cells;  ///< the estimate that exceeded the limit
  double least_eps;           ///< about the smallest eps whose estimate fits the limit
};

/// Figures of the paper's Tables 2-4 for one run (seconds are summed over faces, i.e. CPU time of
/// the stages; `seconds` is the wall time).
struct TessellateStats {
  int faces = 0, failed_faces = 0;
  TrimApproxStats trim;       ///< §4-§5 loops (conversion and approximation seconds inside)
  long long cells = 0;        ///< §5 leaves
  long long cell_nodes = 0;   ///< §5 nodes visited
  int unconverged_cells = 0;  ///< leaves cut by the depth limit above their budget
  long long trim_edges = 0;   ///< loop polyline edges after simplification
  long long triangles = 0, vertices = 0;
  long long degenerate_triangles = 0;  ///< zero-area triangles in (u, v) the triangulation could not avoid
  long long collapsed_triangles = 0;   ///< zero-area in space (at poles, corners within the weld), dropped
  long long flipped_slivers = 0;       ///< flat in space (collinear corners), flipped with a neighbour
  int edge_shared = 0;                 ///< watertight: loop vertices a face took from its B-rep edge's other face
  int shared_vertices = 0;             ///< watertight: loop vertices inserted or merged across faces
  int t_junction_splits = 0;           ///< watertight: triangles split at other faces' boundary vertices
  int sliver_holes = 0;                ///< watertight: sliver holes closed (watertight.h, close_t_junctions)
  double seconds_surface = 0.0, seconds_trimming = 0.0, seconds_triangulation = 0.0, seconds_evaluation = 0.0;
  double seconds = 0.0;
};

struct FaceFailure {
  int face = -1;       ///< index in the input
  std::string reason;  ///< what went wrong, for the user
};

struct TessellateResult {
  TriangleMesh mesh;  ///< positions, normals, uv, vertex_face, triangles, triangle_face
  TessellateStats stats;
  std::vector<FaceFailure> failures;  ///< faces that produced no triangles, with the reason
  /// Vertices this close are one point: TessellateOptions::weld or 1e-9 x the largest face's
  /// control-box diagonal, the larger (watertight mode closes T-junctions within it; count open
  /// edges with it too).
  double weld_tolerance = 0.0;
  /// Watertight: the widest sliver hole closed (close_t_junctions); the mesh lies that much farther
  /// from the faces than eps at most.
  double fill_width = 0.0;
};

/// Tessellates `faces` (world coordinates, e.g. world_faces(model)). Each face's triangles are
/// counter-clockwise seen from its outside (Su x Sv, flipped for reversed faces). A face that throws
/// or yields no triangles is reported in `failures`; the others still come out. So is, in guaranteed
/// mode, a face whose subdivision stopped at the node limit with cells above eps (its triangles
/// are kept, but its bound does not hold). `progress` (optional) is called with (faces done, total)
/// from worker threads, serialised. Throws WorkLimitError when options.max_cells is exceeded.
[[nodiscard]] TessellateResult tessellate(const std::vector<TrimmedSurface>& faces, const TessellateOptions& options,
                                          const std::function<void(int, int)>& progress = {});

}  // namespace nurbs::tess
