// Rolling-ball thickness (nurbs/raycast/ball_thickness.h) over the batched point query of
// Krishnamurthy et al. (queries/distance/point_batch.h) on an eccentric spherical shell built of exact
// rational spheres: the GPU query and its double-precision twin (PointBatch::query_cpu) against an
// independent reference (bisection on the emptiness of the ball, with the spheres' exact
// distances), each within its reported bound.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <random>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "nurbs/raycast/ball_thickness.h"
#include "queries/distance/ball_nearest.h"
#include "queries/distance/prepared_model.h"

TEST_CASE("ball thickness over the GPU point batch and its CPU twin: eccentric shell within the bound") {
  const glm::dvec3 m(2.0, 0.0, 0.0);  // inner sphere radius 3 at m, outer radius 10 at the origin
  nurbs::TrimmedSurface outer, inner;
  outer.surface = models::rational_sphere(10.0);
  inner.surface = models::rational_sphere(3.0, m);
  const double size = 20.0 * std::sqrt(3.0);
  gpgpu::Gpu& gpu = test::gpu();
  const queries::PreparedModel prepared = queries::prepare_model(gpu, {outer, inner}, 1e-4 * size);
  queries::PointBatch batch(gpu, prepared);
  std::vector<glm::dvec3> p, n;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g;
  for (int k = 0; k < 100; ++k) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    p.push_back(10.0 * d);
    n.push_back(-d);
  }
  nurbs::ray::BallOptions o;
  o.tolerance = 1e-6 * size;
  o.max_radius = 20.0;
  const std::vector<double> start(p.size(), 0.0);
  nurbs::ray::BallFigures fig;
  const auto on_gpu = nurbs::ray::ball_thickness(p, n, start, queries::ball_nearest(batch), o, &fig);
  const auto on_cpu = nurbs::ray::ball_thickness(p, n, start, queries::ball_nearest(batch, true), o);
  int outside = 0, twins_apart = 0, unconverged = 0;
  double worst = 0.0, worst_bound = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    double lo = 0.0, hi = 10.0;  // the largest r with dist(p + r n, inner) >= r (the outer limits r to 10)
    for (int it = 0; it < 200; ++it) {
      const double r = 0.5 * (lo + hi);
      (glm::length(p[i] + r * n[i] - m) - 3.0 >= r ? lo : hi) = r;
    }
    const double err = std::abs(on_gpu[i].thickness - 2.0 * lo);
    worst = std::max(worst, err);
    worst_bound = std::max(worst_bound, on_gpu[i].bound);
    outside += err > on_gpu[i].bound;
    twins_apart += std::abs(on_gpu[i].thickness - on_cpu[i].thickness) > on_gpu[i].bound + on_cpu[i].bound;
    unconverged += !on_gpu[i].converged;
  }
  MESSAGE("eccentric shell, 100 samples: " << fig.rounds << " rounds, " << fig.queries << " queries; worst |2r - ref| "
                                           << worst << ", worst bound " << worst_bound);
  CHECK(outside == 0);
  CHECK(twins_apart == 0);
  CHECK(unconverged == 0);
  CHECK(worst > 0.0);  // the grid's error shows: the comparison is not vacuous
}
