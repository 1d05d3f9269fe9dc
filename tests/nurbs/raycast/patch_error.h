#pragma once
/// \file patch_error.h
/// Test-side error of a bicubic patch against its face, computed independently of the library
/// (Bernstein sum, not de Casteljau; not sampled_error) so that a wrong library measure shows.
#include <algorithm>
#include <glm/geometric.hpp>

#include "nurbs/raycast/bicubic_patches.h"
#include "nurbs/surface_eval.h"

namespace test {

inline glm::dvec3 bernstein_patch(const nurbs::ray::BicubicPatch& p, double s, double t) {
  auto b = [](int i, double x) {
    const double y = 1.0 - x;
    const double c[4] = {y * y * y, 3 * x * y * y, 3 * x * x * y, x * x * x};
    return c[i];
  };
  glm::dvec3 out(0.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) out += b(i, s) * b(j, t) * p.p[4 * j + i];
  return out;
}

/// Largest distance over an n x n grid of points at (a + 0.5) / n, b likewise.
inline double patch_error(const nurbs::Surface& surface, const nurbs::ray::BicubicPatch& p, int n) {
  double worst = 0.0;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const double s = (a + 0.5) / n, t = (b + 0.5) / n;
      const double u = p.range_u.min + s * (p.range_u.max - p.range_u.min);
      const double v = p.range_v.min + t * (p.range_v.max - p.range_v.min);
      worst = std::max(worst, glm::length(bernstein_patch(p, s, t) - nurbs::surface_point(surface, u, v)));
    }
  return worst;
}

}  // namespace test
