// Faces bounded by their own parameter rectangle (rectangle_face.h): which loops are recognised, and
// that the mesh is then within the cells' bound alone (no loop error; within eps with a hole),
// measured independently (mesh_check.h) on random patches trimmed by random sub-rectangles.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/tessellation/rectangle_face.h"
#include "nurbs/tessellation/tessellate.h"
#include "test_suites.h"

namespace {

using nurbs::Curve2;
using nurbs::TrimLoop;
using nurbs::tess::boundary_rectangle;

/// A straight curve from a to b of the given degree (control points equally spaced, so monotone).
Curve2 segment(glm::dvec2 a, glm::dvec2 b, int degree = 1) {
  Curve2 c;
  c.degree = degree;
  c.knots.assign(size_t(degree) + 1, 0.0);
  c.knots.insert(c.knots.end(), size_t(degree) + 1, 1.0);
  for (int i = 0; i <= degree; ++i) c.points.push_back(a + (b - a) * (double(i) / degree));
  return c;
}

/// The rectangle [lo, hi] as a loop, each side in `pieces` curves of degree 1 or 2, counter-clockwise.
TrimLoop rectangle_loop(glm::dvec2 lo, glm::dvec2 hi, int pieces = 1, bool clockwise = false) {
  const glm::dvec2 c[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  TrimLoop l;
  for (int k = 0; k < 4; ++k)
    for (int p = 0; p < pieces; ++p) {
      const glm::dvec2 a = c[k] + (c[(k + 1) % 4] - c[k]) * (double(p) / pieces);
      const glm::dvec2 b = c[k] + (c[(k + 1) % 4] - c[k]) * (double(p + 1) / pieces);
      l.curves.push_back(segment(a, b, 1 + (k + p) % 2));
    }
  if (clockwise) {
    std::reverse(l.curves.begin(), l.curves.end());
    for (Curve2& cv : l.curves) std::reverse(cv.points.begin(), cv.points.end());
  }
  return l;
}

nurbs::TrimmedSurface plane() {
  nurbs::TrimmedSurface f;
  f.surface = models::bilinear_square(10.0);
  return f;
}

}  // namespace

TEST_CASE("rectangle faces: which loops are a face's own parameter rectangle") {
  nurbs::TrimmedSurface f = plane();
  SUBCASE("untrimmed: the domain") {
    const auto r = boundary_rectangle(f);
    REQUIRE(r);
    CHECK(r->lo == glm::dvec2(0, 0));
    CHECK(r->hi == glm::dvec2(10, 10));
  }
  SUBCASE("a sub-rectangle of iso-curves, several per side, degrees 1 and 2") {
    f.loops.push_back(rectangle_loop({2, 3}, {7, 9}, 3));
    const auto r = boundary_rectangle(f);
    REQUIRE(r);
    CHECK(r->lo == glm::dvec2(2, 3));
    CHECK(r->hi == glm::dvec2(7, 9));
  }
  SUBCASE("reaching past the domain: clipped to it") {
    f.loops.push_back(rectangle_loop({-1e-9, 3}, {7, 10 + 1e-9}, 2));
    const auto r = boundary_rectangle(f);
    REQUIRE(r);
    CHECK(r->lo == glm::dvec2(0, 3));
    CHECK(r->hi == glm::dvec2(7, 10));
  }
  SUBCASE("not a rectangle") {
    TrimLoop l = rectangle_loop({2, 3}, {7, 9}, 2);
    SUBCASE("a side bent inwards (its middle control point off the side)") { l.curves[1].points[1].y += 0.5; }
    SUBCASE("a side running back and forth (control points not monotone)") {
      std::swap(l.curves[1].points[0], l.curves[1].points[1]);
    }
    SUBCASE("clockwise") { l = rectangle_loop({2, 3}, {7, 9}, 2, true); }
    SUBCASE("around twice") {
      const TrimLoop once = l;
      l.curves.insert(l.curves.end(), once.curves.begin(), once.curves.end());
    }
    SUBCASE("a corner cut by a diagonal") {
      l.curves = {segment({2, 3}, {7, 3}), segment({7, 3}, {7, 9}), segment({7, 9}, {2.5, 9}),
                  segment({2.5, 9}, {2, 8.5}), segment({2, 8.5}, {2, 3})};
    }
    f.loops.push_back(l);
    CHECK_FALSE(boundary_rectangle(f));
  }
  SUBCASE("holes do not matter; a second outer loop does") {
    f.loops.push_back(rectangle_loop({2, 3}, {7, 9}));
    f.loops.push_back({{models::rational_circle_2d({4.0, 6.0}, 1.0, false)}, false});
    REQUIRE(boundary_rectangle(f));
    CHECK(boundary_rectangle(f)->hi == glm::dvec2(7, 9));
    f.loops.push_back(rectangle_loop({8, 8}, {9, 9}));
    CHECK_FALSE(boundary_rectangle(f));
  }
}

TEST_CASE("rectangle faces: within eps on random patches trimmed by random rectangles" * test::sweep()) {
  std::mt19937_64 rng(20261201);
  auto unit = [&] { return double(rng() >> 11) * 0x1.0p-53; };
  long long with = 0, paper = 0;
  double worst = 0.0;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    nurbs::TrimmedSurface f;
    f.surface = models::random_surface(seed, 1 + int(seed % 3) + 1, 1 + int(seed / 3 % 3) + 1, seed % 4 == 3);
    const nurbs::Interval du = nurbs::surface_domain_u(f.surface), dv = nurbs::surface_domain_v(f.surface);
    if (seed % 5 != 0) {  // one in five untrimmed: the domain loop
      const double u0 = du.min + 0.4 * unit() * du.width(), u1 = du.max - 0.4 * unit() * du.width();
      const double v0 = dv.min + 0.4 * unit() * dv.width(), v1 = dv.max - 0.4 * unit() * dv.width();
      f.loops.push_back(rectangle_loop({u0, v0}, {u1, v1}, 1 + int(seed % 3)));
      if (seed % 2 == 0)  // a hole: its loop polyline and share of eps as usual
        f.loops.push_back(
            {{models::rational_circle_2d({0.5 * (u0 + u1), 0.5 * (v0 + v1)}, 0.2 * std::min(u1 - u0, v1 - v0), false)},
             false});
    }
    REQUIRE(boundary_rectangle(f));
    const std::vector<nurbs::TrimmedSurface> faces{f};
    nurbs::tess::TessellateOptions o;
    o.eps = (seed % 2 ? 2e-3 : 1e-2) * nurbs::control_box(f.surface).diagonal();
    const auto r = nurbs::tess::tessellate(faces, o);
    REQUIRE(r.failures.empty());
    CHECK(r.stats.trim.rectangle_faces == 1);
    const double d = nurbs::tess::measure_deviation(faces, r.mesh, {32, 0.0, 0}).max();
    CAPTURE(seed);
    // Without a hole the cells' bound alone (no loop error to add), with one the sum.
    CHECK(d <= (f.loops.size() > 1 ? 1.0 : 1.0 - o.loop_share) * o.eps);
    worst = std::max(worst, d / o.eps);
    o.rectangle_faces = false;  // the paper: the boundary as loop polylines
    const auto p = nurbs::tess::tessellate(faces, o);
    CHECK(p.stats.trim.rectangle_faces == 0);
    with += r.stats.triangles, paper += p.stats.triangles;
  }
  MESSAGE("40 random rectangle faces (16 with a hole): " << with << " triangles (" << paper
                                                         << " with loop polylines), worst " << worst << " of eps");
  CHECK(with < paper);
}
