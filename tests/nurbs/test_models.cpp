// Generators in models/: valid surfaces with the stated control-point counts, reproducible seeds.
#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <random>
#include <tuple>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/distance/filip_bound.h"
#include "nurbs/surface_eval.h"
#include "nurbs/validate.h"

TEST_CASE("paper pair and trimmed surface: sizes and validity") {
  struct Case {
    const char* name;
    nurbs::Surface s;
    int count_u, count_v;
    glm::dvec2 footprint;  // mm
  };
  const Case cases[] = {{"199x33", models::wavy_surface_199x33(), 199, 33, {200, 40}},
                        {"100x105", models::wavy_surface_100x105(), 100, 105, {100, 100}}};
  for (const auto& c : cases) {
    CAPTURE(c.name);
    CHECK(nurbs::validate(c.s).empty());
    CHECK(c.s.count_u == c.count_u);
    CHECK(c.s.count_v == c.count_v);
    CHECK(c.s.degree_u == 3);
    CHECK(c.s.degree_v == 3);
    CHECK_FALSE(c.s.rational());
    // Clamped: the surface corners are the control-net corners, which span the footprint exactly.
    const glm::dvec3 far = nurbs::surface_point(c.s, 1.0, 1.0) - nurbs::surface_point(c.s, 0.0, 0.0);
    CHECK(far.x == doctest::Approx(c.footprint.x).epsilon(1e-14));
    CHECK(far.y == doctest::Approx(c.footprint.y).epsilon(1e-14));
  }
  const auto t = models::trimmed_wavy_surface_100x105();
  CHECK(nurbs::validate(t.surface).empty());
  int inner = 0;
  for (const auto& loop : t.loops) {
    inner += loop.outer ? 0 : 1;
    for (const auto& c : loop.curves) CHECK(nurbs::validate(c).empty());
  }
  CHECK(inner >= 2);
}

TEST_CASE("exact shapes: control-point counts and validity") {
  struct Case {
    const char* name;
    nurbs::Surface s;
    int count_u, count_v, degree_v;
  };
  const Case cases[] = {{"sphere", models::rational_sphere(2.0), 9, 5, 2},
                        {"torus", models::rational_torus(3.0, 1.0), 9, 9, 2},
                        {"cylinder", models::rational_cylinder(1.0, 5.0), 9, 2, 1}};
  for (const auto& c : cases) {
    CAPTURE(c.name);
    CHECK(nurbs::validate(c.s).empty());
    CHECK(c.s.count_u == c.count_u);
    CHECK(c.s.count_v == c.count_v);
    CHECK(c.s.degree_u == 2);
    CHECK(c.s.degree_v == c.degree_v);
    CHECK(c.s.rational());
  }
}

TEST_CASE("random family: Random is a function of the raw mt19937_64 stream only") {
  // The documented contract (random_surfaces.h), derived here from the standard engine itself: a
  // double is the top 53 bits of one output times 2^-53, an integer one output modulo the range.
  // mt19937_64's output is fixed by [rand.predef], so the family is the same on every compiler.
  for (std::uint64_t seed : {0ull, 1ull, 12345ull}) {
    CAPTURE(seed);
    models::Random r(seed);
    std::mt19937_64 e(seed);
    for (int k = 0; k < 100; ++k) {
      CHECK(r.uniform() == static_cast<double>(e() >> 11) * 0x1.0p-53);  // exact: same bits
      CHECK(r.integer(-3, 7) == -3 + static_cast<int>(e() % 11u));
    }
  }
  // Range and balance: 1e5 draws, mean within 5 sigma of 1/2 (sigma = sqrt(1/12 / 1e5) = 9.1e-4);
  // every value of integer(0, 100) appears (expected count 990 each).
  models::Random r(7);
  double sum = 0.0, lo = 1.0, hi = 0.0;
  std::vector<int> hits(101, 0);
  for (int k = 0; k < 100000; ++k) {
    const double u = r.uniform();
    sum += u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    const int i = r.integer(0, 100);
    REQUIRE(i >= 0);
    REQUIRE(i <= 100);
    ++hits[static_cast<size_t>(i)];
  }
  CHECK(lo >= 0.0);
  CHECK(hi < 1.0);
  CHECK(std::abs(sum / 100000 - 0.5) < 5 * 9.1e-4);
  CHECK(*std::min_element(hits.begin(), hits.end()) > 0);
}

