// Clearance's intersection test (queries/distance/intersection.h): two overlapping exact spheres meet on
// their circle; a point of that circle inside a hole of one face is no common point.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <utility>
#include <vector>

#include "models/exact_shapes.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "queries/distance/intersection.h"

TEST_CASE("intersection: two overlapping spheres meet on their circle; not where a hole is") {
  nurbs::TrimmedSurface a, b;
  a.surface = models::rational_sphere(1.0);
  b.surface = models::rational_sphere(1.0);
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), {1.0, 0.0, 0.0});  // circle x = 0.5, r = sqrt(3)/2
  const nurbs::Interval du = nurbs::surface_domain_u(a.surface), dv = nurbs::surface_domain_v(a.surface);
  // Starts as a clearance's closest pair gives them: points of A within 0.05 of the circle, and B's
  // point nearest to each (its parameters by projection).
  std::vector<std::pair<glm::dvec2, glm::dvec3>> grid;  // B's samples, to seed the projection
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i) {
      const glm::dvec2 uv(du.min + du.width() * i / 40, dv.min + dv.width() * j / 40);
      grid.emplace_back(uv, nurbs::surface_point(b.surface, uv.x, uv.y));
    }
  std::vector<std::pair<glm::dvec2, glm::dvec2>> starts;
  for (int j = 1; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const glm::dvec2 uv(du.min + du.width() * (i + 0.5) / 40, dv.min + dv.width() * j / 40);
      const glm::dvec3 p = nurbs::surface_point(a.surface, uv.x, uv.y);
      if (std::abs(p.x - 0.5) > 0.05) continue;
      const glm::dvec3 q = p - glm::dvec3(1.0, 0.0, 0.0);
      glm::dvec2 seed = grid.front().first;
      for (const auto& [g, x] : grid)
        if (glm::distance(x, q) < glm::distance(nurbs::surface_point(b.surface, seed.x, seed.y), q)) seed = g;
      starts.emplace_back(uv, nurbs::project_point(b.surface, q, seed, 20));
    }
  REQUIRE(starts.size() >= 20);
  int found = 0;
  for (const auto& [uv_a, uv_b] : starts) {
    const auto x = queries::find_intersection(a, {}, uv_a, b, {}, uv_b, motion, 1e-12);
    if (!x) continue;
    ++found;
    CHECK(std::abs(glm::length(x->point) - 1.0) < 1e-9);
    CHECK(std::abs(glm::length(x->point - glm::dvec3(1.0, 0.0, 0.0)) - 1.0) < 1e-9);
    CHECK(x->residual <= 1e-12);
  }
  CHECK(found == int(starts.size()));
  // Apart: no common point.
  CHECK(!queries::find_intersection(a, {}, {du.min + 0.1, dv.min + 0.5 * dv.width()}, b, {},
                                    {du.min + 0.1, dv.min + 0.5 * dv.width()},
                                    glm::translate(glm::dmat4(1.0), {3.0, 0.0, 0.0}), 1e-12));
  // A's whole domain cut away but a sliver: the circle's points lie in its hole.
  nurbs::TrimmedSurface holed = a;
  nurbs::TrimLoop hole;
  hole.outer = false;
  hole.curves.push_back(models::rational_circle_2d({0.5 * (du.min + du.max), 0.5 * (dv.min + dv.max)},
                                                   0.49 * std::min(du.width(), dv.width()), false));
  holed.loops.push_back(hole);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(holed, 1e-9);
  int in_hole = 0, tried = 0;
  for (const auto& [uv_a, uv_b] : starts) {
    const auto plain = queries::find_intersection(a, {}, uv_a, b, {}, uv_b, motion, 1e-12);
    if (!plain || nurbs::is_material(trim, plain->uv_a)) continue;
    ++tried;
    in_hole += !queries::find_intersection(holed, trim, uv_a, b, {}, uv_b, motion, 1e-12).has_value();
  }
  CHECK(tried > 0);
  CHECK(in_hole == tried);
}
