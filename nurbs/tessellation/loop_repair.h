#pragma once
/// \file loop_repair.h
/// §5's crossing correction (Balázs, Guthe, Klein 2004): trim loops that cross in (u, v) (modelling
/// errors) get a vertex at each crossing, so that edges of the loops meet only at shared vertices.
/// Found by a sweep over u (Bentley-Ottmann style: edges sorted by their smallest u, an active list
/// pruned by largest u, a v-interval test before the exact segment test). A loop that crosses
/// itself (a polyline folded over where its curve runs close to another part of the loop, e.g. along
/// the domain's edge) is cut at its crossings into simple loops, and the thin lobes that turn
/// against it are dropped: their area lies within the polylines' error of the curves, and a folded
/// lobe left in would flip the material side of the half-edge flood (§6). A wide one inside the
/// rest is a hole the loop reaches through a slit. Splitting a self-touching loop into separate
/// loops is left to the half-edge stage, which handles shared vertices.
#include <vector>

#include "nurbs/surface.h"
#include "nurbs/tessellation/tess_types.h"

namespace nurbs::tess {

/// Inserts a vertex (uv at the crossing, xyz = S(uv)) into both edges at every proper crossing
/// (interiors cross, strictly opposite orientations) between two edges of `loops`, any loop with any
/// other or itself. Touching, collinear overlap and vertex-on-edge cases are not crossings. A loop
/// with a crossing of its own is then cut there (and where it passes a vertex twice) into simple
/// loops; those turning against the whole loop (the sign of its area) are dropped when no wider in
/// space than `fold_width` (twice their area over their length: the polylines' error), and kept as
/// loops of the other kind when wider (a hole the loop reaches through a slit). Returns the number
/// of crossings found.
size_t repair_crossings(std::vector<LoopPolyline>& loops, const Surface& surface, double fold_width);

/// Number of proper crossings among the edges of `loops` (the same sweep, nothing changed).
[[nodiscard]] size_t count_crossings(const std::vector<LoopPolyline>& loops);

}  // namespace nurbs::tess
