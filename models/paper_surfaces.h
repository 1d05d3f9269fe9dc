#pragma once
/// \file paper_surfaces.h
/// The test pair of Krishnamurthy et al. (§6: two B-spline surfaces of 199 x 33 and 100 x 105
/// control points) rebuilt as wavy bicubic surfaces, and a trimmed version of the second one.
/// The paper does not publish the shapes; ours are documented here so figures can be reproduced:
///   - 199 x 33: footprint 200 mm (x, along u) by 40 mm (y, along v), z = 5 sin(2 pi x / 50) cos(2 pi y / 40) mm.
///   - 100 x 105: footprint 100 mm by 100 mm, z = 4 cos(2 pi x / 40) sin(2 pi y / 30) mm, lifted by
///     +20 mm in z so the pair is separated (minimum distance queries need disjoint surfaces).
/// Both: degree (3, 3), clamped uniform knots on [0, 1], control points on the uniform grid of the
/// footprint with z from the formula (the surface is a smoothed version of it).
#include "nurbs/trimmed_surface.h"

namespace models {

/// Wavy bicubic clamped-uniform B-spline of count_u x count_v control points over a size_u x size_v mm
/// footprint starting at the origin: z(x, y) = amplitude sin(2 pi x / wave_x + phase) cos(2 pi y / wave_y).
[[nodiscard]] nurbs::Surface wavy_surface(int count_u, int count_v, double size_u, double size_v, double amplitude,
                                          double wave_x, double wave_y, double phase, double z_offset);

/// The paper's 199 x 33 surface (see file comment).
[[nodiscard]] nurbs::Surface wavy_surface_199x33();

/// The paper's 100 x 105 surface (see file comment).
[[nodiscard]] nurbs::Surface wavy_surface_100x105();

/// wavy_surface_100x105 trimmed in (u, v) in [0,1]^2: outer loop = the square [0.05, 0.95]^2 as four
/// degree-1 curves (CCW); inner loops (CW): circles of radius 0.12 about (0.3, 0.3) and 0.1 about
/// (0.7, 0.65), and a cubic B-spline blob about (0.3, 0.72). face_id 1.
[[nodiscard]] nurbs::TrimmedSurface trimmed_wavy_surface_100x105();

/// Clamped uniform knot vector of degree p for `count` points on [0, 1].
[[nodiscard]] std::vector<double> clamped_uniform_knots(int degree, int count);

/// A degree-1 trim curve from a to b (parameter [0, 1]).
[[nodiscard]] nurbs::Curve2 trim_line(glm::dvec2 a, glm::dvec2 b);

}  // namespace models