TEST_CASE("random family: valid, reproducible, as documented") {
  int clamped = 0, unclamped = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const int p = 1 + static_cast<int>(seed % 7), q = 1 + static_cast<int>((seed / 7) % 7);
    const auto a = models::random_surface(seed, p, q, seed % 2 == 0);
    const auto b = models::random_surface(seed, p, q, seed % 2 == 0);
    CAPTURE(seed);
    CHECK(nurbs::validate(a).empty());
    CHECK(a.points == b.points);
    CHECK(a.knots_u == b.knots_u);
    CHECK(a.weights == b.weights);
    // random_surface's documented ranges: degree + 1 + [0, 4] points, domain [a, a + w] with a in
    // [-2, 2] and w in [0.5, 3], points on a grid over [-1, 1]^2 jittered by 0.3, z and weights in range.
    CHECK(a.count_u - p - 1 >= 0);
    CHECK(a.count_u - p - 1 <= 4);
    CHECK(a.count_v - q - 1 >= 0);
    CHECK(a.count_v - q - 1 <= 4);
    for (const auto& [knots, degree, count] :
         {std::tuple{&a.knots_u, p, a.count_u}, std::tuple{&a.knots_v, q, a.count_v}}) {
      const double start = (*knots)[static_cast<size_t>(degree)], end = (*knots)[static_cast<size_t>(count)];
      CHECK(start >= -2.0);
      CHECK(start <= 2.0);
      // 1e-12: start and end are rescaled (unclamped) or computed as a + w (clamped), a few ulps of 5.
      CHECK(end - start >= 0.5 - 1e-12);
      CHECK(end - start <= 3.0 + 1e-12);
      CHECK(std::adjacent_find(knots->begin() + degree + 1, knots->begin() + count, std::greater_equal<>()) ==
            knots->begin() + count);  // simple (strictly increasing) interior knots
    }
    const bool is_clamped = a.knots_u.front() == a.knots_u[static_cast<size_t>(p)];
    (is_clamped ? clamped : unclamped) += 1;
    for (int j = 0; j < a.count_v; ++j) {
      for (int i = 0; i < a.count_u; ++i) {
        const glm::dvec3 pt = a.point(i, j);
        CHECK(std::abs(pt.x - (-1 + 2.0 * i / (a.count_u - 1))) <= 0.3);
        CHECK(std::abs(pt.y - (-1 + 2.0 * j / (a.count_v - 1))) <= 0.3);
        CHECK(std::abs(pt.z) <= 1.0);
      }
    }
    CHECK(a.weights.size() == (seed % 2 == 0 ? a.points.size() : 0u));
    for (double w : a.weights) {
      CHECK(w >= 0.2);
      CHECK(w <= 5.0);
    }
    const auto t = models::random_trimmed_surface(seed);
    CHECK(nurbs::validate(t.surface).empty());
    CHECK(t.face_id == static_cast<int>(seed));
  }
  CHECK(models::random_surface(1, 3, 3, false).points != models::random_surface(2, 3, 3, false).points);
  // "One seed in four gives unclamped knot vectors": 50 expected of 200, both kinds must occur.
  MESSAGE("random family: " << clamped << " clamped, " << unclamped << " unclamped of 200");
  CHECK(clamped > 0);
  CHECK(unclamped > 0);
}

TEST_CASE("Filip K of the 100x105 surface at the note's grid sizes") {
  const auto s = models::wavy_surface_100x105();
  const auto b = nurbs::filip_bound(s);
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : s.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double size = glm::length(hi - lo);  // model size: control-net bbox diagonal (mm)
  const double k1 = nurbs::filip_k_grid(b, 1, 1);
  for (int n : {256, 1024, 2048}) {
    const double k = nurbs::filip_k_grid(b, n, n);
    MESSAGE("100x105 surface, ", n, "x", n, " grid: K = ", k, " mm = ", k / size, " x model size");
    CHECK(k * n * n == doctest::Approx(k1).epsilon(1e-12));  // Eq. 4: K scales as 1/n^2 exactly (n = m)
  }
}
