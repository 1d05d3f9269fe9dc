#pragma once
/// \file rectangle_face.h
/// Beyond the paper: faces bounded by their own parameter rectangle. When a face's outer loop
/// (loops_to_approximate: an untrimmed face's domain loop, or a B-rep face whose edges are the
/// iso-curves of its parameter rectangle) runs once around a rectangle R along its four sides, §5's
/// cells tile R exactly and their outer edges ARE the face's outer boundary. That boundary then needs
/// no polyline of its own: every triangle lies in one cell and every point of S(R) lies in one cell,
/// so away from the holes the mesh and the face are within the cells' proven bound of each other
/// (surface_cells.h), with no loop error to add. The paper approximates such a loop like any
/// other: 3D chords of the boundary curves, whose vertices then cut the boundary cells (more
/// triangles for the same measured deviation: the hammer 5,768 against 5,010, the lens 5,403
/// against 5,023). The cells keep the budget of the other faces' cells, (1 - loop_share) eps: given
/// all of eps, the bearing needs 8,922 triangles instead of 13,880, but its measured deviation then
/// sits on those faces alone (0.88 of eps against 0.40), and at equal measured deviation
/// OpenCASCADE needs fewer triangles on 5 of 8 models (component8: 1,052 against our 3,360).
#include <optional>

#include "nurbs/tessellation/tess_types.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

struct ParamRect {
  glm::dvec2 lo, hi;
};

/// R when the outer loop of loops_to_approximate(face) (the only loop flagged outer; holes may
/// follow) has curves that each lie on one side of the loop's bounding box (every control point
/// within 1e-12 of its larger side, the coordinate along the side monotone in the control points, so
/// the curve traces the segment between its ends), joined end to start, enclosing the box's area once
/// counter-clockwise (shoelace over the curve ends). R is that box clipped to the surface domain.
/// nullopt otherwise (a curved or interior outer edge, several outer loops). Holes keep their loop
/// polylines and their share of eps (tessellate.h).
[[nodiscard]] std::optional<ParamRect> boundary_rectangle(const TrimmedSurface& face);

/// R as a loop polyline: its four corners counter-clockwise, xyz = S(corner).
[[nodiscard]] LoopPolyline rectangle_polyline(const Surface& surface, const ParamRect& r);

}  // namespace nurbs::tess
