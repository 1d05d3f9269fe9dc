// The triangle-triangle distance of the clearance query's CPU end (queries/distance/triangle_distance.cpp)
// against an independent reference: the distance from a point of A to triangle B is convex in the
// point, so its minimum over A is found by nested ternary searches over A's barycentric coordinates.
// Random pairs apart, stacked nearly parallel (the refinement's usual case), crossing and touching.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/random_surfaces.h"
#include "queries/distance/clearance.h"
#include "queries/distance/point_distance.h"

namespace {

/// Least distance from triangle a to triangle b by nested ternary searches (s along a0->a1, then t
/// along the remaining side), each over a convex function.
double reference_distance(const glm::dvec3 a[3], const glm::dvec3 b[3]) {
  auto to_b = [&](double s, double t) {
    const glm::dvec3 p = a[0] + s * (a[1] - a[0]) + t * (a[2] - a[0]);
    glm::dvec3 w;
    return glm::length(queries::closest_on_triangle(p, b[0], b[1], b[2], w) - p);
  };
  auto ternary = [](double lo, double hi, auto&& f) {
    for (int k = 0; k < 64; ++k) {  // (2/3)^64: 5e-12 of the range
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (f(m1) < f(m2)) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    return f(0.5 * (lo + hi));
  };
  return ternary(0.0, 1.0, [&](double s) { return ternary(0.0, 1.0 - s, [&](double t) { return to_b(s, t); }); });
}

glm::dvec3 random_point(models::Random& rng, double r) {
  return {rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-r, r)};
}

}  // namespace

TEST_CASE("triangle distance: equals a convex search over one triangle, apart, stacked, crossing") {
  models::Random rng(41);
  int checked = 0, zero = 0;
  for (int n = 0; n < 600; ++n) {
    const int kind = n % 3;
    glm::dvec3 a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = random_point(rng, 1.0);
    if (kind == 0) {  // anywhere, mostly apart
      const glm::dvec3 shift = random_point(rng, 1.5);
      for (int k = 0; k < 3; ++k) b[k] = shift + random_point(rng, 1.0);
    } else if (kind == 1) {  // nearly parallel, one over the other at a small height h (1 +- 0.5)
      const glm::dvec3 e1 = glm::normalize(a[1] - a[0]), n0 = glm::normalize(glm::cross(a[1] - a[0], a[2] - a[0]));
      const glm::dvec3 e2 = glm::cross(n0, e1);
      const double h = std::pow(10.0, rng.uniform(-6.0, -1.0));
      for (int k = 0; k < 3; ++k)
        b[k] = a[k] + h * rng.uniform(0.5, 1.5) * n0 + 0.3 * (rng.uniform(-1, 1) * e1 + rng.uniform(-1, 1) * e2);
    } else {  // through each other: b's first edge pierces a's plane inside a
      const glm::dvec3 in = (a[0] + a[1] + a[2]) / 3.0, n0 = glm::normalize(glm::cross(a[1] - a[0], a[2] - a[0]));
      b[0] = in + 0.5 * n0;
      b[1] = in - 0.5 * n0 + 0.1 * random_point(rng, 1.0);
      b[2] = b[0] + random_point(rng, 1.0);
    }
    glm::dvec3 pa, pb, wa, wb;
    const double d = queries::triangle_distance(a, b, pa, pb, wa, wb);
    const double ref = std::min(reference_distance(a, b), reference_distance(b, a));
    CAPTURE(n);
    CHECK(std::abs(d - ref) <= 1e-9);
    CHECK(glm::length(pa - pb) == doctest::Approx(d).epsilon(1e-12));
    // The witnesses lie on their triangles (barycentric weights of sum 1, none negative).
    CHECK(glm::length(wa.x * a[0] + wa.y * a[1] + wa.z * a[2] - pa) <= 1e-12);
    CHECK(glm::length(wb.x * b[0] + wb.y * b[1] + wb.z * b[2] - pb) <= 1e-12);
    CHECK(std::min({wa.x, wa.y, wa.z, wb.x, wb.y, wb.z}) >= -1e-12);
    zero += d == 0.0;
    ++checked;
  }
  CHECK(zero >= 150);  // the crossing pairs
  MESSAGE(checked << " triangle pairs, " << zero << " crossing");
}

// Segments and triangles in one plane that is not a coordinate plane (rounding leaves the crossing
// test's determinant a little off zero): never a crossing unless they meet (flat faces of a part and
// of its copy moved in their plane gave distance 0 between points 333 apart).
TEST_CASE("triangle distance: coplanar segments and triangles apart are not crossings") {
  double s;
  glm::dvec3 w;
  // Random coplanar pairs in a tilted plane, apart or overlapping, against the convex search.
  models::Random rng(43);
  const glm::dvec3 e1 = glm::normalize(glm::dvec3(1, 0.3, -0.7)), e2 = glm::normalize(glm::cross(e1, {0.2, 1, 0.4}));
  auto in_plane = [&](double r, double cx) { return (cx + rng.uniform(-r, r)) * e1 + rng.uniform(-r, r) * e2; };
  int checked = 0;
  for (int n = 0; n < 300; ++n) {
    const double apart = n % 2 == 0 ? rng.uniform(2.5, 400.0) : 0.0;
    glm::dvec3 a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = in_plane(1.0, 0.0), b[k] = in_plane(1.0, apart);
    glm::dvec3 pa, pb, wa, wb;
    const double d = queries::triangle_distance(a, b, pa, pb, wa, wb);
    const double ref = std::min(reference_distance(a, b), reference_distance(b, a));
    CAPTURE(n);
    CHECK(std::abs(d - ref) <= 1e-9 * std::max(1.0, apart));
    CHECK(glm::length(pa - pb) == doctest::Approx(d).epsilon(1e-12));
    const double ds = queries::segment_triangle_distance(a[0], a[1], b, s, w);
    CHECK(glm::length(a[0] + s * (a[1] - a[0]) - (w.x * b[0] + w.y * b[1] + w.z * b[2])) ==
          doctest::Approx(ds).epsilon(1e-12));
    ++checked;
  }
  MESSAGE(checked << " coplanar pairs");
}
