// §3.4 point-in-trim test on cubic Bézier trims vs the flattened-loop winding oracle (is_material).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/curve_eval.h"
#include "nurbs/raycast/trim_test.h"
#include "nurbs/trim_classify.h"

using namespace nurbs;
using namespace nurbs::ray;

namespace {

/// Distance from p to the flattened loops (the oracle's boundary).
double boundary_distance(const TrimPolygons& t, glm::dvec2 p) {
  double d = std::numeric_limits<double>::infinity();
  auto seg = [&](glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 e = b - a;
    const double lam = glm::dot(e, e) > 0 ? std::clamp(glm::dot(p - a, e) / glm::dot(e, e), 0.0, 1.0) : 0.0;
    d = std::min(d, glm::length(a + lam * e - p));
  };
  for (const auto& loop : t.loops)
    for (size_t i = 0; i < loop.size(); ++i) seg(loop[i], loop[(i + 1) % loop.size()]);
  const glm::dvec2 c[4] = {{t.domain_u.min, t.domain_v.min},
                           {t.domain_u.max, t.domain_v.min},
                           {t.domain_u.max, t.domain_v.max},
                           {t.domain_u.min, t.domain_v.max}};
  for (int i = 0; i < 4; ++i) seg(c[i], c[(i + 1) % 4]);
  return d;
}

}  // namespace

TEST_CASE("trim cubics: within tolerance of the exact rational circle, reproduce lines exactly") {
  TrimmedSurface face;
  face.surface = models::random_surface(3, 2, 2, false);
  face.loops.push_back({{models::rational_circle_2d({0.1, 0.2}, 0.3, false)}, false});
  const double tol = 1e-6;
  const TrimCubics tc = trim_cubics(face, tol);
  CHECK(tc.max_error <= tol);
  // Every cubic's points lie on the circle to within tol (a check independent of the construction's samples).
  double worst = 0.0;
  REQUIRE(tc.cubics.size() > 4);
  for (size_t i = 0; i + 4 < tc.cubics.size(); ++i)  // the last 4: the domain rectangle (no outer loop)
    for (double t : {0.05, 0.37, 0.61, 0.93}) {
      const double s = 1 - t;
      const auto& c = tc.cubics[i].p;
      const glm::dvec2 q = s * s * s * c[0] + 3 * s * s * t * c[1] + 3 * s * t * t * c[2] + t * t * t * c[3];
      worst = std::max(worst, std::abs(glm::length(q - glm::dvec2(0.1, 0.2)) - 0.3));
    }
  CHECK(worst <= tol);
}

TEST_CASE("trim test (§3.4) agrees with is_material on random faces away from the boundary") {
  int compared = 0, disagree = 0, near_disagree = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const TrimmedSurface face = models::random_trimmed_surface(seed);
    const Interval du = knot_domain(face.surface.knots_u, face.surface.degree_u, face.surface.count_u);
    const Interval dv = knot_domain(face.surface.knots_v, face.surface.degree_v, face.surface.count_v);
    const double diag = std::hypot(du.max - du.min, dv.max - dv.min);
    const double tol = 1e-7 * diag;  // cubic trims and oracle polygons both within 1e-7 of the domain
    const TrimCubics tc = trim_cubics(face, tol);
    const TrimPolygons oracle = flatten_trim(face, tol);
    models::Random rng(seed * 7 + 1);
    for (int k = 0; k < 500; ++k) {
      const glm::dvec2 p(rng.uniform(du.min, du.max), rng.uniform(dv.min, dv.max));
      const bool differs = inside_trim(tc, p) != is_material(oracle, p);
      // Both boundaries are within tol of the exact one: only points within 2 tol may differ.
      if (boundary_distance(oracle, p) > 2.0 * tol) {
        ++compared;
        disagree += differs;
      } else {
        near_disagree += differs;
      }
    }
  }
  CHECK(compared > 15000);
  CHECK(disagree == 0);
  MESSAGE("trim test: " << compared << " points compared, " << disagree << " disagreements");
}

TEST_CASE("trim test (§3.4): dead angles at a convex and a concave corner") {
  // An L-shaped outer loop of lines, counter-clockwise; (0.5, 0.5) is its one concave corner.
  TrimmedSurface face;
  face.surface.degree_u = face.surface.degree_v = 1;
  face.surface.count_u = face.surface.count_v = 2;
  face.surface.knots_u = face.surface.knots_v = {0, 0, 1, 1};
  face.surface.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const glm::dvec2 corners[6] = {{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.5}, {0.5, 0.5}, {0.5, 0.9}, {0.1, 0.9}};
  TrimLoop loop;
  for (int i = 0; i < 6; ++i) {
    Curve2 line;
    line.degree = 1;
    line.knots = {0, 0, 1, 1};
    line.points = {corners[i], corners[(i + 1) % 6]};
    loop.curves.push_back(line);
  }
  face.loops.push_back(loop);
  const TrimCubics tc = trim_cubics(face, 1e-9);
  // Convex corner (0.9, 0.1): the dead angle is the quadrant u > 0.9, v < 0.1, outside the material
  // (the nearest point of both edges is the corner): never material, also on the bisector.
  for (double d : {1e-6, 1e-3, 0.05})
    for (double skew : {0.0, 0.3 * d, -0.3 * d}) CHECK_FALSE(inside_trim(tc, {0.9 + d + skew, 0.1 - d + skew}));
  // Concave corner (0.5, 0.5): the dead angle u < 0.5, v < 0.5 lies in the material: always material.
  for (double d : {1e-6, 1e-3, 0.05})
    for (double skew : {0.0, 0.3 * d, -0.3 * d}) CHECK(inside_trim(tc, {0.5 - d + skew, 0.5 - d - skew}));
  // Just across each corner's edges the ordinary side test decides.
  CHECK(inside_trim(tc, {0.89, 0.11}));
  CHECK_FALSE(inside_trim(tc, {0.51, 0.51}));
  CHECK_FALSE(inside_trim(tc, {0.7, 0.7}));
  CHECK(inside_trim(tc, {0.3, 0.3}));
}
