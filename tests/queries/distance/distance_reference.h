#pragma once
/// \file distance_reference.h
/// Independent references for the distance tests, in double: dense sampling then Newton.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <vector>

#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace test {

/// Whether (u, v) of `face` is material (its loops flattened at 1e-9 of the domain) or, for an
/// answer on a trim edge, lies within 2e-6 of the domain of material: the queries flatten the
/// loops at 1e-6 of it, so a point of their polygons' edges may fall just outside the finer ones.
inline bool material_or_trim_edge(const nurbs::TrimmedSurface& face, glm::dvec2 uv, bool on_trim_edge) {
  const double width = nurbs::surface_domain_u(face.surface).width();
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 1e-9 * width);
  if (nurbs::is_material(trim, uv)) return true;
  if (!on_trim_edge) return false;
  for (int k = 0; k < 16; ++k) {
    const double a = 2.0 * M_PI * k / 16;
    if (nurbs::is_material(trim, uv + 2e-6 * width * glm::dvec2(std::cos(a), std::sin(a)))) return true;
  }
  return false;
}

/// Independent reference: the closest of 200 x 200 samples, then projected Newton on
/// f(u, v) = |S(u, v) - p|^2 from the best 8 samples and one more start (clamped to the domain).
/// The extra start (the query's own answer) only helps the reference find the global minimum where
/// folds of a random net hide it between samples; every distance is still computed on the surface.
struct Reference {
  double distance;
  glm::dvec3 point;
};
inline Reference reference(const nurbs::Surface& s, const glm::dvec3& p, glm::dvec2 extra_start) {
  const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
  constexpr int N = 200;
  std::vector<std::pair<double, glm::dvec2>> samples;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i) {
      const glm::dvec2 uv(du.min + du.width() * i / N, dv.min + dv.width() * j / N);
      samples.emplace_back(glm::length(nurbs::surface_point(s, uv.x, uv.y) - p), uv);
    }
  std::partial_sort(samples.begin(), samples.begin() + 8, samples.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
  Reference best{samples.front().first, nurbs::surface_point(s, samples.front().second.x, samples.front().second.y)};
  for (int k = 0; k < 9; ++k) {
    glm::dvec2 uv = k < 8 ? samples[size_t(k)].second : extra_start;
    double f = glm::length(nurbs::surface_point(s, uv.x, uv.y) - p);
    for (int it = 0; it < 40; ++it) {
      const nurbs::SurfaceDerivatives d = nurbs::surface_derivatives(s, uv.x, uv.y);
      const glm::dvec3 r = d.s - p;
      const double gu = glm::dot(r, d.su), gv = glm::dot(r, d.sv);
      const double huu = glm::dot(d.su, d.su) + glm::dot(r, d.suu), hvv = glm::dot(d.sv, d.sv) + glm::dot(r, d.svv);
      const double huv = glm::dot(d.su, d.sv) + glm::dot(r, d.suv);
      const double det = huu * hvv - huv * huv;
      // Newton where the Hessian is positive definite, else a gradient step; halved until it descends.
      glm::dvec2 step =
          det > 0 && huu > 0
              ? glm::dvec2((hvv * gu - huv * gv) / det, (huu * gv - huv * gu) / det)
              : glm::dvec2(gu, gv) /
                    std::max(glm::length(d.su) * glm::length(d.su) + glm::length(d.sv) * glm::length(d.sv), 1e-300);
      bool moved = false;
      for (int half = 0; half < 30 && !moved; ++half, step *= 0.5) {
        const glm::dvec2 next = glm::clamp(uv - step, glm::dvec2(du.min, dv.min), glm::dvec2(du.max, dv.max));
        const double fn = glm::length(nurbs::surface_point(s, next.x, next.y) - p);
        if (fn < f) uv = next, f = fn, moved = true;
      }
      if (!moved) break;
    }
    if (f < best.distance) best = {f, nurbs::surface_point(s, uv.x, uv.y)};
  }
  return best;
}

/// The checks of a coarse-to-fine answer (queries/distance/refine.h): found, within the tolerance, and the
/// interval [distance - bound, distance] holds `truth` (a true distance, or one realised by a
/// reference at least as close as the true minimum) up to `slack`.
inline void check_proven(bool found, bool meets_tolerance, double distance, double bound, double tolerance,
                         double truth, double slack) {
  REQUIRE(found);
  CHECK(meets_tolerance);
  CHECK(bound <= tolerance);
  CHECK(truth >= distance - bound - slack);
  CHECK(truth <= distance + slack);
}

}  // namespace test
