#pragma once
/// \file trim_loops.h
/// Trim loop hygiene, as CAD readers need it: report loops that do not close or that cross (naming
/// the face), close small gaps, and orient loops (outer counter-clockwise, inner clockwise, so the
/// material is on the left; the convention of trimmed_surface.h and of IGES 141/142).
#include <string>
#include <vector>

#include "nurbs/trim_classify.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs {

/// Everything wrong with a face's loops, empty when fine. Each message starts "face <face_id>:".
/// Reports: invalid curves (validate()), empty loops, gaps > gap_tolerance between the end of a
/// curve and the start of the next (and last -> first), and crossings: any two non-adjacent edges
/// of the flattened loops (flatten_trim with flatten_tolerance) that intersect or touch, within a
/// loop ("crosses itself") or between loops ("loops a and b cross"), with the (u, v) where. The
/// crossing search stops after 3e7 candidate edge pairs (loops lying on top of each other) or 1000
/// crossing loop pairs, with a message saying so, which bounds its time and output whatever the input.
[[nodiscard]] std::vector<std::string> check_trim_loops(const TrimmedSurface& face, double gap_tolerance,
                                                        double flatten_tolerance);
/// The same with the loops already flattened (flatten_trim of this face, whose curves are valid),
/// for callers that also orient the loops: one flattening serves both. With `touch_tolerance` (model
/// units, > 0), these meetings are touches, as OpenCASCADE's BRepCheck holds them, not crossings:
/// a loop meeting itself where the part of it between the two passes spans at most
/// `touch_tolerance` in space (a loop through a surface's pole, a pcurve running out and back along
/// a degenerate side, curve ends a hair apart); any meeting with a loop that encloses no area (a
/// pcurve retracing itself); a meeting within `touch_tolerance` of a vertex (curve end) that both
/// loops pass through, or that the loop passes twice (a hole whose vertex lies on the outline); and
/// two loops whose vertices on the wrong side of each other lie within `touch_tolerance` of it (a
/// hole tangent to the outline, the fits crossing in a thin lens). `touch_size`, when given, gets
/// the largest span, distance from the vertex or lens width of a touch taken: the face's boundary
/// is known only that closely there.
[[nodiscard]] std::vector<std::string> check_trim_loops(const TrimmedSurface& face, double gap_tolerance,
                                                        const TrimPolygons& polygons, double touch_tolerance = 0.0,
                                                        double* touch_size = nullptr);

/// The closed polygon encloses no area: it retraces itself (its area below 1e-9 of its box's), or
/// has fewer than 3 vertices. Such a loop bounds nothing (check_trim_loops' touches).
[[nodiscard]] bool encloses_nothing(const std::vector<glm::dvec2>& polygon);

/// Closes gaps of size in (min_gap, tolerance] between consecutive curves of each loop by moving the
/// end of the earlier curve onto the start of the next (its last control point, after clamping the
/// curve if it was unclamped). Returns the number of gaps closed; larger gaps are left for the
/// checker, and gaps <= min_gap (rounding of joined end points) are left untouched and uncounted.
int repair_trim_gaps(TrimmedSurface& face, double tolerance, double min_gap = 0.0);

/// Chains the curves of each loop end to start again where the file lists them out of order or
/// with some reversed (an edge used against its direction, as B-rep files record in a flag a writer
/// may drop): a loop with a gap over `tolerance` between consecutive curves is rebuilt from its
/// first curve, each next curve the remaining one whose start or end (then reversed) lies nearest
/// the chain's end. Kept only when every joint and the closing one are then within `tolerance`;
/// otherwise the loop is left for the checker. Returns the number of loops rebuilt.
int reorder_trim_curves(TrimmedSurface& face, double tolerance);

/// Where the one loop a face declares outer lies inside another of its loops, and that loop holds
/// every other loop too (most of each polygon's vertices within it: loops may touch), that loop is
/// made the outer one and the declared one a hole: a file that names the wrong loop outer (an IGES
/// 144 whose PTO is one of the holes) bounds the same region as OpenCASCADE's fixed face. `polys`:
/// flatten_trim of the face, its outer flags changed alike. Returns 1 when the roles changed, else 0.
int fix_outer_loop(TrimmedSurface& face, TrimPolygons& polys);

/// Reverses loops whose flattened signed area has the wrong sign for their role (outer must be > 0,
/// inner < 0): curve order reversed and each curve reparametrised backwards. Returns how many loops
/// were reversed.
int orient_trim_loops(TrimmedSurface& face, double flatten_tolerance);
/// The same with the loops already flattened (flatten_trim of this face as it is now).
int orient_trim_loops(TrimmedSurface& face, const TrimPolygons& polygons);

}  // namespace nurbs
