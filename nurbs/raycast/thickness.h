#pragma once
/// \file thickness.h
/// Wall thickness by ray casting (Lemasson et al. §1 and §4: from samples on the surface, a ray
/// along the inward normal; the thickness is the distance to the nearest valid hit).
///
/// Samples: per face a grid of cell centres in (u, v) whose spacing in space is about `spacing`
/// (the face's extent along u and v measured on a 9 x 9 grid of points), the centres outside the
/// trim dropped. Cell centres keep samples off the face's edges, where a ray starts on the
/// neighbouring face. The same grid gives the coloured mesh: two triangles per grid cell whose
/// four corner samples are all material.
///
/// Orientation: IGES 144 faces without a 514 shell carry no orientation, so every face's inward
/// side is decided by ray parity: from a few interior points of the face a ray along +N (= Su x Sv)
/// counts its crossings with the model; an odd count means +N points into the material. The
/// majority of the face's points decides; faces where the file's flag (TrimmedSurface::reversed)
/// disagrees are counted. On an open shell the parity has no meaning (and neither has thickness).
///
/// Accuracy of one thickness: the hit is the exact NURBS face point found by the final Newton step
/// (residual <= exact_residual x size, raycast_cpu.h), so |t - t*| <= that residual over the cosine
/// of the incidence angle for the surface hit; that no nearer hit was missed is the ray caster's
/// claim (bicubic boxes padded by twice their tolerance), not a proof.
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/raycast/raycast_cpu.h"
#include "nurbs/triangle_mesh.h"

namespace nurbs::ray {

struct ThicknessOptions {
  double spacing = 0.0;        ///< sample spacing in model units (> 0)
  double start_offset = 1e-7;  ///< rays ignore hits with t <= this x scene size (the sample's own face)
  int parity_points = 3;       ///< interior points per face for the orientation vote
  int max_grid = 2048;         ///< per face at most this many samples along u and along v
};

/// One face's grid of samples (row-major, nu x nv); material[i] false where the centre is trimmed.
struct FaceSamples {
  int face = -1;
  int nu = 0, nv = 0;
  std::vector<glm::dvec2> uv;
  std::vector<glm::dvec3> point, inward;  ///< inward = unit normal into the material
  std::vector<bool> material;
};

struct ThicknessSamples {
  std::vector<FaceSamples> faces;
  std::vector<int> inward_sign;           ///< per face: +1 when Su x Sv points into the material, -1 otherwise
  int orientation_flips = 0;              ///< faces whose parity disagrees with the file's `reversed` flag
  int orientation_unsure = 0;             ///< faces whose parity vote was not unanimous (or had no ray)
  [[nodiscard]] long long count() const;  ///< material samples
};

/// Spacing that gives about `samples` material samples over the model (area / samples, from the
/// faces' 9 x 9 point grids and their trims).
[[nodiscard]] double spacing_for_samples(const Scene& scene, long long samples);

/// A function that casts rays (any engine: the CPU twin, DACRT or the GPU) and returns their hits.
using CastFn = std::function<std::vector<Hit>(const std::vector<Ray>&, double t_min)>;

/// Orients the faces by ray parity (through `cast`) and places the samples.
[[nodiscard]] ThicknessSamples thickness_samples(const Scene& scene, const ThicknessOptions& options,
                                                 const CastFn& cast);

/// The rays of the material samples, in face then grid order, and where each one came from.
struct ThicknessRays {
  std::vector<Ray> rays;
  std::vector<std::pair<int, int>> source;  ///< (index in ThicknessSamples::faces, grid index)
};
[[nodiscard]] ThicknessRays thickness_rays(const ThicknessSamples& samples);

/// Thickness per sample of every face (ThicknessSamples::faces order, grid order), -1 where there
/// is no ray or no hit.
using SampleThickness = std::vector<std::vector<double>>;

/// The thickness colour ramp, thin to thick: red, yellow, green, blue. Every picture of a thickness
/// uses these stops (the PLY of `thickness -o`, the viewer's shader through a uniform, its legend).
inline constexpr double kThicknessRamp[4][3] = {{0.9, 0.1, 0.1}, {0.95, 0.85, 0.1}, {0.2, 0.75, 0.3}, {0.15, 0.35, 0.9}};
/// The ramp at x in [0, 1] (clamped): linear between the stops at 0, 1/3, 2/3 and 1.
[[nodiscard]] glm::dvec3 thickness_ramp(double x);
/// thickness_ramp of t from lo (thin) to hi (thick); grey for t < 0 (no hit).
[[nodiscard]] glm::dvec3 thickness_colour(double t, double lo, double hi);

/// The sample grids as one mesh: a vertex per material sample (normal = -inward, (u, v), face,
/// colour by thickness_colour), two triangles per grid cell whose four samples are material,
/// counter-clockwise seen from outside. `vertex_thickness` (optional) gets each vertex's thickness.
[[nodiscard]] TriangleMesh thickness_mesh(const ThicknessSamples& samples, const SampleThickness& thickness, double lo,
                                          double hi, std::vector<double>* vertex_thickness = nullptr);

/// Min, median, mean and max of a set of thicknesses (-1 each when it is empty), as the CLI's ray
/// and rolling-ball summaries report them.
struct ThicknessSummary {
  long long count = 0;
  double min = -1.0, median = -1.0, mean = -1.0, max = -1.0;
};
[[nodiscard]] ThicknessSummary summarize_thickness(std::vector<double> values);

}  // namespace nurbs::ray
