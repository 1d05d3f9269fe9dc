// §3.3 ray / bicubic patch: the three outcomes, the control-polyhedron start, the parametric scale.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/raycast/ray_patch.h"

using namespace nurbs::ray;

namespace {

/// A curved bicubic patch: z = sin-like bump through control points; (x, y) = 2 (s, t) exactly
/// (control x, y on the uniform grid: linear precision of Bernstein polynomials).
BicubicPatch bump() {
  BicubicPatch p;
  const double z[4] = {0.0, 0.4, -0.3, 0.1};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) p.p[4 * j + i] = {2.0 * i / 3.0, 2.0 * j / 3.0, z[i] + 0.5 * z[j]};
  p.box_min = p.box_max = p.p[0];
  for (const auto& q : p.p) p.box_min = glm::min(p.box_min, q), p.box_max = glm::max(p.box_max, q);
  return p;
}

}  // namespace

TEST_CASE("ray/patch: vertical rays converge to (s, t) = (x, y) / 2 from the control-polyhedron start") {
  const BicubicPatch p = bump();
  int bad = 0;
  for (double x : {0.01, 0.3, 0.77, 1.2, 1.99})
    for (double y : {0.02, 0.5, 1.1, 1.98}) {
      const Ray ray{{x, y, 5.0}, {0, 0, -1}};
      glm::dvec2 start[4];
      REQUIRE(initial_guesses(p, ray, start, 4) >= 1);
      // The net's (x, y) is the uniform grid, so the linear interpolation on the crossed triangle is exact:
      // the start is (x, y) / 2 already (round-off of the unit square).
      bad += glm::length(start[0] - glm::dvec2(x, y) / 2.0) > 1e-12;
      const PatchHit h = newton_patch(p, ray, ray_planes(ray), start[0], RayPatchOptions{});
      bad += h.outcome != PatchOutcome::Converged;
      // x, y are linear in (s, t): Newton lands on (x/2, y/2) to round-off (1e-12 of the unit square).
      bad += glm::length(h.st - glm::dvec2(x, y) / 2.0) > 1e-12;
      bad += std::abs(h.t - (5.0 - h.point.z)) > 1e-12;
    }
  CHECK(bad == 0);
}

TEST_CASE("ray/patch: outcomes outside and no-convergence") {
  const BicubicPatch p = bump();
  // Beside the patch: the polynomial's extension is hit at s = 1.25 > 1.
  const Ray beside{{2.5, 1.0, 5.0}, {0, 0, -1}};
  CHECK(newton_patch(p, beside, ray_planes(beside), {0.5, 0.5}, RayPatchOptions{}).outcome == PatchOutcome::Outside);
  // Parallel to the x axis far above the patch: R never vanishes.
  const Ray above{{-1.0, 1.0, 7.0}, {1, 0, 0}};
  CHECK(newton_patch(p, above, ray_planes(above), {0.5, 0.5}, RayPatchOptions{}).outcome ==
        PatchOutcome::NoConvergence);
  std::array<PatchHit, 4> hits;
  CHECK(intersect_patch(p, above, RayPatchOptions{}, 0.0, hits) == 0);
  CHECK(intersect_patch(p, beside, RayPatchOptions{}, 0.0, hits) == 0);
}

TEST_CASE("ray/patch: the 1e4 parametric scale changes nothing in double; oblique rays and the far hit") {
  const BicubicPatch p = bump();
  RayPatchOptions unscaled;
  unscaled.param_scale = 1.0;
  const Ray ray{{-0.5, 0.2, 2.0}, glm::normalize(glm::dvec3(1.0, 0.6, -1.2))};
  const PatchHit a = newton_patch(p, ray, ray_planes(ray), {0.5, 0.5}, RayPatchOptions{});
  const PatchHit b = newton_patch(p, ray, ray_planes(ray), {0.5, 0.5}, unscaled);
  REQUIRE(a.outcome == PatchOutcome::Converged);
  CHECK(glm::length(a.st - b.st) <= 1e-12);  // same iterates up to round-off
  // The hit is on the ray: distance from the ray line within round-off of the unit patch.
  const glm::dvec3 q = ray.origin + a.t * ray.direction;
  CHECK(glm::length(q - a.point) <= 1e-12);
  // A grazing ray along the bump in x crosses the surface more than once: every hit is reported, nearest first.
  const Ray along{{-0.1, 0.0, 0.05}, glm::normalize(glm::dvec3(1.0, 0.0, 0.0))};
  std::array<PatchHit, 4> hits;
  const int n = intersect_patch(p, along, RayPatchOptions{}, 0.0, hits);
  CHECK(n >= 2);
  for (int k = 1; k < n; ++k) CHECK(hits[k - 1].t < hits[k].t);
}
