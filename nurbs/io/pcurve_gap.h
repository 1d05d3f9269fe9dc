#pragma once
/// \file pcurve_gap.h
/// How far a B-rep edge's model-space curve lies from its face's boundary as the face's parameter
/// curves give it (the surface along them): the two curves a file gives for one edge need not
/// meet, and the face's trim is the second one. Internal to the readers.
#include <span>

#include "nurbs/curve.h"
#include "nurbs/surface.h"

namespace nurbs::io {

/// Samples per curve at which pcurve_gap measures: the ends and 31 interior parameters, evenly
/// spaced.
inline constexpr int kPcurveGapSamples = 32;

/// Two-sided (Hausdorff) distance, model units, between the model-space curves `edge` and the
/// surface `s` along the parameter-space curves `pcurves` (in s's (u, v)), measured at
/// kPcurveGapSamples + 1 evenly spaced parameters of every curve of either side: each sample's
/// distance to the nearest point found on the other side (nearest polyline point of the other
/// side's samples, then Gauss-Newton on the curve itself). Every distance is to a point on the
/// other curve, so a sample's distance is never underestimated; neither side's parametrisation nor
/// direction matters. Samples whose nearest sample of the other side lies within `floor` are not
/// refined: the result is exact only where it exceeds `floor`. Parameter curves reaching beyond
/// the surface's domain along a direction in which it closes within `floor` are taken whole periods
/// back into it (the seam placed elsewhere by the file). Infinite when a point is not finite.
double pcurve_gap(const Surface& s, std::span<const Curve2> pcurves, std::span<const Curve3> edge, double floor);

}  // namespace nurbs::io
