// Point-in-trim classification, loop checks (gaps, crossings, face id), gap repair and orientation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/trim_classify.h"
#include "nurbs/trim_loops.h"

using models::trim_line;

namespace {

/// Flattening tolerance in parameter units for faces on [0,1]^2: far below the feature sizes (0.1).
constexpr double kFlat = 1e-5;

nurbs::Surface unit_plane() {
  nurbs::Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  return s;
}

nurbs::TrimLoop square_loop(glm::dvec2 lo, glm::dvec2 hi, bool ccw, bool outer) {
  const glm::dvec2 a = lo, b(hi.x, lo.y), c = hi, d(lo.x, hi.y);
  if (ccw) return {{trim_line(a, b), trim_line(b, c), trim_line(c, d), trim_line(d, a)}, outer};
  return {{trim_line(a, d), trim_line(d, c), trim_line(c, b), trim_line(b, a)}, outer};
}

/// Unit square face with a circular hole of radius 0.2 at the centre.
nurbs::TrimmedSurface square_with_hole(bool correctly_oriented) {
  nurbs::TrimmedSurface f;
  f.surface = unit_plane();
  f.face_id = 17;
  f.loops.push_back(square_loop({0, 0}, {1, 1}, correctly_oriented, true));
  f.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.2, !correctly_oriented)}, false});
  return f;
}

bool contains(const std::vector<std::string>& v, const std::string& needle) {
  for (const auto& s : v) {
    if (s.find(needle) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("winding number counts a vertex on the ray once") {
  const std::vector<glm::dvec2> diamond = {{1, 0}, {2, 1}, {1, 2}, {0, 1}};  // CCW
  CHECK(nurbs::winding_number(diamond, {1, 1}) == 1);
  CHECK(nurbs::winding_number(diamond, {0.5, 1}) == 1);   // ray to +x passes through vertex (2, 1)
  CHECK(nurbs::winding_number(diamond, {-0.5, 1}) == 0);  // ray passes through both side vertices
  CHECK(nurbs::winding_number({{1, 0}, {0, 1}, {1, 2}, {2, 1}}, {1, 1}) == -1);  // CW
  CHECK(nurbs::signed_area(diamond) == doctest::Approx(2.0).epsilon(1e-15));
}

TEST_CASE("square with hole: classification, CCW and CW") {
  struct Case {
    glm::dvec2 uv;
    bool material;
  };
  const Case cases[] = {{{0.1, 0.1}, true},   {{0.5, 0.5}, false},   {{0.75, 0.5}, true},
                        {{0.5, 0.69}, false}, {{0.5, 0.71}, true},   {{0.36, 0.36}, false},
                        {{1.5, 0.5}, false},  {{-0.01, 0.5}, false}, {{0.99, 0.99}, true}};
  for (bool oriented : {true, false}) {
    const auto face = square_with_hole(oriented);
    const auto polys = nurbs::flatten_trim(face, kFlat);
    for (const auto& c : cases) {
      CAPTURE(oriented);
      CAPTURE(c.uv.x);
      CAPTURE(c.uv.y);
      CHECK(nurbs::is_material(polys, c.uv) == c.material);
    }
  }
  // Orientation fix-up: the mis-oriented face has both loops reversed, then none.
  auto bad = square_with_hole(false);
  CHECK(nurbs::orient_trim_loops(bad, kFlat) == 2);
  const auto polys = nurbs::flatten_trim(bad, kFlat);
  CHECK(nurbs::signed_area(polys.loops[0]) == doctest::Approx(1.0).epsilon(1e-12));
  // Hole area: pi r^2 minus the flattening loss (<= perimeter x tolerance).
  CHECK(std::abs(nurbs::signed_area(polys.loops[1]) + M_PI * 0.04) < 2 * M_PI * 0.2 * kFlat);
  CHECK(nurbs::orient_trim_loops(bad, kFlat) == 0);
  CHECK(nurbs::check_trim_loops(bad, 1e-12, kFlat).empty());
}

TEST_CASE("untrimmed face and face with holes only") {
  nurbs::TrimmedSurface f;
  f.surface = unit_plane();
  CHECK(nurbs::is_material(f, {0.3, 0.3}, kFlat));
  CHECK(nurbs::is_material(f, {1.0, 1.0}, kFlat));  // the domain is closed
  CHECK_FALSE(nurbs::is_material(f, {1.0001, 0.5}, kFlat));
  f.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.2, false)}, false});
  CHECK_FALSE(nurbs::is_material(f, {0.5, 0.5}, kFlat));
  CHECK(nurbs::is_material(f, {0.1, 0.5}, kFlat));
}

