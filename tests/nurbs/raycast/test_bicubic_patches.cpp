// §3.1 bicubic approximation: sampled error on random surfaces, exactness on bicubic polynomials.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/raycast/bicubic_patches.h"
#include "nurbs/surface_eval.h"
#include "test_suites.h"
#include "tests/nurbs/raycast/patch_error.h"

using namespace nurbs;
using namespace nurbs::ray;

TEST_CASE("bicubic: error <= tolerance on random surfaces (denser check than the construction's)" * test::sweep()) {
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    const int du = 1 + static_cast<int>(seed % 5), dv = 1 + static_cast<int>((seed / 5) % 5);
    TrimmedSurface face;
    face.surface = models::random_surface(seed, du, dv, seed % 2 == 0);
    BicubicOptions opt;
    opt.tolerance = 1e-4;  // the paper's value; the surfaces span about 2 units
    BicubicStats st;
    const auto patches = bicubic_patches(face, 0, opt, &st);
    CAPTURE(seed);
    REQUIRE(st.converged);
    CHECK(st.patches == static_cast<int>(patches.size()));
    double worst = 0.0;
    for (const auto& p : patches)
      worst = std::max(worst, test::patch_error(face.surface, p, 11));  // 11: other points than the 6 x 6 of the build
    CHECK(worst <= opt.tolerance);
    // The control-point box contains the patch (convex hull): check the centre.
    const glm::dvec3 c = evaluate_patch(patches[0], 0.5, 0.5).s;
    CHECK(glm::all(glm::lessThanEqual(patches[0].box_min, c)));
    CHECK(glm::all(glm::lessThanEqual(c, patches[0].box_max)));
  }
}

TEST_CASE("bicubic: polynomial surfaces of degree <= 3 are reproduced exactly, one patch per knot span") {
  for (std::uint64_t seed = 30; seed < 36; ++seed) {
    TrimmedSurface face;
    face.surface = models::random_surface(seed, 3, 2, false);
    const int spans_u = face.surface.count_u - 3, spans_v = face.surface.count_v - 2;  // simple interior knots
    BicubicStats st;
    const auto patches = bicubic_patches(face, 0, BicubicOptions{}, &st);
    CHECK(st.rounds == 0);
    CHECK(static_cast<int>(patches.size()) == spans_u * spans_v);
    double worst = 0.0;
    for (const auto& p : patches) worst = std::max(worst, test::patch_error(face.surface, p, 7));
    CHECK(worst <= 1e-13);  // Hermite reproduces bicubics: round-off only
  }
}

TEST_CASE("bicubic: culling of cells inside a hole") {
  TrimmedSurface face;
  face.surface = models::rational_sphere(1.0);  // refined in u and v, so cells can lie inside the hole
  BicubicOptions opt;
  opt.tolerance = 1e-5;
  BicubicStats full;
  (void)bicubic_patches(face, 0, opt, &full);
  // A hole covering most of the middle of the (u, v) rectangle [0, 1]^2.
  face.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.45, false)}, false});
  BicubicStats holed;
  const auto patches = bicubic_patches(face, 0, opt, &holed);
  CHECK(holed.culled > 0);
  CHECK(holed.patches < full.patches);  // culled cells also stop driving refinement, so not an equality
  for (const auto& p : patches) {       // no kept patch lies wholly inside the circle (its farthest corner is outside)
    const glm::dvec2 c(0.5, 0.5);
    double far = 0.0;
    for (double u : {p.range_u.min, p.range_u.max})
      for (double v : {p.range_v.min, p.range_v.max}) far = std::max(far, glm::length(glm::dvec2(u, v) - c));
    CHECK(far >= 0.45 - 1e-6);
  }
}
