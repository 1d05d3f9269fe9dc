// Clearance (Krishnamurthy et al. §5.1-5.3): the GPU hierarchy descent against an exhaustive CPU
// twin over all cell pairs (same triangles in double), exact spheres (|d - d*| < K_a + K_b), and a
// rigid motion applied in the leaf pass against the same model moved beforehand.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "../gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "queries/clearance.h"

namespace {

/// Every cell pair of the two models, two triangles each, in double: the exhaustive twin.
double brute_force(const queries::PreparedModel& a, const queries::PreparedModel& b) {
  double best = 1e300;
  auto tris = [](const queries::PreparedModel& m, size_t f) {
    std::vector<std::array<glm::dvec3, 3>> out;
    const auto& g = m.grids[f].grid;
    const auto& s = m.faces[f].surface;
    for (int j = 0; j < g.cells_v(); ++j)
      for (int i = 0; i < g.cells_u(); ++i) {
        const auto p = [&](int di, int dj) {
          return nurbs::surface_point(s, g.u[size_t(i + di)], g.v[size_t(j + dj)]);
        };
        out.push_back({p(0, 0), p(1, 0), p(1, 1)});
        out.push_back({p(0, 0), p(1, 1), p(0, 1)});
      }
    return out;
  };
  for (size_t fa = 0; fa < a.faces.size(); ++fa)
    for (size_t fb = 0; fb < b.faces.size(); ++fb) {
      const auto ta = tris(a, fa), tb = tris(b, fb);
      for (const auto& x : ta)
        for (const auto& y : tb) {
          glm::dvec3 pa, pb, wa, wb;
          best = std::min(best, queries::triangle_distance(x.data(), y.data(), pa, pb, wa, wb));
        }
    }
  return best;
}

}  // namespace

TEST_CASE("clearance: hierarchy descent equals the exhaustive twin on random surface pairs") {
  gpgpu::Gpu& gpu = test::gpu();
  int cases = 0;
  size_t max_levels = 0;
  for (uint64_t seed = 0; seed < 10; ++seed) {
    nurbs::TrimmedSurface fa, fb;
    fa.surface = models::random_surface(seed + 300, 1 + int(seed % 3), 2, seed % 2 == 1);
    fb.surface = models::random_surface(seed + 700, 2, 1 + int(seed % 3), seed % 3 == 1);
    for (auto& p : fb.surface.points) p += glm::dvec3(0.3, -0.2, 2.0 + 0.1 * double(seed));
    const auto a = queries::prepare_model(gpu, {fa}, 2e-2);
    const auto b = queries::prepare_model(gpu, {fb}, 2e-2);
    const queries::Clearance c = queries::clearance(gpu, a, b);
    CAPTURE(seed);
    REQUIRE(c.found);
    CHECK(c.distance == doctest::Approx(brute_force(a, b)).epsilon(1e-12));
    CHECK(c.bound <= 4e-2);
    CHECK(std::abs(glm::length(c.point_a - c.point_b) - c.distance) < 1e-12);
    max_levels = std::max(max_levels, c.pairs_per_level.size());
    ++cases;
  }
  MESSAGE(cases << " pairs, up to " << max_levels << " levels");
}

TEST_CASE("clearance: two exact spheres, and a rigid motion of the second") {
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  const auto a = queries::prepare_model(gpu, {s1}, 1e-3);
  const auto b = queries::prepare_model(gpu, {s2}, 1e-3);
  for (double gap : {0.05, 0.7, 3.0}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1, 2, -0.5));
    // Rotate the second sphere about an axis through its centre (no change), then move it.
    const glm::dmat4 motion =
        glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir) * glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0.3, 1, 0.2));
    const queries::Clearance c = queries::clearance(gpu, a, b, motion);
    CAPTURE(gap);
    REQUIRE(c.found);
    CHECK(std::abs(c.distance - gap) < c.bound);
    CHECK(c.bound <= 2e-3);
    CHECK(glm::length(c.point_a - dir) < 0.1);  // near the true closest point of the first sphere
    MESSAGE("gap " << gap << ": distance " << c.distance << " +- " << c.bound << ", pairs per level "
                   << c.pairs_per_level.size() << " levels, " << c.leaf_pairs << " leaf pairs");
  }
}