TEST_CASE("flattening stays within its tolerance") {
  const auto circle = models::rational_circle_2d({0.2, 0.3}, 0.5, true);
  for (double tol : {1e-2, 1e-4, 1e-6}) {
    const auto poly = nurbs::flatten_curve(circle, tol);
    CAPTURE(tol);
    for (size_t i = 0; i + 1 < poly.size(); ++i) {
      // Vertices are curve points (roundoff); the chord sagitta of the arc between them is <= tol.
      CHECK(std::abs(glm::length(poly[i] - glm::dvec2(0.2, 0.3)) - 0.5) < 1e-12);
      const double half = 0.5 * glm::length(poly[i + 1] - poly[i]);
      CHECK(0.5 - std::sqrt(0.25 - half * half) <= tol);
    }
    CHECK(glm::length(poly.front() - poly.back()) < 1e-12);  // a closed curve returns to its start
  }
}

TEST_CASE("flattening stops at once on non-finite points") {
  // A NaN control point (an overflow in a damaged file) makes every deviation NaN: each of the four
  // pieces a Bézier segment is always cut into ends there (start + 4 points), not at depth 30.
  nurbs::Curve2 c;
  c.degree = 2;
  c.knots = {0, 0, 0, 1, 1, 1};
  c.points = {{0, 0}, {std::nan(""), 0}, {1, 0}};
  CHECK(nurbs::flatten_curve(c, 1e-6).size() == 5);
}

TEST_CASE("reversed curves: exact copies backwards, C_r(u) = C(a + b - u)") {
  const auto circle = models::rational_circle_2d({0.2, 0.3}, 0.5, true);
  const nurbs::Curve2 r = nurbs::reversed(circle);
  CHECK(std::equal(r.points.begin(), r.points.end(), circle.points.rbegin()));  // copies: bit-exact
  CHECK(std::equal(r.weights.begin(), r.weights.end(), circle.weights.rbegin()));
  const nurbs::Curve2 rr = nurbs::reversed(r);
  CHECK(rr.knots == circle.knots);  // a + b - (a + b - k) = k exactly for these dyadic knots
  const nurbs::Interval d = nurbs::curve_domain(circle);
  for (double t : {0.0, 0.1, 0.37, 0.5, 0.99, 1.0}) {
    const double u = d.min + t * (d.max - d.min);
    // Roundoff of two evaluations of a unit-size curve.
    CHECK(glm::length(nurbs::curve_point(r, u) - nurbs::curve_point(circle, d.min + d.max - u)) < 1e-14);
  }
}

