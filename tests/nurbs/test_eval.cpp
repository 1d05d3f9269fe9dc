// CPU evaluation against closed forms (rational circle, sphere, torus) and finite differences.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/bezier_eval.h"
#include "nurbs/curve_eval.h"
#include "nurbs/surface_eval.h"
#include "nurbs/validate.h"

TEST_CASE("rational quarter circle has radius 1 and the right derivatives") {
  const auto c = models::rational_quarter_circle(1.0);
  REQUIRE(nurbs::validate(c).empty());
  for (int s = 0; s <= 100; ++s) {
    const double u = s / 100.0;
    const auto d = nurbs::curve_derivatives(c, u, 2);
    // 1e-12: the closed-form tolerance of the tests; roundoff is ~1e-16.
    CHECK(std::abs(glm::length(d[0]) - 1.0) < 1e-12);
    // |C|^2 = 1 implies C . C' = 0 and C . C'' + |C'|^2 = 0.
    CHECK(std::abs(glm::dot(d[0], d[1])) < 1e-12);
    CHECK(std::abs(glm::dot(d[0], d[2]) + glm::dot(d[1], d[1])) < 1e-11);
  }
  // Ends: C(0) = (1,0,0), C(1) = (0,1,0) (clamped); C'(0) = 2 (w1/w0) (P1 - P0) = (0, sqrt 2, 0).
  CHECK(glm::length(nurbs::curve_point(c, 1.0) - glm::dvec3(0, 1, 0)) < 1e-15);
  const auto d0 = nurbs::curve_derivatives(c, 0.0, 1);
  CHECK(glm::length(d0[1] - glm::dvec3(0, std::sqrt(2.0), 0)) < 1e-14);
}

TEST_CASE("2D circles have their radius") {
  for (bool ccw : {true, false}) {
    const auto c = models::rational_circle_2d({0.25, -3.0}, 0.7, ccw);
    REQUIRE(nurbs::validate(c).empty());
    for (int s = 0; s <= 400; ++s) {
      const glm::dvec2 p = nurbs::curve_point(c, s / 400.0);
      CHECK(std::abs(glm::length(p - glm::dvec2(0.25, -3.0)) - 0.7) < 1e-12);  // closed form, roundoff only
    }
  }
}

TEST_CASE("sphere, torus and cylinder match their closed forms") {
  const glm::dvec3 centre(1.5, -2.0, 0.25);
  const auto sphere = models::rational_sphere(2.0, centre);
  const auto torus = models::rational_torus(3.0, 0.75, centre);
  const auto cyl = models::rational_cylinder(1.25, 4.0, centre);
  REQUIRE(nurbs::validate(sphere).empty());
  REQUIRE(nurbs::validate(torus).empty());
  REQUIRE(nurbs::validate(cyl).empty());
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      const double u = i / 40.0, v = j / 40.0;
      // 1e-12 absolute on radii of 1-3: the closed-form tolerance of the tests (roundoff ~1e-15).
      const glm::dvec3 ps = nurbs::surface_point(sphere, u, v);
      CHECK(std::abs(glm::length(ps - centre) - 2.0) < 1e-12);
      const glm::dvec3 pt = nurbs::surface_point(torus, u, v) - centre;
      const glm::dvec3 tube_centre = 3.0 * glm::normalize(glm::dvec3(pt.x, pt.y, 0.0));
      CHECK(std::abs(glm::length(pt - tube_centre) - 0.75) < 1e-12);
      const glm::dvec3 pc = nurbs::surface_point(cyl, u, v) - centre;
      CHECK(std::abs(std::hypot(pc.x, pc.y) - 1.25) < 1e-12);
      CHECK(std::abs(pc.z - 4.0 * v) < 1e-12);  // degree 1 along the axis: z is linear in v
      // Outward normals: the sphere normal is the radial direction (also at the poles, by the limit).
      const glm::dvec3 ns = nurbs::surface_normal(sphere, u, v);
      CHECK(glm::length(ns - glm::normalize(ps - centre)) < 1e-9);  // 1e-9: pole limit uses Suv, ~1e-12 elsewhere
      const glm::dvec3 nt = nurbs::surface_normal(torus, u, v);
      CHECK(glm::length(nt - glm::normalize(pt - tube_centre)) < 1e-12);
    }
  }
}

