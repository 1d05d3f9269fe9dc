// Rolling-ball thickness (ball_thickness.h, the shrinking ball) with exact closest points of
// analytic shapes, against independent answers: a wedge (closed form), a spherical shell, and an
// eccentric shell (bisection on the emptiness of the ball tangent at p, the definition).
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <random>

#include "nurbs/raycast/ball_thickness.h"

using nurbs::ray::BallOptions;
using nurbs::ray::NearestPoint;

namespace {

/// Closest point of `c` on the half-plane through the origin spanned by e_y and (cos a, 0, sin a), s >= 0.
glm::dvec3 on_half_plane(const glm::dvec3& c, double a) {
  const glm::dvec3 dir(std::cos(a), 0.0, std::sin(a));
  return std::max(glm::dot(c, dir), 0.0) * dir + glm::dvec3(0.0, c.y, 0.0);
}

/// The union of shapes' closest points, exact (bound 0).
template <class Closest>
nurbs::ray::NearestFn exact(Closest closest) {
  return [closest](const std::vector<glm::dvec3>& cs, const std::vector<double>&) {
    std::vector<NearestPoint> out;
    for (const glm::dvec3& c : cs) {
      const glm::dvec3 q = closest(c);
      out.push_back({true, glm::length(c - q), q, 0.0, 0.0, 0});
    }
    return out;
  };
}

/// Closest point on a sphere (centre m, radius R) or on either of two.
glm::dvec3 on_sphere(const glm::dvec3& c, const glm::dvec3& m, double radius) {
  const glm::dvec3 d = c - m;
  return m + radius * (glm::length(d) > 0.0 ? glm::normalize(d) : glm::dvec3(1, 0, 0));
}

}  // namespace

TEST_CASE("ball thickness: a wedge of angle a gives 2 x tan(a / 2) where the ray gives x tan a") {
  for (const double a : {0.2, 0.6, 1.0, 1.4}) {
    CAPTURE(a);
    std::vector<glm::dvec3> p, n;
    std::vector<double> start;
    for (const double x : {0.5, 1.0, 3.0}) {
      p.emplace_back(x, 0.3, 0.0);  // on the lower face z = 0, inward +z
      n.emplace_back(0.0, 0.0, 1.0);
      start.push_back(0.5 * x * std::tan(a));  // half the ray thickness
    }
    const auto nearest = exact([a](const glm::dvec3& c) {
      const glm::dvec3 low = on_half_plane(c, 0.0), up = on_half_plane(c, a);
      return glm::length(c - low) <= glm::length(c - up) ? low : up;
    });
    BallOptions o;
    o.tolerance = 1e-12;
    nurbs::ray::BallFigures fig;
    const auto b = nurbs::ray::ball_thickness(p, n, start, nearest, o, &fig);
    for (size_t i = 0; i < p.size(); ++i) {
      const double want = 2.0 * p[i].x * std::tan(a / 2.0);
      CHECK(b[i].converged);
      CHECK(b[i].thickness == doctest::Approx(want).epsilon(1e-9));
      CHECK(b[i].thickness < 2.0 * start[i]);
    }
    MESSAGE("wedge " << a << ": " << fig.rounds << " rounds, " << fig.queries << " queries");
  }
}

TEST_CASE("ball thickness: spherical shell from a far start, R_out - R_in") {
  std::vector<glm::dvec3> p, n;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  for (int k = 0; k < 200; ++k) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    p.push_back(10.0 * d);  // outer sphere, inward -d
    n.push_back(-d);
  }
  const auto nearest = exact([](const glm::dvec3& c) {
    const glm::dvec3 a = on_sphere(c, glm::dvec3(0.0), 10.0), b = on_sphere(c, glm::dvec3(0.0), 7.0);
    return glm::length(c - a) <= glm::length(c - b) ? a : b;
  });
  BallOptions o;
  o.tolerance = 1e-10;
  o.max_radius = 20.0;
  const auto b = nurbs::ray::ball_thickness(p, n, std::vector<double>(p.size(), 0.0), nearest, o);
  int wrong = 0;
  for (const auto& s : b) wrong += !s.converged || std::abs(s.thickness - 3.0) > 1e-9;
  CHECK(wrong == 0);
}

TEST_CASE("ball thickness: eccentric shell against bisection on the empty ball") {
  // Inner sphere radius 3 at (2, 0, 0) inside an outer sphere of radius 10 at the origin; samples
  // on the outer sphere. Reference: the largest r with dist(p + r n, inner) >= r and r <= the
  // outer sphere's own limit (the ball tangent at p inside the outer sphere: r <= 10), by bisection.
  const glm::dvec3 m(2.0, 0.0, 0.0);
  const auto nearest = exact([m](const glm::dvec3& c) {
    const glm::dvec3 a = on_sphere(c, glm::dvec3(0.0), 10.0), b = on_sphere(c, m, 3.0);
    return glm::length(c - a) <= glm::length(c - b) ? a : b;
  });
  std::vector<glm::dvec3> p, n;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  for (int k = 0; k < 300; ++k) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    p.push_back(10.0 * d);
    n.push_back(-d);
  }
  BallOptions o;
  o.tolerance = 1e-11;
  o.max_radius = 20.0;
  const auto b = nurbs::ray::ball_thickness(p, n, std::vector<double>(p.size(), 0.0), nearest, o);
  int wrong = 0;
  double worst = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    double lo = 0.0, hi = 10.0;
    for (int it = 0; it < 200; ++it) {
      const double r = 0.5 * (lo + hi);
      (glm::length(p[i] + r * n[i] - m) - 3.0 >= r ? lo : hi) = r;
    }
    worst = std::max(worst, std::abs(b[i].thickness - 2.0 * lo));
    wrong += !b[i].converged || std::abs(b[i].thickness - 2.0 * lo) > 1e-8;
  }
  MESSAGE("eccentric shell: worst |2r - reference| " << worst);
  CHECK(wrong == 0);
}