TEST_CASE("loop checks: gaps reported and repaired, crossings named with the face id") {
  auto face = square_with_hole(true);
  face.loops[0].curves[1].points[0] += glm::dvec2(0.0, 1e-7);  // curve 0 ends 1e-7 from curve 1's start
  const auto problems = nurbs::check_trim_loops(face, 1e-9, kFlat);
  REQUIRE(problems.size() == 1);
  CHECK(contains(problems, "face 17: loop 0 does not close: curve 0 ends 1e-07 from the start of curve 1"));
  CHECK(nurbs::repair_trim_gaps(face, 1e-9) == 0);  // above the repair tolerance: left alone
  CHECK(nurbs::repair_trim_gaps(face, 1e-6) == 1);
  CHECK(nurbs::check_trim_loops(face, 1e-9, kFlat).empty());
  CHECK(nurbs::repair_trim_gaps(face, 1e-6) == 0);  // nothing left to repair

  // Two gaps, one in each loop, repaired together; a large gap remains reported.
  auto two = square_with_hole(true);
  two.loops[0].curves[3].points[1] += glm::dvec2(2e-8, 0.0);
  two.loops[1].curves[0].points.back() += glm::dvec2(0.0, 3e-8);
  two.loops[0].curves[2].points[1] += glm::dvec2(0.05, 0.0);
  CHECK(nurbs::repair_trim_gaps(two, 1e-6) == 2);
  const auto left = nurbs::check_trim_loops(two, 1e-6, kFlat);
  REQUIRE(left.size() == 1);
  CHECK(contains(left, "face 17: loop 0 does not close: curve 2 ends 0.05"));

  // Two holes that overlap, and a figure-eight outer loop.
  auto crossing = square_with_hole(true);
  crossing.loops.push_back({{models::rational_circle_2d({0.65, 0.5}, 0.2, false)}, false});
  const auto cp = nurbs::check_trim_loops(crossing, 1e-9, kFlat);
  REQUIRE(cp.size() == 1);
  CHECK(contains(cp, "face 17: loops 1 and 2 cross near (u, v) = (0.57"));
  nurbs::TrimmedSurface eight;
  eight.surface = unit_plane();
  eight.face_id = 4;
  eight.loops.push_back({{trim_line({0.1, 0.1}, {0.9, 0.9}), trim_line({0.9, 0.9}, {0.9, 0.1}),
                          trim_line({0.9, 0.1}, {0.1, 0.9}), trim_line({0.1, 0.9}, {0.1, 0.1})},
                         true});
  const auto ep = nurbs::check_trim_loops(eight, 1e-9, kFlat);
  REQUIRE(ep.size() == 1);
  CHECK(contains(ep, "face 4: loop 0 crosses itself near (u, v) = (0.5, 0.5)"));
  // An invalid trim curve is reported with its loop and curve index.
  eight.loops[0].curves[2].knots = {0, 1, 0, 1};
  CHECK(contains(nurbs::check_trim_loops(eight, 1e-9, kFlat), "face 4: loop 0 curve 2: knots: knots decrease"));
}

TEST_CASE("a declared outer loop lying inside another loop becomes a hole of it") {
  // As a 144 naming one of its holes PTO: the small square declared outer, the big one a hole.
  // The small square (0.4 to 0.5) declared outer, two others (corners lo and hi) declared holes.
  const auto three_squares = [](glm::dvec2 lo1, glm::dvec2 hi1, glm::dvec2 lo2, glm::dvec2 hi2) {
    nurbs::TrimmedSurface f;
    f.surface = unit_plane();
    f.loops = {square_loop({0.4, 0.4}, {0.5, 0.5}, true, true), square_loop(lo1, hi1, false, false),
               square_loop(lo2, hi2, false, false)};
    return f;
  };
  nurbs::TrimmedSurface face = three_squares({0.1, 0.1}, {0.9, 0.9}, {0.6, 0.6}, {0.7, 0.7});
  auto polys = nurbs::flatten_trim(face, kFlat);
  CHECK(nurbs::fix_outer_loop(face, polys) == 1);
  CHECK_FALSE(face.loops[0].outer);
  CHECK(face.loops[1].outer);
  CHECK_FALSE(face.loops[2].outer);
  CHECK(polys.outer == std::vector<bool>{false, true, false});
  CHECK(nurbs::orient_trim_loops(face, polys) == 2);
  const auto fixed = nurbs::flatten_trim(face, kFlat);
  CHECK(nurbs::is_material(fixed, {0.2, 0.2}));
  CHECK_FALSE(nurbs::is_material(fixed, {0.45, 0.45}));
  CHECK_FALSE(nurbs::is_material(fixed, {0.65, 0.65}));
  // The usual face, and a declared outer that does not hold a loop lying partly outside it: unchanged.
  auto usual = square_with_hole(true);
  auto usual_polys = nurbs::flatten_trim(usual, kFlat);
  CHECK(nurbs::fix_outer_loop(usual, usual_polys) == 0);
  CHECK(usual.loops[0].outer);
  nurbs::TrimmedSurface two = three_squares({0.1, 0.1}, {0.6, 0.6}, {0.55, 0.55}, {0.95, 0.95});
  auto two_polys = nurbs::flatten_trim(two, kFlat);
  CHECK(nurbs::fix_outer_loop(two, two_polys) == 0);
  CHECK(two.loops[0].outer);
}

