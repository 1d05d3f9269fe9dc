// Tests of §7 (triangulate.h) of Balázs, Guthe, Klein 2004 on polygons given directly.
// Oracle: shoelace area of the polygon, orientation of each triangle, edge-use count.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <map>
#include <random>

#include "nurbs/tessellation/triangulate.h"
#include "nurbs/trim_classify.h"
#include "test_suites.h"

using nurbs::tess::TriangulationStats;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Triangulates polygon 0..n-1 of `v` with `fn` and checks: n - 2 triangles, none flipped, at most
/// `max_zero` of zero area, area = shoelace area (1e-12 relative: a sum of n terms of size <= area),
/// polygon edges used once in their direction, other edges twice in opposite directions.
template <class Fn>
TriangulationStats check(const std::vector<glm::dvec2>& v, Fn fn, int max_zero = 0) {
  std::vector<int> poly(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) poly[i] = static_cast<int>(i);
  std::vector<glm::ivec3> tris;
  TriangulationStats s;
  fn(v, poly, tris, &s);
  CHECK(tris.size() == v.size() - 2);
  double area = 0.0;
  int zero = 0;
  std::map<std::pair<int, int>, int> use;
  for (glm::ivec3 t : tris) {
    const glm::dvec2 a = v[static_cast<std::size_t>(t.x)], b = v[static_cast<std::size_t>(t.y)],
                     c = v[static_cast<std::size_t>(t.z)];
    const double o = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    // Sign unknown within the determinant's rounding bound (Shewchuk 1997): counted, not failed.
    const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
    const bool thin = std::abs(l - r) <= 3.3306690738754716e-16 * (std::abs(l) + std::abs(r));
    CHECK((o > 0.0 || thin));
    zero += thin;
    area += o;
    for (int k = 0; k < 3; ++k) ++use[{t[k], t[(k + 1) % 3]}];
  }
  CHECK(zero <= max_zero);
  CHECK(zero == s.degenerate_triangles);
  CHECK(area == doctest::Approx(nurbs::signed_area(v)).epsilon(1e-12));
  if (zero == 0) {
    const int n = static_cast<int>(v.size());
    int bad = 0;
    for (auto [e, k] : use) {
      const bool boundary = e.second == (e.first + 1) % n;
      bad += k != 1 || (!boundary && use.count({e.second, e.first}) != 1);
    }
    for (int i = 0; i < n; ++i) bad += use.count({i, (i + 1) % n}) != 1;
    CHECK(bad == 0);
  }
  return s;
}

void nonconvex(const std::vector<glm::dvec2>& v, const std::vector<int>& p, std::vector<glm::ivec3>& t,
               TriangulationStats* s) {
  nurbs::tess::triangulate_nonconvex(v, p, t, s);
}
void convex(const std::vector<glm::dvec2>& v, const std::vector<int>& p, std::vector<glm::ivec3>& t,
            TriangulationStats* s) {
  nurbs::tess::triangulate_convex(v, p, t, s);
}

std::vector<glm::dvec2> star(std::mt19937_64& rng, int n, double r0, double r1) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<glm::dvec2> p;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * (i + 0.45 * (u01(rng) - 0.5)) / n, r = r0 + (r1 - r0) * u01(rng);
    p.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return p;
}

}  // namespace

