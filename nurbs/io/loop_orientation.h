#pragma once
/// \file loop_orientation.h
/// Orientation of trim loops in the (u, v) plane. IGES does not fix the direction of trim
/// boundaries; nurbs/trimmed_surface.h wants outer loops counter-clockwise and holes clockwise.
#include "nurbs/trimmed_surface.h"

namespace nurbs::io {

/// Signed area of a loop (positive = counter-clockwise), by the shoelace formula over points
/// sampled on every curve (`samples_per_curve` + 1 per curve, more for long control polygons).
double signed_area(const TrimLoop& loop, int samples_per_curve = 16);

/// Reverses the loop (curve order and each curve) if its orientation disagrees with loop.outer.
/// Returns true if it was reversed. Loops of zero area are left alone.
bool orient_loop(TrimLoop& loop);

/// The boundary of the surface's parameter domain as an outer loop of four degree-1 curves,
/// counter-clockwise from (u0, v0).
TrimLoop domain_loop(const Surface& s);

}  // namespace nurbs::io
