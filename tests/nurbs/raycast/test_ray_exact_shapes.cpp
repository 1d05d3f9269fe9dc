// Exact shapes with analytic hits: rational sphere and cylinder, a plane with a circular hole.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/raycast/raycast_cpu.h"

using namespace nurbs;
using namespace nurbs::ray;

namespace {

TrimmedSurface untrimmed(Surface s) {
  TrimmedSurface f;
  f.surface = std::move(s);
  return f;
}

/// Smallest t > 0 of |o + t d - c|^2 = r^2 in the coordinates selected by `mask` (1 = used).
double quadric_hit(glm::dvec3 o, glm::dvec3 d, glm::dvec3 c, double r, glm::dvec3 mask) {
  const glm::dvec3 oc = (o - c) * mask, dm = d * mask;
  const double a = glm::dot(dm, dm), b = glm::dot(oc, dm), cc = glm::dot(oc, oc) - r * r;
  const double disc = b * b - a * cc;
  if (disc < 0.0) return -1.0;
  return (-b - std::sqrt(disc)) / a;
}

}  // namespace

TEST_CASE("raycast: rational sphere, rays from outside hit at the analytic distance") {
  const glm::dvec3 c(0.3, -0.2, 0.1);
  const double r = 2.0;
  const Scene scene = build_scene({untrimmed(models::rational_sphere(r, c))});
  REQUIRE(scene.patches.size() > 0);
  models::Random rng(11);
  int hits = 0;
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    // Origin on a sphere of radius 5, aimed within 0.9 r of the centre: no grazing rays.
    const double z = rng.uniform(-1, 1), a = rng.uniform(0, 6.283185307179586);
    const glm::dvec3 o =
        c + 5.0 * glm::dvec3(std::sqrt(1 - z * z) * std::cos(a), std::sqrt(1 - z * z) * std::sin(a), z);
    const glm::dvec3 aim =
        c + 0.9 * r * glm::dvec3(rng.uniform(-0.57, 0.57), rng.uniform(-0.57, 0.57), rng.uniform(-0.57, 0.57));
    const Ray ray{o, glm::normalize(aim - o)};
    const double expected = quadric_hit(ray.origin, ray.direction, c, r, glm::dvec3(1.0));
    REQUIRE(expected > 0.0);
    const Hit h = cast_ray(scene, ray, 0.0);
    hits += h.face == 0;
    if (h.face == 0) worst = std::max(worst, std::abs(h.t - expected));
  }
  CHECK(hits == 300);
  // The required bound: 1e-9 x model size after the final Newton step on the exact surface.
  CHECK(worst <= 1e-9 * scene.size);
  MESSAGE("sphere: " << scene.patches.size() << " patches, worst |t - t_exact| = " << worst);
}

TEST_CASE("raycast: rational cylinder, horizontal rays hit at the analytic distance") {
  const double r = 1.0, height = 3.0;
  const Scene scene = build_scene({untrimmed(models::rational_cylinder(r, height))});
  models::Random rng(12);
  double worst = 0.0;
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    const double a = rng.uniform(0, 6.283185307179586), zo = rng.uniform(0.1, 2.9);
    const glm::dvec3 o(4.0 * std::cos(a), 4.0 * std::sin(a), zo);
    // Aim within 0.9 r of the axis at a height inside (0.1, 2.9): the ray crosses the side only.
    const glm::dvec3 aim(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), zo + rng.uniform(-0.05, 0.05));
    const Ray ray{o, glm::normalize(aim - o)};
    const double expected = quadric_hit(ray.origin, ray.direction, glm::dvec3(0.0), r, glm::dvec3(1, 1, 0));
    const Hit h = cast_ray(scene, ray, 0.0);
    hits += h.face == 0;
    if (h.face == 0) worst = std::max(worst, std::abs(h.t - expected));
  }
  CHECK(hits == 200);
  CHECK(worst <= 1e-9 * scene.size);  // as for the sphere
}

TEST_CASE("raycast: plane with a circular hole, rays through the hole miss") {
  Surface plane;
  plane.degree_u = plane.degree_v = 1;
  plane.count_u = plane.count_v = 2;
  plane.knots_u = plane.knots_v = {0, 0, 1, 1};
  plane.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}};
  TrimmedSurface face = untrimmed(plane);
  face.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.2, false)}, false});  // hole of radius 0.4 in xy
  const Scene scene = build_scene({face});
  models::Random rng(13);
  int wrong = 0;
  for (int k = 0; k < 400; ++k) {
    const glm::dvec2 p(rng.uniform(0.05, 1.95), rng.uniform(0.05, 1.95));
    const double rho = glm::length(p - glm::dvec2(1.0));
    if (std::abs(rho - 0.4) < 1e-3) continue;  // within the trim flattening of the circle: either way
    const Ray ray{{p.x, p.y, 1.5}, {0, 0, -1}};
    const Hit h = cast_ray(scene, ray, 0.0);
    const bool expect_hit = rho > 0.4;
    wrong += (h.face == 0) != expect_hit;
    if (h.face == 0) wrong += std::abs(h.t - 1.5) > 1e-12;  // a plane: exact to round-off
  }
  CHECK(wrong == 0);
}
