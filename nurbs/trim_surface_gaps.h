#pragma once
/// \file trim_surface_gaps.h
/// Gaps of trim loops judged where they matter: on the surface, in model space. A gap between the end
/// of one trim curve and the start of the next is harmless when both ends are (nearly) the same point
/// of the surface: at a pole or a collapsed side (a whole row of control points in one place, the
/// apex of a cone, the pole of a sphere written as NURBS), or where the file's 3D edges meet within
/// its precision but their parameter curves were fitted apart (OpenCASCADE's faces-mode output of
/// the Ventilator: planar faces whose pcurves stop 0.014 and 0.024 mm short of each other, 1.2e-4
/// and 2e-4 of the model size). OpenCASCADE closes such gaps through its edge and vertex tolerances
/// (ShapeFix_Wire: FixConnected, FixDegenerated, FixLacking; read.maxprecision.val caps them at one
/// file unit); here the gap is closed in (u, v) by a straight segment whose image on the surface is
/// checked to stay within the 3D tolerance, so the loop's material side never changes.
#include <vector>

#include "nurbs/model.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs {

/// Gaps whose ends are at most this fraction of the model size apart in model space are closed by
/// close_gaps_on_surface (the IGES reader's choice: 1e-3 x 118 mm = 0.12 mm on the Ventilator, well
/// below OpenCASCADE's cap of 1 mm and above its 0.024 mm gaps).
inline constexpr double kTrimGap3d = 1e-3;

/// For each loop of `face`, each gap between consecutive curves (and last -> first) larger than
/// `min_gap` in (u, v) whose straight (u, v) segment stays on the surface within `tolerance_3d` of
/// the gap's first end (sampled at 16 points; model-space units): the segment, a degree-1 Curve2,
/// is inserted into the loop. Returns how many segments were added. Gaps whose image is longer are
/// left to check_trim_loops (e.g. a jump across the seam of a closed surface).
int close_gaps_on_surface(TrimmedSurface& face, double tolerance_3d, double min_gap);

/// What is still open after close_gaps_on_surface, where OpenCASCADE's healing would close it (its
/// read.maxprecision.val allows a whole file unit), up to `cap_3d` in space: a curve that runs on
/// past its neighbour's end is cut there (the overshoot of close_gaps_on_surface); then each gap
/// larger than `min_gap` in (u, v) whose straight (u, v) segment has an image on the surface no
/// longer than twice the gap's chord in space (a bridge, not a turn round a closed surface) and
/// within `cap_3d` of both ends gets that segment; so does a gap of any length whose two ends lie
/// on one side of the domain, neither curve running back along it (the missing edge is the
/// surface's own side there, exactly).
/// The face's boundary is then known only as closely as the bridge is long: returns the largest
/// extent bridged or cut (0 when none), for the caller's edge gap; `added` counts the repairs.
double bridge_open_joints(TrimmedSurface& face, double cap_3d, double min_gap, int& added);

/// The curves the repairs above added (Curve2::edge -1) where a file's loops skip an edge: where
/// the loops of two faces of one body each skip it, their two added curves join the same two points
/// in space (within `tolerance`, either way round), and are the same missing edge. Each such pair,
/// and only a pair (no third added curve there), gets one new edge number above every edge of
/// `bodies`, so that a watertight mesh meshes it once (watertight.h). Returns the pairs numbered.
int pair_added_edges(std::vector<Body>& bodies, double tolerance);

}  // namespace nurbs
