// §3.3 ray / bicubic patch: the three outcomes, the control-polyhedron start, the parametric scale.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "models/random_surfaces.h"
#include "nurbs/raycast/ray_patch.h"
#include "nurbs/surface_eval.h"

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

TEST_CASE("exact step: converges wherever plain Newton does, to the same hit, with no larger residual (surface and Bezier form)") {
  // refine_on_surface stops at the rounding floor; the reference here iterates 40 times with no
  // stop. Starts a few percent of the domain off the ray's point, so that some first steps do not
  // yet halve the residual.
  int converged = 0, lost = 0, moved = 0, worse = 0;
  for (int seed = 0; seed < 30; ++seed) {
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed + 7), 1 + seed % 4, 1 + (seed / 4) % 4,
                                          seed % 3 == 0);
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const nurbs::BezierForm form(s);
    const double size = 10.0, tol = 1e-10 * size;
    for (int k = 0; k < 20; ++k) {
      const glm::dvec2 at(du.min + du.width() * (0.2 + 0.6 * ((k * 7 + seed) % 20) / 20.0),
                          dv.min + dv.width() * (0.2 + 0.6 * ((k * 11 + seed) % 20) / 20.0));
      const glm::dvec3 n = nurbs::surface_normal(s, at.x, at.y);
      if (glm::length(n) == 0.0) continue;
      const glm::dvec3 tilt(0.3 * std::sin(k + seed), 0.3 * std::cos(3.0 * k), 0.2);
      Ray ray;
      ray.direction = glm::normalize(-n + tilt);
      ray.origin = nurbs::surface_point(s, at.x, at.y) - 2.0 * ray.direction;
      const RayPlanes planes = ray_planes(ray);
      const glm::dvec2 start = at + glm::dvec2(0.04 * du.width() * std::cos(k), 0.04 * dv.width() * std::sin(k));
      // The reference: plain Newton, clamped to the domain, 40 steps.
      glm::dvec2 uv = start;
      double residual = 0.0;
      for (int it = 0; it <= 40; ++it) {
        const auto d = nurbs::surface_derivatives(s, uv.x, uv.y);
        const glm::dvec2 r(glm::dot(planes.n1, d.s) + planes.d1, glm::dot(planes.n2, d.s) + planes.d2);
        residual = glm::length(r);
        const double a = glm::dot(planes.n1, d.su), b = glm::dot(planes.n1, d.sv), c = glm::dot(planes.n2, d.su),
                     e = glm::dot(planes.n2, d.sv), det = a * e - b * c;
        if (it == 40 || det == 0.0) break;
        uv = glm::clamp(uv - glm::dvec2(e * r.x - b * r.y, a * r.y - c * r.x) / det, glm::dvec2(du.min, dv.min),
                        glm::dvec2(du.max, dv.max));
      }
      if (!(residual <= tol)) continue;
      ++converged;
      const glm::dvec3 p = nurbs::surface_point(s, uv.x, uv.y);
      // On the surface, and on its Bézier form.
      for (const ExactHit& h : {refine_on_surface(s, ray, planes, start, 40, tol),
                                refine_on_surface(form, s, ray, planes, start, 40, tol)}) {
        if (!h.ok) {
          ++lost;
          continue;
        }
        moved += glm::length(h.point - p) > 1e-9 * size;
        const glm::dvec3 q = nurbs::surface_point(s, h.uv.x, h.uv.y);
        const glm::dvec2 rh(glm::dot(planes.n1, q) + planes.d1, glm::dot(planes.n2, q) + planes.d2);
        worse += glm::length(rh) > 4.0 * std::max(residual, 1e-15 * size);
      }
    }
  }
  CAPTURE(converged);
  CHECK(converged > 300);
  CHECK(lost == 0);
  CHECK(moved == 0);
  CHECK(worse == 0);
}
