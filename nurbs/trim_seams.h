#pragma once
/// \file trim_seams.h
/// Trim loops that go round a closed surface. A NURBS surface that closes on itself in u (S(u0, v) =
/// S(u1, v), a cylinder, a cone, a sphere or a surface of revolution) has its seam at u0 = u1 in
/// the (u, v) plane; a loop that goes once round it (the circle bounding a band of a cylinder) runs
/// from one side of the domain to the other and cannot close in (u, v): the gap is exactly the
/// period u1 - u0. OpenCASCADE keeps such faces closed with seam edges (ShapeFix_Face::FixMissingSeam);
/// here the same seam segments are added in (u, v). Same in v.
#include "nurbs/trimmed_surface.h"

namespace nurbs {

/// Closes loops of `face` that go round the seam of its closed surface. A gap counts as a seam jump
/// when its ends lie on opposite sides of the domain (u0 and u1, the same v within `min_gap`; or the
/// same with u and v swapped) and the surface is closed there (|S(u0, v) - S(u1, v)| <= tolerance_3d
/// at 9 values of v). Loops with exactly one seam jump are closed pairwise: two such loops (the
/// boundary circles of a band) become one loop through two seam segments, the second loop turned
/// round first when both run the same way; a loop left over (a cap whose other side is a pole or
/// the surface's own boundary) is closed along the side of the domain on its material side (left
/// of its direction: curves running towards u1 have their material towards v1). A loop with two
/// seam jumps (a patch straddling the seam) is split into its two pieces, one at each side of the
/// domain, each closed by a segment along its seam side (a hole straddling the seam of a face whose
/// outer loop runs along the seam then touches it there, which check_trim_loops reports). A loop
/// that goes once round but crosses the seam 3, 5, ... times (a thread's run-out that dips back
/// across it) keeps the one piece that runs from side to side, closed as above; each dip, a piece
/// from one side back to the same side, is closed along that side into a region of the face or a
/// hole in it, as the material lies on its left or right once the loop is closed. Returns the
/// number of loops closed this way.
int close_loops_round_seam(TrimmedSurface& face, double tolerance_3d, double min_gap);

/// Brings the loops of a face on a closed surface into its domain where the file puts its seam
/// elsewhere than the surface's (a cylinder whose pcurves run over u in [2 pi, 4 pi] on a surface
/// of domain [4 pi / 3, 10 pi / 3]): loops reaching beyond the domain by more than `min_gap` are
/// moved by whole periods to start inside it, and where they still reach beyond its far side the
/// surface is made one period longer (its net followed by a copy of itself, joined with
/// continuity C0 at the seam; the same points in space). Material beyond the domain would
/// otherwise be left out of every mesh and query. Loops spanning more than a period, and surfaces
/// not closed within `tolerance_3d`, are left as they are. Returns the number of directions (u, v)
/// changed.
int wrap_loops_into_domain(TrimmedSurface& face, double tolerance_3d, double min_gap);

}  // namespace nurbs