TEST_CASE("random trimmed faces: classification agrees with the exact shapes") {
  int checked = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const auto face = models::random_trimmed_surface(seed);
    CAPTURE(seed);
    CHECK(nurbs::check_trim_loops(face, 1e-12, 1e-6).empty());
    auto copy = face;
    CHECK(nurbs::orient_trim_loops(copy, 1e-6) == 0);  // the generator orients its loops
    const auto polys = nurbs::flatten_trim(face, 1e-7);
    models::Random rng(seed + 99);
    for (int k = 0; k < 50; ++k) {
      const glm::dvec2 uv(rng.uniform(polys.domain_u.min, polys.domain_u.max),
                          rng.uniform(polys.domain_v.min, polys.domain_v.max));
      // Exact answer: the outer loop is a polygon (flattening is exact), holes are circles.
      bool material = true;
      bool near = false;
      for (size_t l = 0; l < face.loops.size(); ++l) {
        if (face.loops[l].outer) {
          material = material && nurbs::winding_number(polys.loops[l], uv) != 0;
        } else {
          const auto& pts = face.loops[l].curves[0].points;
          const glm::dvec2 centre = 0.5 * (pts[0] + pts[4]);  // 9-point circle: P0 and P4 are opposite
          const double r = 0.5 * glm::length(pts[0] - pts[4]);
          const double d = glm::length(uv - centre);
          if (d < r) material = false;
          near = near || std::abs(d - r) < 1e-6;  // within the flattening band: either answer is right
        }
      }
      if (near) continue;
      CHECK(nurbs::is_material(polys, uv) == material);
      ++checked;
    }
  }
  CHECK(checked > 9000);
}

TEST_CASE("the trimmed paper surface has clean loops") {
  const auto face = models::trimmed_wavy_surface_100x105();
  CHECK(face.loops.size() == 4);
  CHECK(nurbs::check_trim_loops(face, 1e-12, 1e-6).empty());
  auto copy = face;
  CHECK(nurbs::orient_trim_loops(copy, 1e-6) == 0);
  const auto polys = nurbs::flatten_trim(face, 1e-6);
  CHECK(nurbs::is_material(polys, {0.5, 0.5}));
  CHECK_FALSE(nurbs::is_material(polys, {0.3, 0.3}));   // first hole centre
  CHECK_FALSE(nurbs::is_material(polys, {0.7, 0.65}));  // second hole centre
  CHECK_FALSE(nurbs::is_material(polys, {0.3, 0.72}));  // blob
  CHECK_FALSE(nurbs::is_material(polys, {0.02, 0.5}));  // outside the outer loop
}

TEST_CASE("junctions that meet up to rounding are one vertex, not a self-crossing") {
  // As written by CAD kernels (occt_hammer.iges face 3): consecutive edges meet within ~1e-20.
  nurbs::TrimmedSurface f;
  f.surface = unit_plane();
  f.face_id = 3;
  const glm::dvec2 a(0, 0), b(1, 0), c(1, 1), d(0, 1), eps(1e-17, -1e-17);
  f.loops.push_back({{trim_line(a, b), trim_line(b + eps, c), trim_line(c, d - eps), trim_line(d, a + eps)}, true});
  const nurbs::TrimPolygons t = nurbs::flatten_trim(f, kFlat);
  CHECK(t.loops[0].size() == 4);  // four corners, no sliver edges
  CHECK(nurbs::check_trim_loops(f, 1e-9, kFlat).empty());
  // A real gap (far above rounding) still shows.
  f.loops[0].curves[1] = trim_line(b + glm::dvec2(0, 1e-3), c);
  CHECK(contains(nurbs::check_trim_loops(f, 1e-9, kFlat), "face 3: loop 0 does not close"));
}

