// §4 of Balázs, Guthe, Klein 2004: trim curves lifted to 3D Bézier curves (trim_bezier3d.h).
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <random>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/curve_eval.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/trim_bezier3d.h"

using namespace nurbs;
using namespace nurbs::tess;

namespace {

/// Max |lifted - S(c(t))| over `n` random parameters of every piece (fixed seed), model units.
double random_param_error(const Surface& s, const std::vector<TrimCurve3>& pieces, int n = 200) {
  std::mt19937_64 rng(7);
  double err = 0.0;
  for (const auto& p : pieces)
    for (int k = 0; k < n; ++k) {
      const double t = p.range.min + double(rng() >> 11) * 0x1p-53 * p.range.width();
      const glm::dvec2 uv = piece_uv(s, p.uv, t);
      err = std::max(err, glm::length(bezier_point3(p.xyz, t) - surface_point(s, uv.x, uv.y)));
    }
  return err;
}

/// Bicubic wavy surface over 100 x 80 mm (count x count control points, count - 3 spans per direction).
Surface bicubic(int count) { return models::wavy_surface(count, count, 100.0, 80.0, 6.0, 45.0, 50.0, 0.3, 0.0); }

LiftOptions method(LiftMethod m, bool reduce) {
  LiftOptions o;
  o.method = m;
  o.reduce = reduce;
  return o;
}

}  // namespace

TEST_CASE("trim: a line on one bicubic patch lifts exactly, by collocation and by composition") {
  const Surface s = bicubic(4);  // one Bézier patch
  const auto patches = extract_bezier_patches(s);
  const Curve2 line = models::trim_line({0.1, 0.2}, {0.9, 0.7});
  for (LiftMethod m : {LiftMethod::Collocation, LiftMethod::Composition}) {
    const auto pieces = convert_trim_curve(s, patches, line, method(m, false));
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0].lifted_degree == 6);  // d2d (du + dv) = 1 * (3 + 3)
    CHECK(pieces[0].xyz.degree == 6);
    // 1e-9 relative to the 100 mm model: the exactness bar of the tests (rounding is ~1e-13 here).
    CHECK(random_param_error(s, pieces) <= 1e-9 * 100.0);
    CHECK(lift_error(s, pieces[0]) <= 1e-9 * 100.0);
  }
  // The lifted curve is not any degree-6 curve: a perturbed control point fails the same check.
  auto pieces = convert_trim_curve(s, patches, line, method(LiftMethod::Collocation, false));
  pieces[0].xyz.points[3].z += 1e-3;
  CHECK(random_param_error(s, pieces) > 1e-9 * 100.0);
}

TEST_CASE("trim: knot-line cuts put every piece on one patch") {
  const Surface s = bicubic(9);  // 6 x 6 spans, knots at k / 6
  const auto patches = extract_bezier_patches(s);
  const Curve2 line = models::trim_line({0.05, 0.1}, {0.95, 0.8});
  BezierSegment<2> seg{line, {0.0, 1.0}};
  std::vector<double> lines;
  for (int k = 1; k < 6; ++k) lines.push_back(k / 6.0);
  const auto cuts = knot_line_crossings(seg, lines, lines);
  // x = 0.05 + 0.9 t crosses 5 u lines; y = 0.1 + 0.7 t crosses k/6 for k = 1..4 (0.8 < 5/6).
  REQUIRE(cuts.size() == 9);
  for (int k = 1; k < 6; ++k) {
    const double t = (k / 6.0 - 0.05) / 0.9;
    bool found = false;
    for (double c : cuts) found = found || std::abs(c - t) < 1e-14;  // bisection to 1e-17, rounding
    CHECK(found);
  }
  const auto pieces = convert_trim_curve(s, patches, line);
  CHECK(pieces.size() == 10);
  for (const auto& p : pieces) {
    const auto& patch = patches[size_t(p.patch)];
    for (double t : {p.range.min, 0.5 * (p.range.min + p.range.max), p.range.max}) {
      const glm::dvec2 uv = curve_point(p.uv, t);
      CHECK(uv.x >= patch.range_u.min - 1e-12);  // 1e-12: the root tolerance of the knot-line cuts
      CHECK(uv.x <= patch.range_u.max + 1e-12);
      CHECK(uv.y >= patch.range_v.min - 1e-12);
      CHECK(uv.y <= patch.range_v.max + 1e-12);
    }
  }
  CHECK(random_param_error(s, pieces) <= 1e-9 * 100.0);  // exactness bar, as above
}

TEST_CASE("trim: circles (rational, degree 2) on a sphere and a torus lift exactly") {
  const Curve2 circle = models::rational_circle_2d({0.3, 0.4}, 0.15, true);
  struct Shape {
    Surface s;
    double r;
  };
  for (const auto& sh :
       {Shape{models::rational_sphere(2.0, {1, 2, 3}), 2.0}, Shape{models::rational_torus(3.0, 1.0), 4.0}}) {
    const auto patches = extract_bezier_patches(sh.s);
    const auto pieces = convert_trim_curve(sh.s, patches, circle);
    CHECK(pieces.size() > 4);  // 4 circle quadrants plus knot-line cuts at u = 1/4, 1/2 (and v lines)
    for (const auto& p : pieces) {
      CHECK(p.lifted_degree == 8);  // 2 * (2 + 2)
      CHECK(!p.composed);           // degree 8 <= 20 and the collocation verifies
    }
    CHECK(random_param_error(sh.s, pieces) <= 1e-9 * sh.r);  // exactness bar relative to the size
  }
  // Independent oracle: points of the lifted curve lie on the sphere.
  const Surface sphere = models::rational_sphere(2.0, {1, 2, 3});
  const auto pieces = convert_trim_curve(sphere, extract_bezier_patches(sphere), circle);
  for (const auto& p : pieces)
    for (int k = 0; k <= 10; ++k) {
      const glm::dvec3 x = bezier_point3(p.xyz, p.range.min + 0.1 * k * p.range.width());
      CHECK(std::abs(glm::length(x - glm::dvec3(1, 2, 3)) - 2.0) <= 1e-12 * 2.0);  // rounding of ~100 flops
    }
}