namespace {

/// Max-norm of the difference scaled by the magnitude of the reference.
double rel_err(const glm::dvec3& a, const glm::dvec3& ref, double scale) {
  const glm::dvec3 d = glm::abs(a - ref);
  return std::max({d.x, d.y, d.z}) / scale;
}

}  // namespace

TEST_CASE("surface derivatives agree with central finite differences") {
  // Random surfaces of degrees 1-5, rational and not. Central differences with step h have error
  // h^2/6 |S'''| + eps |S| / h; h = 1e-5 (first order) and 1e-4 (second order, from analytic first
  // derivatives). Weights up to 25:1 make |S''''| / |S''| reach ~1e3 on short spans, so the
  // truncation error is up to ~1e-5 relative: 1e-4 relative to the derivative scale.
  int checked = 0;
  for (int seed = 0; seed < 60; ++seed) {
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed), p, q, seed % 2 == 1);
    REQUIRE(nurbs::validate(s).empty());
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    for (int k = 0; k < 10; ++k) {
      // Points inside spans, away from knots where second derivatives jump.
      const double u = du.min + du.width() * (0.05 + 0.9 * ((k * 7 + seed) % 10 + 0.37) / 10.0);
      const double v = dv.min + dv.width() * (0.05 + 0.9 * ((k * 3 + seed) % 10 + 0.61) / 10.0);
      const double h1 = 1e-5, h2 = 1e-4;
      bool near_knot = false;
      for (double x : s.knots_u) near_knot |= std::abs(x - u) < 2 * h2;
      for (double x : s.knots_v) near_knot |= std::abs(x - v) < 2 * h2;
      if (near_knot) continue;
      const auto d = nurbs::surface_derivatives(s, u, v);
      auto S = [&](double a, double b) { return nurbs::surface_point(s, a, b); };
      auto D = [&](double a, double b) { return nurbs::surface_derivatives(s, a, b); };
      const double scale = 1.0 + glm::length(d.su) + glm::length(d.sv) + glm::length(d.suu) + glm::length(d.svv);
      CHECK(rel_err(d.s, S(u, v), 1.0) < 1e-14);
      CHECK(rel_err(d.su, (S(u + h1, v) - S(u - h1, v)) / (2 * h1), scale) < 1e-4);
      CHECK(rel_err(d.sv, (S(u, v + h1) - S(u, v - h1)) / (2 * h1), scale) < 1e-4);
      CHECK(rel_err(d.suu, (D(u + h2, v).su - D(u - h2, v).su) / (2 * h2), scale) < 1e-4);
      CHECK(rel_err(d.svv, (D(u, v + h2).sv - D(u, v - h2).sv) / (2 * h2), scale) < 1e-4);
      CHECK(rel_err(d.suv, (D(u + h2, v).sv - D(u - h2, v).sv) / (2 * h2), scale) < 1e-4);
      ++checked;
    }
  }
  CHECK(checked > 300);
}

TEST_CASE("surface tangents are surface derivatives' first order, bit for bit") {
  // surface_tangents serves Newton steps; it must not round differently from the full evaluation,
  // at knots, at the domain's ends and inside spans, for every degree and rational or not.
  int differ = 0, checked = 0;
  for (int seed = 0; seed < 40; ++seed) {
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed + 100), p, q, seed % 2 == 0);
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    for (int k = 0; k <= 12; ++k)
      for (int l = 0; l <= 12; ++l) {
        const double u = du.min + du.width() * k / 12.0, v = dv.min + dv.width() * (l + 0.3 * (k % 2)) / 12.3;
        const auto d = nurbs::surface_derivatives(s, u, v);
        const auto t = nurbs::surface_tangents(s, u, v);
        differ += !(d.s == t.s && d.su == t.su && d.sv == t.sv);
        ++checked;
      }
  }
  CHECK(checked == 40 * 169);
  CHECK(differ == 0);
}

