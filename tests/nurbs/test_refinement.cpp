// Knot insertion (A5.1), degree elevation (A5.9), clamping and Bézier extraction leave the geometry
// unchanged. Sampled comparison at 1e-12 relative to the control-net size (the closed-form tolerance of the tests;
// each algorithm is a short chain of convex combinations, so roundoff is ~1e-15).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/bezier_extraction.h"
#include "nurbs/curve_eval.h"
#include "nurbs/degree_elevation.h"
#include "nurbs/knot_insertion.h"
#include "nurbs/surface_eval.h"
#include "nurbs/validate.h"

namespace {

constexpr double kTol = 1e-12;  // relative, see the file comment

/// Max distance between two surfaces over a 23 x 19 parameter grid of `a`'s domain (odd sizes so
/// samples fall on and off knots).
double surface_gap(const nurbs::Surface& a, const nurbs::Surface& b) {
  const auto du = nurbs::surface_domain_u(a), dv = nurbs::surface_domain_v(a);
  double gap = 0.0;
  for (int i = 0; i <= 22; ++i) {
    for (int j = 0; j <= 18; ++j) {
      const double u = du.min + du.width() * i / 22, v = dv.min + dv.width() * j / 18;
      gap = std::max(gap, glm::length(nurbs::surface_point(a, u, v) - nurbs::surface_point(b, u, v)));
    }
  }
  return gap;
}

nurbs::Curve3 random_curve(std::uint64_t seed, int degree, bool rational) {
  // Row 0 of a random surface is a random curve with the same knot/weight variety.
  const auto s = models::random_surface(seed, degree, 1, rational);
  nurbs::Curve3 c;
  c.degree = degree;
  c.knots = s.knots_u;
  for (int i = 0; i < s.count_u; ++i) {
    c.points.push_back(s.point(i, 0));
    if (rational) c.weights.push_back(s.weight(i, 0));
  }
  return c;
}

double curve_gap(const nurbs::Curve3& a, const nurbs::Curve3& b) {
  const auto d = nurbs::curve_domain(a);
  double gap = 0.0;
  for (int i = 0; i <= 101; ++i) {
    const double u = d.min + d.width() * i / 101;
    gap = std::max(gap, glm::length(nurbs::curve_point(a, u) - nurbs::curve_point(b, u)));
  }
  return gap;
}

}  // namespace

TEST_CASE("curve knot insertion, clamping, elevation and extraction preserve the curve") {
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const int p = 1 + static_cast<int>(seed % 5);
    const auto c = random_curve(seed, p, seed % 2 == 1);
    REQUIRE(nurbs::validate(c).empty());
    CAPTURE(seed);
    const auto d = nurbs::curve_domain(c);
    // Insert twice at a fresh value, and once at an existing interior knot if any.
    auto ci = nurbs::insert_knot(c, d.min + 0.377 * d.width(), 2);
    CHECK(nurbs::validate(ci).empty());
    CHECK(ci.points.size() == c.points.size() + static_cast<size_t>(std::min(2, p)));
    CHECK(curve_gap(c, ci) < kTol);
    const auto h = nurbs::clamp_curve(nurbs::to_homogeneous(c));
    const auto cc = nurbs::from_homogeneous<3>(h, c.rational());
    CHECK(nurbs::is_clamped(cc.knots, p));
    CHECK(nurbs::validate(cc).empty());
    CHECK(curve_gap(c, cc) < kTol);
    for (int t = 1; t <= 2; ++t) {
      const auto ce = nurbs::elevate_degree(c, t);
      CHECK(ce.degree == p + t);
      CHECK(nurbs::validate(ce).empty());
      CHECK(curve_gap(c, ce) < kTol);
    }
    const auto segs = nurbs::extract_bezier_segments(c);
    for (const auto& seg : segs) {
      CHECK(seg.curve.points.size() == static_cast<size_t>(p) + 1);
      for (int k = 0; k <= 7; ++k) {
        const double u = seg.range.min + seg.range.width() * k / 7;
        CHECK(glm::length(nurbs::curve_point(seg.curve, u) - nurbs::curve_point(c, u)) < kTol);
      }
    }
  }
}

