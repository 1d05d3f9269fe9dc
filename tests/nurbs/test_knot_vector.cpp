// Knot vector validation, span search and basis functions (The NURBS Book §2, A2.1-A2.3).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "nurbs/knot_vector.h"

using nurbs::validate_knots;

namespace {

bool has_problem(const std::vector<std::string>& problems, const std::string& needle) {
  for (const auto& p : problems) {
    if (p.find(needle) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("validate_knots reports each problem") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* name;
    std::vector<double> knots;
    int degree, count;
    const char* expected;  // substring of the one message expected, nullptr = valid
  };
  const Case cases[] = {
      {"clamped cubic", {0, 0, 0, 0, 0.5, 1, 1, 1, 1}, 3, 5, nullptr},
      {"unclamped quadratic", {0, 1, 2, 3, 4, 5, 6}, 2, 4, nullptr},
      {"C0 interior knot (mult = p)", {0, 0, 0, 1, 1, 2, 2, 2}, 2, 5, nullptr},
      {"too few knots", {0, 0, 0, 1, 1}, 2, 3, "expected count + degree + 1 = 6"},
      {"too many knots", {0, 0, 0, 0.5, 1, 1, 1}, 2, 3, "expected count + degree + 1 = 6"},
      {"decreasing", {0, 0, 0, 0.7, 0.4, 1, 1, 1}, 2, 5, "knots decrease at index 4"},
      {"NaN", {0, 0, 0, nan, 1, 1, 1}, 2, 4, "knot 3 is not finite"},
      {"infinity", {0, 0, 0, 0.5, 1, 1, std::numeric_limits<double>::infinity()}, 2, 4, "knot 6 is not finite"},
      {"end multiplicity > p+1", {0, 0, 0, 0, 1, 1, 1}, 2, 4, "multiplicity 4 > degree + 1"},
      {"interior multiplicity p+1", {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, 2, 6, "interior knot 0.5 has multiplicity 3"},
      {"empty domain", {0, 0, 0, 0, 0, 0}, 2, 3, "multiplicity 6"},
      {"degenerate domain", {0, 1, 1, 1, 1, 2}, 3, 2, "control points < degree + 1"},
      {"degree 0", {0, 1}, 0, 1, "degree 0 < 1"},
      {"too few points", {0, 0, 1, 1}, 3, 0, "control points < degree + 1"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const auto problems = validate_knots(c.knots, c.degree, c.count);
    if (c.expected == nullptr) {
      CHECK(problems.empty());
    } else {
      CHECK(has_problem(problems, c.expected));
    }
  }
  // An empty domain inside a correctly sized, monotone vector is its own message.
  CHECK(has_problem(validate_knots({0, 1, 1, 1, 1, 2}, 1, 4), "empty domain"));
}

TEST_CASE("is_clamped and domain") {
  CHECK(nurbs::is_clamped({0, 0, 0, 0.5, 1, 1, 1}, 2));
  CHECK_FALSE(nurbs::is_clamped({0, 1, 2, 3, 4, 5, 6}, 2));
  CHECK_FALSE(nurbs::is_clamped({0, 0, 0, 0.5, 1, 1, 2}, 2));
  const auto d = nurbs::knot_domain({0, 1, 2, 3, 4, 5, 6}, 2, 4);
  CHECK(d.min == 2.0);
  CHECK(d.max == 4.0);
}

TEST_CASE("find_span (A2.1) including u = u_max") {
  // The NURBS Book Ex 2.3 knot vector, p = 2, n + 1 = 8 points.
  const std::vector<double> U = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  struct Case {
    double u;
    int span;
  };
  const Case cases[] = {{0.0, 2}, {0.5, 2}, {1.0, 3}, {2.5, 4},  {3.999, 5},
                        {4.0, 7}, {4.5, 7}, {5.0, 7}, {-1.0, 2}, {6.0, 7}};
  for (const auto& c : cases) {
    CAPTURE(c.u);
    CHECK(nurbs::find_span(U, 2, 8, c.u) == c.span);
  }
  // Unclamped vector whose last span of the domain is followed by repeated knots: u_max picks the
  // last non-empty span, not an empty one.
  const std::vector<double> V = {0, 0, 0, 1, 1, 1, 2};
  CHECK(nurbs::find_span(V, 2, 4, 1.0) == 2);
}

TEST_CASE("basis functions: The NURBS Book Ex 2.3 at u = 5/2") {
  const std::vector<double> U = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  const int span = nurbs::find_span(U, 2, 8, 2.5);
  REQUIRE(span == 4);
  const auto N = nurbs::basis_functions(U, 2, span, 2.5);
  // Ex 2.3: N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8; exact in binary, so compare to 1e-15 (roundoff).
  CHECK(N[0] == doctest::Approx(1.0 / 8).epsilon(1e-15));
  CHECK(N[1] == doctest::Approx(6.0 / 8).epsilon(1e-15));
  CHECK(N[2] == doctest::Approx(1.0 / 8).epsilon(1e-15));
  // Ex 2.4 derivatives at 5/2: N'_{2,2} = -1/2, N'_{3,2} = 0, N'_{4,2} = 1/2; second: 1, -2, 1.
  const auto D = nurbs::basis_function_derivatives(U, 2, span, 2.5, 3);
  const double expected[4][3] = {{0.125, 0.75, 0.125}, {-0.5, 0.0, 0.5}, {1.0, -2.0, 1.0}, {0.0, 0.0, 0.0}};
  for (int k = 0; k <= 3; ++k) {
    for (int j = 0; j < 3; ++j)
      CHECK(D[static_cast<size_t>(k * 3 + j)] == doctest::Approx(expected[k][j]).epsilon(1e-14));
  }
}

TEST_CASE("basis functions: partition of unity and derivative sums vanish") {
  const std::vector<double> U = {-1, -1, -1, -1, -0.3, 0.2, 0.2, 0.9, 1.7, 1.7, 1.7, 1.7};
  const int p = 3, count = 8;
  for (int s = 0; s <= 200; ++s) {
    const double u = -1 + 2.7 * s / 200;
    const int span = nurbs::find_span(U, p, count, u);
    const auto D = nurbs::basis_function_derivatives(U, p, span, u, 2);
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j <= p; ++j) sum[k] += D[static_cast<size_t>(k * (p + 1) + j)];
    }
    // Sums are exact identities; 1e-12 allows roundoff of O(10) terms with derivative sizes ~ 100.
    CHECK(sum[0] == doctest::Approx(1.0).epsilon(1e-14));
    CHECK(std::abs(sum[1]) < 1e-12);
    CHECK(std::abs(sum[2]) < 1e-11);
  }
}