TEST_CASE("loops listed out of order or with a reversed curve are chained again, real gaps are not") {
  nurbs::TrimmedSurface plane;
  plane.surface = models::bilinear_square(10.0);
  const glm::dvec2 a(1, 1), b(9, 1), c(9, 9), d(1, 9);
  using models::trim_line;
  nurbs::Curve2 bulge;  // a curved side, so a reversed curve is not the same line
  bulge.degree = 2, bulge.knots = {0, 0, 0, 1, 1, 1}, bulge.points = {d, {-1, 5}, a};
  const std::vector<nurbs::TrimLoop> broken{
      {{trim_line(a, b), trim_line(c, b), trim_line(c, d), bulge}, true},                      // one reversed
      {{trim_line(a, b), trim_line(c, d), trim_line(b, c), bulge}, true},                      // out of order
      {{trim_line(a, b), nurbs::reversed(bulge), trim_line(c, d), trim_line(c, b)}, true}};  // both
  const nurbs::TrimLoop right{{trim_line(a, b), trim_line(b, c), trim_line(c, d), bulge}, true};
  for (const nurbs::TrimLoop& loop : broken) {
    nurbs::TrimmedSurface face = plane;
    face.loops = {loop};
    CHECK_FALSE(nurbs::check_trim_loops(face, 1e-6, 1e-4).empty());  // gaps between the curves
    CHECK(nurbs::reorder_trim_curves(face, 1e-6) == 1);
    CHECK(nurbs::check_trim_loops(face, 1e-6, 1e-4).empty());
    REQUIRE(face.loops[0].curves.size() == 4);
    // The same loop as drawn right (up to where it starts): the same material everywhere.
    nurbs::TrimmedSurface expected = plane;
    expected.loops = {right};
    models::Random rng(3);
    int differ = 0;
    for (int k = 0; k < 2000; ++k) {
      const glm::dvec2 p(rng.uniform(0, 10), rng.uniform(0, 10));
      differ += nurbs::is_material(face, p, 1e-5) != nurbs::is_material(expected, p, 1e-5);
    }
    CHECK(differ == 0);
  }
  // A loop with a real gap (a side missing) is left as it is, for the checker to name.
  nurbs::TrimmedSurface open = plane;
  open.loops = {{{trim_line(a, b), trim_line(b, c), trim_line(c, d)}, true}};
  CHECK(nurbs::reorder_trim_curves(open, 1e-6) == 0);
  CHECK(open.loops[0].curves.size() == 3);
  // A chained loop is left alone.
  nurbs::TrimmedSurface fine = plane;
  fine.loops = {right};
  CHECK(nurbs::reorder_trim_curves(fine, 1e-6) == 0);
}

TEST_CASE("loops along the domain's sides in thousands of edges are checked whole, their crossings found") {
  // The sides u = 0 and u = 1 in 6000 pieces each (pcurves sampled along a B-spline's boundary):
  // a sweep in u alone would pass every pair of edges on one side, beyond the check's budget.
  constexpr int kPieces = 6000;
  nurbs::TrimmedSurface face;
  face.surface = unit_plane();
  face.face_id = 9;
  nurbs::TrimLoop outer{{trim_line({0, 0}, {1, 0})}, true};
  for (int i = 0; i < kPieces; ++i)
    outer.curves.push_back(trim_line({1, double(i) / kPieces}, {1, double(i + 1) / kPieces}));
  outer.curves.push_back(trim_line({1, 1}, {0, 1}));
  for (int i = kPieces; i > 0; --i)
    outer.curves.push_back(trim_line({0, double(i) / kPieces}, {0, double(i - 1) / kPieces}));
  face.loops.push_back(outer);
  CHECK(nurbs::check_trim_loops(face, 1e-9, kFlat).empty());
  // A hole across the side u = 1 is still found where it crosses it.
  face.loops.push_back(square_loop({0.95, 0.4}, {1.05, 0.6}, false, false));
  const auto problems = nurbs::check_trim_loops(face, 1e-9, kFlat);
  REQUIRE(problems.size() == 1);
  CHECK(contains(problems, "face 9: loops 0 and 1 cross near (u, v) = (1, 0.4)"));
}