TEST_CASE("triangulate: convex cell polygons with T-junction points (paper zipper)") {
  // Rectangle with collinear points on every side: no zero-area triangle is needed.
  const std::vector<glm::dvec2> rect{{0, 0}, {0.25, 0}, {0.5, 0}, {1, 0},    {1, 0.5},
                                     {1, 1}, {0.5, 1},  {0, 1},   {0, 0.75}, {0, 0.5}};
  CHECK(nurbs::tess::is_convex(rect, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  const auto s = check(rect, convex);
  CHECK(s.convex_polygons == 1);
  CHECK(check(rect, nonconvex).degenerate_triangles == 0);  // the monotone path agrees
  // Many points on the bottom side only.
  std::vector<glm::dvec2> comb;
  for (int i = 0; i <= 20; ++i) comb.push_back({i / 20.0, 0.0});
  comb.push_back({1, 1}), comb.push_back({0, 1});
  check(comb, convex);
  check(comb, nonconvex);
  // Regular 50-gon.
  std::vector<glm::dvec2> ngon;
  for (int i = 0; i < 50; ++i) ngon.push_back({std::cos(2 * kPi * i / 50), std::sin(2 * kPi * i / 50)});
  check(ngon, convex);
}

TEST_CASE("triangulate: convexity check") {
  const std::vector<glm::dvec2> v{{0, 0}, {1, 0}, {0.5, 0.2}, {1, 1}, {0, 1}};
  CHECK_FALSE(nurbs::tess::is_convex(v, {0, 1, 2, 3, 4}));
  CHECK(nurbs::tess::is_convex(v, {0, 1, 3, 4}));
  CHECK(nurbs::tess::is_convex(v, {0, 1, 3}));
}

TEST_CASE("triangulate: non-convex polygons (monotone partition, Garey et al. 1978)") {
  // Comb with notches from the top (merge vertices) and, mirrored, from the bottom (split vertices);
  // equal heights everywhere.
  std::vector<glm::dvec2> down{{0, 1}, {0, 0}, {1, 0}, {1, 1}};
  for (int i = 9; i >= 1; --i) down.push_back({i / 10.0, 1.0}), down.push_back({i / 10.0 - 0.05, 0.3});
  const auto s = check(down, nonconvex);
  CHECK(s.monotone_pieces >= 1);
  std::vector<glm::dvec2> up;
  for (auto p : down) up.push_back({p.x, 1.0 - p.y});
  std::reverse(up.begin(), up.end());
  check(up, nonconvex);
  // Random star polygons, fixed seed: reflex vertices of every kind, no collinear points.
  std::mt19937_64 rng(1978);
  int pieces = 0, tris = 0;
  for (int k = 0; k < 300; ++k) {
    const auto p = star(rng, 5 + k % 80, 0.2, 1.0);
    pieces += check(p, nonconvex).monotone_pieces;
    tris += static_cast<int>(p.size()) - 2;
  }
  MESSAGE("300 star polygons: " << tris << " triangles, " << pieces << " monotone pieces");
  // Stars on a grid: axis-parallel runs and equal heights (the tie-breaking of the sweep order).
  for (int k = 0; k < 200; ++k) {
    auto p = star(rng, 6 + k % 14, 0.3, 1.0);  // few points: rounding keeps the angular order
    for (auto& q : p) q = glm::round(q * 16.0) / 16.0;
    std::vector<glm::dvec2> d;  // rounding may repeat points or flip the shape: keep simple cases
    for (auto q : p)
      if (d.empty() || q != d.back()) d.push_back(q);
    while (d.size() > 1 && d.front() == d.back()) d.pop_back();
    if (d.size() < 3 || nurbs::signed_area(d) <= 0.0) continue;
    bool spike = false;
    for (std::size_t i = 0; i < d.size(); ++i) {
      const glm::dvec2 a = d[i], b = d[(i + 1) % d.size()], c = d[(i + 2) % d.size()];
      spike = spike || (((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) == 0.0 && glm::dot(b - a, c - b) < 0.0);
    }
    if (spike) continue;
    check(d, nonconvex, static_cast<int>(d.size()));
  }
}

TEST_CASE("triangulate: a star polygon of 100000 vertices" * test::sweep()) {
  // The monotone partition at scale, and a printout of its time (minutes under the sanitizers).
  std::mt19937_64 rng(100000);
  const auto big = star(rng, 100000, 0.2, 1.0);
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = check(big, nonconvex);
  MESSAGE("star polygon with 100000 vertices: "
          << s.monotone_pieces << " monotone pieces, "
          << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s incl. checks");
}

TEST_CASE("triangulate: a trim line with a 1e-24 dent (face 125 of pythonocc_Ventilator_brep.igs)") {
  // B = v[4] is reflex by an area of 1.8e-24 (exact rational arithmetic), which double orientation
  // about A cannot see: the convexity check must not call the polygon convex.
  const std::vector<glm::dvec2> v{{1.7553725928000001, 3.1545758981442259e-08},
                                  {1.7553725928000001, 0.25000000000000033},
                                  {0.59490337699999996, 0.25000000000000033},
                                  {0.59490337699999996, 1.6477454870000001e-15},
                                  {1.739386248, 3.1111192215820688e-08}};
  CHECK_FALSE(nurbs::tess::is_convex(v, {0, 1, 2, 3, 4}));
  nurbs::tess::TrimmedPolygons polys;
  polys.vertices = v;
  polys.on_trim.assign(v.size(), true);
  polys.polygons = {{0, 1, 2, 3, 4}};
  polys.has_trim_edge = {true};
  TriangulationStats s;
  const auto tris = nurbs::tess::triangulate_polygons(polys, &s);
  CHECK(s.nonconvex_polygons == 1);
  CHECK(tris.size() == 3);
  for (glm::ivec3 t : tris) {
    // Every triangle must contain B's neighbourhood correctly: none may be C, A, B (the flipped sliver).
    const bool has_a = t.x == 3 || t.y == 3 || t.z == 3, has_b = t.x == 4 || t.y == 4 || t.z == 4,
               has_c = t.x == 0 || t.y == 0 || t.z == 0;
    CHECK_FALSE((has_a && has_b && has_c));
  }
}
