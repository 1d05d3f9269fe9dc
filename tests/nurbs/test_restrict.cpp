// Restriction of curves and surfaces to a sub-domain: same points at the same parameters, the new
// domain is the cut interval, the result is valid; also at knots, on unclamped and rational input.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "models/random_surfaces.h"
#include "nurbs/curve_eval.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"
#include "nurbs/validate.h"

TEST_CASE("restrict: random surfaces restricted to random sub-rectangles keep their points") {
  models::Random rng(404);
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const nurbs::Surface s = models::random_surface(seed, 1 + int(seed % 4), 1 + int(seed / 4 % 4), seed % 3 == 0);
    const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    // Cuts anywhere, sometimes exactly on a knot or at the domain ends.
    double a = du.min + du.width() * rng.uniform(0.0, 0.45), b = du.min + du.width() * rng.uniform(0.55, 1.0);
    if (seed % 5 == 0) a = s.knots_u[size_t(s.degree_u) + 1 < s.knots_u.size() ? size_t(s.degree_u) + 1 : 0];
    if (seed % 7 == 0) b = du.max;
    if (!(a < b)) a = du.min;
    const double c = dv.min + dv.width() * rng.uniform(0.0, 0.45), d = dv.min + dv.width() * rng.uniform(0.55, 1.0);
    const nurbs::Surface r = nurbs::restrict_surface(s, {a, b}, {c, d});
    CAPTURE(seed);
    REQUIRE(nurbs::validate(r).empty());
    CHECK(nurbs::surface_domain_u(r).min == a);
    CHECK(nurbs::surface_domain_u(r).max == b);
    CHECK(nurbs::surface_domain_v(r).min == c);
    CHECK(nurbs::surface_domain_v(r).max == d);
    double worst = 0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) {
        const double u = a + (b - a) * i / 8, v = c + (d - c) * j / 8;
        worst = std::max(worst, glm::length(nurbs::surface_point(r, u, v) - nurbs::surface_point(s, u, v)));
      }
    CHECK(worst < 1e-12 * 10);  // control points in [-1,1]^3 (weights up to 5): a few roundings of size ~1
  }
}

TEST_CASE("restrict: a 2D rational curve cut twice, and cuts outside the domain are clipped") {
  nurbs::Curve2 c;
  c.degree = 2;
  c.knots = {0, 0, 0, 0.5, 1, 1, 1};
  c.points = {{0, 0}, {1, 2}, {2, -1}, {3, 0}};
  c.weights = {1, 2, 0.5, 1};
  const nurbs::Curve2 r = nurbs::restrict_curve(c, 0.2, 0.7);
  CHECK(nurbs::validate(r).empty());
  CHECK(r.knots.front() == 0.2);
  CHECK(r.knots.back() == 0.7);
  for (double u : {0.2, 0.3, 0.5, 0.6, 0.7})
    CHECK(glm::length(nurbs::curve_point(r, u) - nurbs::curve_point(c, u)) < 1e-14);
  const nurbs::Curve2 whole = nurbs::restrict_curve(c, -5.0, 5.0);
  CHECK(whole.knots == c.knots);
  CHECK(whole.points == c.points);
}
