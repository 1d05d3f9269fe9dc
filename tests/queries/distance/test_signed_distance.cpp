// Signed distances (queries/distance/side_test.h, PointQueryOptions::signed_distance): negative inside
// the model's closed solids. On a closed sphere against |p| - r: the sides from the normal where it
// decides, from the rays where it does not (forced here by marking the answers as on a trim edge),
// a reversed face turning every side, and the refusal of a model whose body is not stated closed.
// On two overlapping balls, against the union's exact signed distance: the part is the union of
// its solids.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "queries/distance/point_query.h"
#include "queries/distance/side_test.h"
#include "tests/gpgpu/gl_fixture.h"

namespace {

constexpr double kRadius = 10.0;

/// Points at radii from 0.2 r to 2 r in random directions (fixed seed).
std::vector<glm::dvec3> points_in_and_out(size_t n) {
  std::mt19937 rng(17);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> radius(0.2 * kRadius, 2.0 * kRadius);
  std::vector<glm::dvec3> out;
  for (size_t k = 0; k < n; ++k) out.push_back(glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))) * radius(rng));
  return out;
}

queries::PointQueryResult signed_query(const nurbs::LoadedModel& model, std::span<const glm::dvec3> points) {
  queries::PointQueryOptions o;
  o.tolerance = 1e-5;
  o.cache = false;
  o.signed_distance = true;
  queries::PointQuery q(test::gpu(), model, o);
  return q.query(points);
}

}  // namespace

TEST_CASE("signed distance: negative inside a closed sphere, within the answer's bound of |p| - r") {
  const auto points = points_in_and_out(500);
  const queries::PointQueryResult r = signed_query(models::loaded_sphere(kRadius), points);
  REQUIRE(r.signed_distance.size() == points.size());
  CHECK(r.failure().empty());
  size_t inside = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    CAPTURE(k);
    const double exact = glm::length(points[k]) - kRadius;
    CHECK(std::abs(r.signed_distance[k] - exact) <= r.answers[k].bound);
    inside += r.signed_distance[k] < 0.0;
  }
  CHECK(inside > 100);  // the radii spread over both sides
  CHECK(r.sides.by_normal + r.sides.by_rays == points.size());
  CHECK(r.sides.unsure == 0);
}

TEST_CASE("signed distance: where the normal cannot tell, the rays find the same sides") {
  const nurbs::LoadedModel sphere = models::loaded_sphere(kRadius);
  const auto points = points_in_and_out(300);
  queries::PointQueryOptions o;
  o.tolerance = 1e-5;
  o.cache = false;
  queries::PointQuery q(test::gpu(), sphere, o);
  const queries::PointQueryResult r = q.query(points);
  std::vector<queries::PointDistance> answers = r.answers;
  for (queries::PointDistance& a : answers) a.on_trim_edge = true;  // the normal then abstains
  queries::SideTest test(q.faces());
  const std::vector<queries::SideAnswer> sides = test.sides(points, answers, r.normals);
  CHECK(test.figures().by_normal == 0);
  CHECK(test.figures().by_rays == points.size());
  for (size_t k = 0; k < points.size(); ++k) {
    CAPTURE(k);
    CHECK(sides[k].side == (glm::length(points[k]) < kRadius ? queries::Side::Inside : queries::Side::Outside));
  }
}

TEST_CASE("signed distance: a face stated reversed turns every side") {
  nurbs::LoadedModel sphere = models::loaded_sphere(kRadius);
  sphere.model.bodies[0].faces[0].reversed = true;  // its outward normal points to the centre
  const auto points = points_in_and_out(100);
  const queries::PointQueryResult r = signed_query(sphere, points);
  for (size_t k = 0; k < points.size(); ++k) {
    CAPTURE(k);
    CHECK(std::abs(r.signed_distance[k] + glm::length(points[k]) - kRadius) <= r.answers[k].bound);
  }
}

TEST_CASE("signed distance: refused for a body the file does not state closed") {
  nurbs::LoadedModel sphere = models::loaded_sphere(kRadius);
  sphere.model.bodies[0].closed = false;
  const std::vector<glm::dvec3> one{{0.0, 0.0, 25.0}};
  CHECK_THROWS_AS(signed_query(sphere, one), nurbs::RequestError);
}

namespace {

/// The exact signed distance to the union of two balls of radius r about 0 and c: outside, the
/// nearer sphere; inside, the nearest point of either sphere's cap outside the other ball (the
/// point the centre's ray meets on the sphere when that lies on the cap, else the circle where the
/// spheres meet).
double union_of_balls(const glm::dvec3& p, const glm::dvec3& c, double r) {
  const double a = glm::length(p), b = glm::length(p - c);
  if (a >= r && b >= r) return std::min(a - r, b - r);
  double best = std::numeric_limits<double>::infinity();
  if (a > 0.0 && glm::length(p * (r / a) - c) >= r) best = std::min(best, std::abs(a - r));
  if (b > 0.0 && glm::length(c + (p - c) * (r / b)) >= r) best = std::min(best, std::abs(b - r));
  const glm::dvec3 axis = glm::normalize(c);
  const double h = 0.5 * glm::length(c), ring = std::sqrt(r * r - h * h);
  const double along = glm::dot(p, axis) - h, across = glm::length(p - glm::dot(p, axis) * axis);
  best = std::min(best, std::hypot(along, across - ring));
  return -best;
}

}  // namespace

TEST_CASE("signed distance: a part of two overlapping solids is their union") {
  // Two balls of radius 10, 12 apart: they overlap in a lens 8 wide. A point in one ball whose
  // rays first enter the other, or whose nearest face is the other's (inside the first), is inside.
  nurbs::LoadedModel two = models::loaded_sphere(kRadius);
  const glm::dvec3 c(12.0, 0.0, 0.0);
  two.model.bodies.push_back(two.model.bodies[0]);
  two.model.bodies[1].transform = glm::translate(glm::dmat4(1.0), c);
  two.report = nurbs::model_report(two.model);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-11.0, 23.0), yz(-11.0, 11.0);
  std::vector<glm::dvec3> points;
  for (int k = 0; k < 2000; ++k) points.push_back({x(rng), yz(rng), yz(rng)});
  const queries::PointQueryResult r = signed_query(two, points);
  size_t certified = 0, inside = 0, hidden = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    CAPTURE(k);
    CAPTURE(points[k]);
    const double exact = union_of_balls(points[k], c, kRadius);
    if (!r.reasons[k].empty()) {
      // Uncertified only where the face point found lies in or on the other ball, from inside.
      CHECK(exact < r.answers[k].bound);
      ++hidden;
      continue;
    }
    ++certified;
    inside += exact < 0.0;
    CHECK(std::abs(r.signed_distance[k] - exact) <= r.answers[k].bound);
  }
  CHECK(r.sides.hidden == hidden);
  CHECK(hidden > 50);          // the lens and the faces inside the other ball are met
  CHECK(inside > 300);         // and the certified answers inside the part are many
  CHECK(certified > 1000);
}
