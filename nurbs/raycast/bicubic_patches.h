#pragma once
/// \file bicubic_patches.h
/// Lemasson et al. §3.1 "Surfaces": every NURBS face becomes polynomial bicubic Bézier patches
/// (4 x 4 control points) within an absolute tolerance, each with its parameter rectangle on the
/// face and the axis-aligned box of its control points (convex hull property); patches wholly in a
/// hole or outside the trim are culled.
///
/// Method (ours; the paper only says "C² bicubic"): bicubic Hermite interpolation per cell of a
/// tensor grid of the face's parameter rectangle. The grid starts at the knot lines (each cell then
/// lies in one Bézier piece, so one-sided derivatives at C⁰ knots are right) and is refined by
/// inserting whole grid lines through cells whose sampled error is too large, so the grid stays
/// conforming. A cell's patch takes S, Su, Sv and the twist Suv of the exact surface at its four
/// corners: with h, k the cell sizes, P10 = S00 + h/3 Su, P11 = S00 + h/3 Su + k/3 Sv + hk/9 Suv,
/// and so on from every corner. A patch edge depends only on the data of that edge, so neighbours
/// share their edges and cross-boundary derivatives: the patch set is C¹ (not C²) and has no cracks.
/// Error: the Hermite interpolant reproduces bicubic polynomials exactly, so polynomial faces of
/// degree <= 3 have zero error (proven); in general the error is O(h⁴) and measured by sampling an
/// n x n grid of interior points against the exact surface with a safety margin (not a proof).
#include <array>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/knot_vector.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::ray {

/// One bicubic Bézier patch on local (s, t) in [0, 1]^2; face point at (s, t) ~ S(u, v) with
/// u = range_u.min + s (range_u.max - range_u.min), v likewise.
struct BicubicPatch {
  std::array<glm::dvec3, 16> p{};         ///< control points, p[4 j + i] with i along s (u), j along t (v)
  Interval range_u, range_v;              ///< the patch's rectangle in the face's (u, v)
  glm::dvec3 box_min{0.0}, box_max{0.0};  ///< box of the 16 control points (contains the patch)
  int face = -1;                          ///< index of the face in the caller's face list
};

struct BicubicOptions {
  double tolerance = 1e-4;     ///< absolute, model units (the paper: 1e-4; ours: relative to model size)
  int samples = 6;             ///< n: the sampled check uses n x n interior points per cell
  double margin = 0.5;         ///< a cell passes when its sampled error <= margin * tolerance
  int max_rounds = 16;         ///< refinement rounds (each halves the failing grid intervals)
  int max_cells = 200000;      ///< stop refining a face beyond this many grid cells
  double trim_flatten = 1e-6;  ///< trim flattening tolerance for culling, relative to the domain diagonal
  /// Beyond the tolerance, a cell is also split while its normals turn by more than this (degrees;
  /// 0 = off, the paper's conversion; the ray caster's scene turns it on, raycast_cpu.h): on a flatter patch a ray
  /// crosses at most once away from grazing, and the start from the control polyhedron lies near the hit, so the fixed
  /// Newton iterations find it. Without it a large exact bicubic (the teapot's 32 patches) kept whole missed 2 % of
  /// nearest hits. Cells whose box is under 100 x tolerance are not split for this (near poles normals always turn).
  double max_turn_degrees = 0.0;
};

struct BicubicStats {
  int patches = 0;                 ///< kept
  int culled = 0;                  ///< cells outside the material
  double max_sampled_error = 0.0;  ///< over kept cells, from the final sampled check
  int rounds = 0;
  bool converged = true;  ///< false when max_rounds or max_cells stopped refinement first
};

/// Bicubic patches of one face (surface rational or not, any degree), `face` copied into each.
[[nodiscard]] std::vector<BicubicPatch> bicubic_patches(const TrimmedSurface& face, int face_index,
                                                        const BicubicOptions& options, BicubicStats* stats = nullptr);

/// Point and first partials (wrt s, t) of a bicubic patch by de Casteljau (the paper's choice on
/// the GPU: halving weights are exact in float).
struct PatchPoint {
  glm::dvec3 s{0.0}, ss{0.0}, st{0.0};  ///< S, dS/ds, dS/dt
};
[[nodiscard]] PatchPoint evaluate_patch(const BicubicPatch& patch, double s, double t);

/// Largest |patch(s, t) - S(u(s), v(t))| over an n x n grid of interior sample points.
[[nodiscard]] double sampled_error(const Surface& surface, const BicubicPatch& patch, int n);

}  // namespace nurbs::ray
