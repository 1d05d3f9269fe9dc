// The certified mesh's point distances (queries/distance/mesh_distance.h) against independent
// references in double: the true distance lies within the answer's bound, Embree's BVH finds the
// same closest triangle as testing every one, and the answer's (u, v) is a surface point within the
// bound of the mesh point.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/mesh_distance.h"
#include "test_suites.h"
#include "tests/queries/distance/distance_reference.h"

namespace {

std::vector<glm::dvec3> random_points(models::Random& rng, int n, double half) {
  std::vector<glm::dvec3> out;
  for (int k = 0; k < n; ++k) out.emplace_back(rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(-half, half));
  return out;
}

}  // namespace

TEST_CASE("mesh distance: random surfaces, the reference within the bound, the BVH equal to every triangle") {
  double worst = 0.0;
  int cases = 0;
  for (uint64_t seed = 0; seed < 10; ++seed) {
    nurbs::TrimmedSurface face;
    face.surface = models::random_surface(seed + 40, 1 + int(seed % 4), 1 + int(seed / 4 % 3), seed % 2 == 1);
    const double size = nurbs::control_box(face.surface).diagonal(), eps = 2e-3 * size;
    const queries::MeshDistance mesh({face}, eps);
    REQUIRE(mesh.tessellation().failures.empty());
    models::Random rng(seed);
    const std::vector<glm::dvec3> points = random_points(rng, 6, 1.5);
    const std::vector<queries::PointDistance> got = mesh.query(points);
    for (size_t k = 0; k < points.size(); ++k) {
      CAPTURE(seed);
      CAPTURE(k);
      const queries::PointDistance& r = got[k];
      REQUIRE(r.found);
      CHECK(r.bound == eps);
      const queries::PointDistance all = mesh.brute_force(points[k]);
      CHECK(r.distance == all.distance);
      const test::Reference ref = test::reference(face.surface, points[k], r.uv);
      CHECK(std::abs(ref.distance - r.distance) <= r.bound);
      // The answer's (u, v) is a surface point within the bound of the mesh point.
      CHECK(glm::length(nurbs::surface_point(face.surface, r.uv.x, r.uv.y) - r.point) <= r.bound);
      worst = std::max(worst, std::abs(ref.distance - r.distance) / r.bound);
      ++cases;
    }
  }
  MESSAGE(cases << " points: |distance - reference| <= " << worst << " bound");
}

TEST_CASE("mesh distance: trimmed faces, no material sample nearer than the lower bound") {
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const nurbs::TrimmedSurface face = models::random_trimmed_surface(seed);
    const double size = nurbs::control_box(face.surface).diagonal(), eps = 1e-3 * size;
    const queries::MeshDistance mesh({face}, eps);
    REQUIRE(mesh.tessellation().failures.empty());
    const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 1e-9 * nurbs::surface_domain_u(face.surface).width());
    const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
    models::Random rng(seed + 5);
    const std::vector<glm::dvec3> points = random_points(rng, 3, 1.5);
    const std::vector<queries::PointDistance> got = mesh.query(points);
    for (size_t k = 0; k < points.size(); ++k) {
      CAPTURE(seed);
      CAPTURE(k);
      REQUIRE(got[k].found);
      double sampled = 1e300;
      for (int j = 0; j <= 80; ++j)
        for (int i = 0; i <= 80; ++i) {
          const glm::dvec2 uv(du.min + du.width() * i / 80, dv.min + dv.width() * j / 80);
          if (nurbs::is_material(trim, uv))
            sampled = std::min(sampled, glm::length(nurbs::surface_point(face.surface, uv.x, uv.y) - points[k]));
        }
      CHECK(sampled >= got[k].distance - got[k].bound);
      CHECK(got[k].distance == mesh.brute_force(points[k]).distance);
    }
  }
}

TEST_CASE("mesh distance: an exact sphere, the distance | |p| - r | inside and outside") {
  nurbs::TrimmedSurface s;
  s.surface = models::rational_sphere(2.0);
  const double eps = 1e-3;
  const queries::MeshDistance mesh({s}, eps);
  REQUIRE(mesh.tessellation().failures.empty());
  models::Random rng(3);
  std::vector<glm::dvec3> points = random_points(rng, 200, 4.0);
  points.push_back(glm::dvec3(0.0));  // every triangle equally near, up to eps
  const std::vector<queries::PointDistance> got = mesh.query(points);
  double worst = 0.0;
  for (size_t k = 0; k < points.size(); ++k) {
    CAPTURE(k);
    const double truth = std::abs(glm::length(points[k]) - 2.0);
    REQUIRE(got[k].found);
    CHECK(std::abs(got[k].distance - truth) <= got[k].bound);
    worst = std::max(worst, std::abs(got[k].distance - truth) / got[k].bound);
  }
  MESSAGE(mesh.triangles() << " triangles at eps " << eps << ": |distance - truth| <= " << worst << " bound");
  // The same answers whatever the other points and their order: the centre, where every triangle
  // lies within eps of the nearest, among them; of equals the lowest index, as every triangle tested.
  std::vector<glm::dvec3> reversed(points.rbegin(), points.rend());
  reversed.resize(points.size() / 2);
  const std::vector<queries::PointDistance> again = mesh.query(reversed);
  for (size_t k = 0; k < again.size(); ++k) {
    const queries::PointDistance& a = again[k];
    const queries::PointDistance& b = got[points.size() - 1 - k];
    CHECK(a.distance == b.distance);
    CHECK(a.point == b.point);
    CHECK(a.uv == b.uv);
  }
  CHECK(got.back().point == mesh.brute_force(points.back()).point);
}

TEST_CASE("mesh distance, built for rays: a ray through the tube of a long boundary edge meets it") {
  // A 300 x 10 rectangle meshed in a few long triangles: rays along its 300-long edge at shallow
  // angles, each passing a point within 1.5 eps of the edge outside the face, start beyond the
  // rectangle's end: each meets the edge's tube (radius 2 eps), or a shell, before that point.
  nurbs::TrimmedSurface face;
  face.surface = models::bilinear_patch({glm::dvec3(0, 0, 0), glm::dvec3(300, 0, 0), glm::dvec3(0, 10, 0),
                                         glm::dvec3(300, 10, 0)});
  const std::vector<nurbs::TrimmedSurface> faces{face};
  const double eps = 1e-4 * 300.0;
  const queries::MeshDistance mesh(faces, eps, 0, nurbs::tess::TessellateOptions{}.max_cells, true);
  models::Random rng(31);
  int rays = 0, missed = 0;
  for (int k = 0; k < 4000; ++k) {
    const double phi = rng.uniform(-0.5 * M_PI, 0.5 * M_PI), rho = rng.uniform(0.0, 1.5 * eps);
    const glm::dvec3 q(rng.uniform(20.0, 280.0), -rho * std::cos(phi), rho * std::sin(phi));
    const double tilt = std::pow(10.0, rng.uniform(-4.0, -2.0)), turn = rng.uniform(0.0, 2.0 * M_PI);
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, tilt * std::cos(turn), tilt * std::sin(turn)));
    const double s = (q.x + 50.0) / d.x;
    const queries::MeshRayHit h = mesh.first_hit(q - s * d, d, 0.0, 3.4e38);
    ++rays;
    missed += !(h.boundary || h.triangle >= 0) || h.t > s + 1e-6;
  }
  CAPTURE(rays);
  CHECK(missed == 0);
}