TEST_CASE("degree elevation: control point counts (each distinct interior knot gains t)") {
  // Clamped cubic with interior knots 0.3 (simple) and 0.6 (double): n + 1 = 6 points, 2 distinct
  // interior knots, 3 spans. Elevating by t adds t per span: 6 + 3 t points; knots grow by t per
  // distinct value (4 values).
  nurbs::Curve2 c;
  c.degree = 3;
  c.knots = {0, 0, 0, 0, 0.3, 0.6, 0.6, 1, 1, 1, 1};
  c.points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}, {5, 1}, {6, 0}};
  REQUIRE(nurbs::validate(c).empty());
  const auto e = nurbs::elevate_degree(c, 2);
  CHECK(e.degree == 5);
  CHECK(e.points.size() == 7 + 3 * 2);
  CHECK(e.knots.size() == c.knots.size() + 4 * 2);
  CHECK(nurbs::knot_multiplicity(e.knots, 0.6) == 4);
  CHECK(nurbs::validate(e).empty());
}

TEST_CASE("surface knot insertion, elevation and Bézier patches preserve the surface") {
  for (std::uint64_t seed = 0; seed < 30; ++seed) {
    const int p = 1 + static_cast<int>(seed % 4), q = 1 + static_cast<int>((seed / 4) % 4);
    const auto s = models::random_surface(seed, p, q, seed % 3 != 0);
    REQUIRE(nurbs::validate(s).empty());
    CAPTURE(seed);
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const auto su = nurbs::insert_knot_u(s, du.min + 0.61 * du.width(), 1);
    const auto sv = nurbs::insert_knot_v(s, dv.min + 0.29 * dv.width(), 3);
    CHECK(nurbs::validate(su).empty());
    CHECK(nurbs::validate(sv).empty());
    CHECK(su.count_u == s.count_u + 1);
    CHECK(sv.count_v == s.count_v + std::min(3, q));
    CHECK(surface_gap(s, su) < kTol);
    CHECK(surface_gap(s, sv) < kTol);
    const auto eu = nurbs::elevate_degree_u(s, 1);
    const auto ev = nurbs::elevate_degree_v(s, 2);
    CHECK(nurbs::validate(eu).empty());
    CHECK(nurbs::validate(ev).empty());
    CHECK(surface_gap(s, eu) < kTol);
    CHECK(surface_gap(s, ev) < kTol);
    const auto patches = nurbs::extract_bezier_patches(s);
    int spans_u = 0, spans_v = 0;
    for (size_t i = 1; i < s.knots_u.size(); ++i)
      spans_u += s.knots_u[i] > s.knots_u[i - 1] && s.knots_u[i] > du.min && s.knots_u[i - 1] < du.max;
    for (size_t i = 1; i < s.knots_v.size(); ++i)
      spans_v += s.knots_v[i] > s.knots_v[i - 1] && s.knots_v[i] > dv.min && s.knots_v[i - 1] < dv.max;
    CHECK(patches.size() == static_cast<size_t>(spans_u * spans_v));
    for (const auto& patch : patches) {
      CHECK(nurbs::validate(patch.surface).empty());
      for (int i = 0; i <= 4; ++i) {
        for (int j = 0; j <= 4; ++j) {
          const double u = patch.range_u.min + patch.range_u.width() * i / 4;
          const double v = patch.range_v.min + patch.range_v.width() * j / 4;
          CHECK(glm::length(nurbs::surface_point(patch.surface, u, v) - nurbs::surface_point(s, u, v)) < kTol);
        }
      }
    }
  }
}

TEST_CASE("sphere Bézier patches stay on the sphere") {
  const auto sphere = models::rational_sphere(1.0);
  const auto patches = nurbs::extract_bezier_patches(sphere);
  CHECK(patches.size() == 4 * 2);  // 4 quarter arcs around, 2 from pole to pole
  for (const auto& patch : patches) {
    for (int i = 0; i <= 6; ++i) {
      for (int j = 0; j <= 6; ++j) {
        const double u = patch.range_u.min + patch.range_u.width() * i / 6;
        const double v = patch.range_v.min + patch.range_v.width() * j / 6;
        CHECK(std::abs(glm::length(nurbs::surface_point(patch.surface, u, v)) - 1.0) < kTol);
      }
    }
  }
}
