#pragma once
/// \file random_surfaces.h
/// A reproducible random family of surfaces and trimmed faces for property tests. Reproducible
/// across compilers and standard libraries: only the raw 64-bit output of std::mt19937_64 (fully
/// specified by the standard) is used, never std::uniform_*_distribution (implementation-defined).
#include <cstdint>
#include <random>

#include "nurbs/trimmed_surface.h"

namespace models {

/// Uniform doubles and integers from the raw mt19937_64 stream.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1): the top 53 bits of one output, times 2^-53.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [lo, hi] (modulo bias < 2^-50 for the small ranges used here).
  int integer(int lo, int hi) { return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1)); }

 private:
  std::mt19937_64 engine_;
};

/// A valid random surface of the given degrees: count = degree + 1 + [0, 4] control points per
/// direction, random interior knots (simple) on a random domain [a, a + w], a in [-2, 2], w in
/// [0.5, 3]; one seed in four gives unclamped knot vectors. Control points in [-1, 1]^3 on a jittered
/// grid; weights in [0.2, 5] when `rational`.
[[nodiscard]] nurbs::Surface random_surface(std::uint64_t seed, int degree_u, int degree_v, bool rational);

/// A harder random surface for the certified grids: degrees as given (1-11), clamped knots
/// on [0, w] whose interior knots repeat 1 to `degree` times (at `degree`, the surface is only C^0
/// there: piecewise Bézier as in VDA-FS and CATIA data), including a run of tiny spans; when
/// `weight_ratio` > 1 the surface is rational with weights log-uniform in [1, weight_ratio].
[[nodiscard]] nurbs::Surface random_kinked_surface(std::uint64_t seed, int degree_u, int degree_v, double weight_ratio);

/// A random trimmed face: random_surface with degrees in [1, 4] and rational or not drawn from the
/// seed, an outer CCW loop (a random star-shaped polygon of 4-7 degree-1 edges, or none, one seed in
/// four), and 0-3 circular CW holes placed in separate cells about the centre so loops never cross. face_id = seed %
/// 1000.
[[nodiscard]] nurbs::TrimmedSurface random_trimmed_surface(std::uint64_t seed);

}  // namespace models