TEST_CASE("Bezier form: the surface's S, Su, Sv up to rounding, at knots, ends and inside spans") {
  double worst = 0.0;
  int checked = 0;
  for (int seed = 0; seed < 50; ++seed) {
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed + 300), p, q, seed % 2 == 0);
    const nurbs::BezierForm form(s);
    REQUIRE_FALSE(form.empty());
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    std::vector<double> us{du.min - 0.1, du.max + 0.1}, vs{dv.min, dv.max};
    for (double k : s.knots_u) us.push_back(k);  // knots: the span on the right, as find_span
    for (double k : s.knots_v) vs.push_back(k);
    for (int k = 0; k <= 16; ++k) us.push_back(du.min + du.width() * k / 16.3), vs.push_back(dv.min + dv.width() * k / 15.7);
    for (double u : us)
      for (double v : vs) {
        const auto a = nurbs::surface_tangents(s, u, v);
        const auto b = form.tangents(u, v);
        const double scale = 1.0 + glm::length(a.s) + glm::length(a.su) + glm::length(a.sv);
        worst = std::max({worst, rel_err(a.s, b.s, scale), rel_err(a.su, b.su, scale), rel_err(a.sv, b.sv, scale)});
        ++checked;
      }
  }
  CAPTURE(worst);
  CHECK(checked > 10000);
  CHECK(worst < 1e-12);
  // Degrees past the form's limit are left to the surface.
  CHECK(nurbs::BezierForm(models::random_surface(1, nurbs::BezierForm::kMaxDegree + 1, 2, false)).empty());
}

TEST_CASE("curve derivatives agree with finite differences (2D rational, degree 3)") {
  nurbs::Curve2 c;
  c.degree = 3;
  c.knots = {0, 0, 0, 0, 0.3, 0.55, 1, 1, 1, 1};
  c.points = {{0, 0}, {1, 2}, {2, -1}, {3, 3}, {4, 0}, {5, 1}};
  c.weights = {1, 0.5, 2, 0.7, 1.5, 1};
  REQUIRE(nurbs::validate(c).empty());
  for (double u : {0.1, 0.2, 0.4, 0.6, 0.8, 0.95}) {
    const auto d = nurbs::curve_derivatives(c, u, 2);
    const double h = 1e-5;  // see the surface test for the error budget
    const auto dp = nurbs::curve_derivatives(c, u + h, 1), dm = nurbs::curve_derivatives(c, u - h, 1);
    CHECK(glm::length(d[1] - (dp[0] - dm[0]) / (2 * h)) < 1e-5 * (1 + glm::length(d[1])));
    CHECK(glm::length(d[2] - (dp[1] - dm[1]) / (2 * h)) < 1e-4 * (1 + glm::length(d[2])));
  }
}

TEST_CASE("speed bounds hold |Su| and |Sv| everywhere, for plain and rational surfaces") {
  int tight = 0;  // surfaces whose largest sampled speed comes within a factor 2 of the bound
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const bool rational = seed % 2 == 0;
    const nurbs::Surface s = models::random_surface(seed, 1 + int(seed % 4), 1 + int((seed / 4) % 4), rational);
    const glm::dvec2 bound = nurbs::speed_bounds(s);
    REQUIRE(std::isfinite(bound.x));
    REQUIRE(std::isfinite(bound.y));
    const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    glm::dvec2 largest(0.0);
    for (int i = 0; i <= 24; ++i)
      for (int j = 0; j <= 24; ++j) {
        const nurbs::SurfaceTangents t =
            nurbs::surface_tangents(s, du.min + du.width() * i / 24.0, dv.min + dv.width() * j / 24.0);
        largest = glm::max(largest, glm::dvec2(glm::length(t.su), glm::length(t.sv)));
      }
    CAPTURE(seed);
    CHECK(largest.x <= bound.x * (1.0 + 1e-12));
    CHECK(largest.y <= bound.y * (1.0 + 1e-12));
    tight += !rational && largest.x > 0.5 * bound.x;
  }
  CHECK(tight > 0);  // the plain bound is the control polygon's: reached on some nets
}