TEST_CASE("trim: lossless degree reduction recovers the lower degree") {
  // An iso-line u = 0.37 of a bicubic patch is a cubic: lifted at degree 6, reduced to 3.
  const Surface s = bicubic(4);
  const auto pieces = convert_trim_curve(s, extract_bezier_patches(s), models::trim_line({0.37, 0.1}, {0.37, 0.9}));
  REQUIRE(pieces.size() == 1);
  CHECK(pieces[0].lifted_degree == 6);
  CHECK(pieces[0].xyz.degree == 3);
  CHECK(random_param_error(s, pieces) <= 1e-9 * 100.0);  // exactness bar

  // A random quadratic elevated to degree 7 comes back to degree 2 with its control points.
  std::mt19937_64 rng(3);
  auto rnd = [&] { return double(rng() >> 11) * 0x1p-53 * 2.0 - 1.0; };
  HomogeneousCurve q{2, {0, 0, 0, 1, 1, 1}, {}};
  for (int i = 0; i < 3; ++i) q.points.push_back({rnd(), rnd(), rnd(), 1.0 + 0.5 * (rnd() + 1.0)});
  HomogeneousCurve e = q;
  for (int k = 0; k < 5; ++k) e = elevate_bezier(e);
  const HomogeneousCurve r = reduce_degree_lossless(e, 1e-10);
  REQUIRE(r.degree == 2);
  for (int i = 0; i < 3; ++i) CHECK(glm::length(r.points[size_t(i)] - q.points[size_t(i)]) <= 1e-12);  // rounding
  // A genuine cubic is not reducible: it stays at degree 3.
  HomogeneousCurve c{3, {0, 0, 0, 0, 1, 1, 1, 1}, {{0, 0, 0, 1}, {1, 2, 0, 1}, {2, -1, 0, 1}, {3, 0, 1, 1}}};
  CHECK(reduce_degree_lossless(c, 1e-10).degree == 3);
}

TEST_CASE("trim: lifted degree above the paper's cap of 20 (cubic trims on quintic surfaces)") {
  const Surface s = models::random_surface(11, 5, 5, false);
  const auto patches = extract_bezier_patches(s);
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  auto at = [&](double a, double b) { return glm::dvec2(du.min + a * du.width(), dv.min + b * dv.width()); };
  Curve2 cubic{3, {0, 0, 0, 0, 1, 1, 1, 1}, {at(0.1, 0.2), at(0.4, 0.9), at(0.6, 0.1), at(0.9, 0.7)}, {}};
  double size = 0.0;
  for (const auto& p : s.points) size = std::max(size, glm::length(p));
  const auto automatic = convert_trim_curve(s, patches, cubic);
  for (const auto& p : automatic) {
    CHECK(p.lifted_degree == 30);
    CHECK(p.composed);  // 30 > max_degree 20: exact Bernstein composition
  }
  CHECK(random_param_error(s, automatic) <= 1e-9 * size);  // exactness bar
  // What collocation alone does at degree 30 (equally spaced nodes): measured, reported.
  const auto colloc = convert_trim_curve(s, patches, cubic, method(LiftMethod::Collocation, false));
  MESSAGE("degree-30 collocation error / size = ", random_param_error(s, colloc) / size,
          ", composition: ", random_param_error(s, automatic) / size);
}

TEST_CASE("trim: trims overshooting the domain are clamped; pole edges (zero length in 3D) work") {
  const Surface sphere = models::rational_sphere(1.0);
  const auto patches = extract_bezier_patches(sphere);
  // Overshoot of 1e-6 and 1e-5 (parameter units on [0, 1]), as in IGES files.
  const auto pieces = convert_trim_curve(sphere, patches, models::trim_line({-1e-6, 0.3}, {1.0 + 1e-5, 0.6}));
  for (const auto& p : pieces)
    for (const auto& q : p.uv.points) CHECK((q.x >= 0.0 && q.x <= 1.0));
  CHECK(random_param_error(sphere, pieces) <= 1e-9);  // exactness bar, radius 1
  // The south pole edge v = 0: every point is the pole.
  const auto pole = convert_trim_curve(sphere, patches, models::trim_line({0.0, 0.0}, {1.0, 0.0}));
  CHECK(pole.size() == 4);  // cut at u = 1/4, 1/2, 3/4
  for (const auto& p : pole)
    CHECK(glm::length(bezier_point3(p.xyz, p.range.min + 0.3 * p.range.width()) - glm::dvec3(0, 0, -1)) <= 1e-12);
  CHECK(random_param_error(sphere, pole) <= 1e-9);
}

TEST_CASE("trim: domain_loop is the counter-clockwise domain rectangle") {
  const Surface s = models::random_surface(5, 2, 3, true);
  const TrimLoop loop = domain_loop(s);
  REQUIRE(loop.curves.size() == 4);
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  CHECK(loop.curves[0].points[0] == glm::dvec2(du.min, dv.min));
  CHECK(loop.curves[1].points[0] == glm::dvec2(du.max, dv.min));
  CHECK(loop.curves[2].points[0] == glm::dvec2(du.max, dv.max));
  CHECK(loop.curves[3].points[1] == glm::dvec2(du.min, dv.min));
}
