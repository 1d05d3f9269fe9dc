// Batched evaluation: many faces' grids packed into one atlas, evaluated in one pass and
// trimmed in one fill, against the CPU twins of each face (points in double, winding-number masks).
#include <doctest/doctest.h>

#include <algorithm>
#include <glm/geometric.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "gpgpu/polygon_fill.h"
#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/face_atlas.h"
#include "queries/distance/surface_grid.h"
#include "queries/distance/trim_texture.h"

namespace {

/// Faces with their uniform n x m grids, atlas sizes and trim flattening tolerances (a tenth of a cell).
struct AtlasFaces {
  std::vector<nurbs::TrimmedSurface> faces;
  std::vector<nurbs::ParamGrid> grids;
  std::vector<std::pair<int, int>> sizes;
  std::vector<double> flatten;
  void add(nurbs::TrimmedSurface f, int n, int m) {
    const nurbs::Interval du = nurbs::surface_domain_u(f.surface), dv = nurbs::surface_domain_v(f.surface);
    grids.push_back(nurbs::uniform_param_grid(du, dv, n, m));
    sizes.emplace_back(n + 1, m + 1);
    flatten.push_back(0.1 * std::min(du.width() / n, dv.width() / m));
    faces.push_back(std::move(f));
  }
};

}  // namespace

TEST_CASE("face atlas: packing keeps slots apart, within the side and the sample budget") {
  std::vector<std::pair<int, int>> sizes;
  models::Random rng(5);
  for (int k = 0; k < 300; ++k) sizes.emplace_back(rng.integer(2, 90), rng.integer(2, 90));
  sizes.emplace_back(300, 4);  // wider than the side: left to the tiled path
  std::vector<int> unpacked;
  const auto plans = queries::plan_atlases(sizes, 256, 40'000, unpacked);
  CHECK(unpacked == std::vector<int>{300});
  size_t slots = 0;
  for (const auto& plan : plans) {
    long long used = 0;
    CHECK(plan.width <= 256);
    CHECK(plan.height <= 256);
    for (size_t a = 0; a < plan.slots.size(); ++a) {
      const auto& s = plan.slots[a];
      CHECK(s.width == sizes[size_t(s.face)].first);
      CHECK(s.height == sizes[size_t(s.face)].second);
      CHECK(s.x + s.width <= plan.width);
      CHECK(s.y + s.height <= plan.height);
      CHECK(s.x % queries::kSlotAlign == 0);  // aligned: pyramid nodes below that size hold one face
      CHECK(s.y % queries::kSlotAlign == 0);
      used += static_cast<long long>(s.width) * s.height;
      for (size_t b = 0; b < a; ++b) {
        const auto& t = plan.slots[b];
        const bool apart =
            s.x + s.width <= t.x || t.x + t.width <= s.x || s.y + s.height <= t.y || t.y + t.height <= s.y;
        CHECK(apart);
      }
    }
    CHECK(used <= 40'000);
    slots += plan.slots.size();
  }
  CHECK(slots == 300);
  MESSAGE("300 grids of 2-90 samples in " << plans.size() << " atlases of at most 256^2 and 40000 samples");
}

TEST_CASE("face atlas: one pass evaluates every face as its CPU twin, one fill trims them") {
  gpgpu::Gpu& gpu = test::gpu();
  AtlasFaces set;
  for (uint64_t seed = 0; seed < 40; ++seed)
    set.add(models::random_trimmed_surface(seed), 8 + int(seed * 7 % 50), 5 + int(seed * 11 % 40));
  const auto& [faces, grids, sizes, flatten] = set;
  std::vector<int> unpacked;
  const auto plans = queries::plan_atlases(sizes, 200, 1 << 20, unpacked);
  REQUIRE(unpacked.empty());
  REQUIRE(plans.size() >= 2);  // more than one atlas at this side
  double worst = 0.0;
  int differ = 0, samples = 0, outside_nonzero = 0;
  for (const auto& plan : plans) {
    const queries::FaceAtlas atlas = queries::evaluate_atlas(gpu, plan, faces, grids, flatten);
    const auto pts = atlas.points.read(), mask = atlas.mask.read();
    std::vector<char> covered(size_t(plan.width) * size_t(plan.height), 0);
    for (const auto& sl : plan.slots) {
      const auto& f = faces[size_t(sl.face)];
      const auto cpu = queries::evaluate_surface_cpu(f.surface, grids[size_t(sl.face)]);
      const auto cpu_mask = queries::trim_mask_cpu(f, grids[size_t(sl.face)], flatten[size_t(sl.face)]);
      const double size = nurbs::control_box(f.surface).diagonal();
      for (int j = 0; j < sl.height; ++j)
        for (int i = 0; i < sl.width; ++i) {
          const size_t t = size_t(sl.y + j) * size_t(plan.width) + size_t(sl.x + i);
          covered[t] = 1;
          const size_t k = size_t(j) * size_t(sl.width) + size_t(i);
          const glm::dvec3 g(pts[4 * t], pts[4 * t + 1], pts[4 * t + 2]);
          worst = std::max(worst, glm::length(g - cpu.points[k]) / size);
          differ += (mask[t] > 0.5f) != (cpu_mask[k] != 0) ? 1 : 0;
          ++samples;
        }
    }
    for (size_t t = 0; t < covered.size(); ++t)
      if (!covered[t] && (pts[4 * t + 3] != 0.0f || mask[t] != 0.0f)) ++outside_nonzero;
  }
  CHECK(worst <= 5e-7);             // the tabulated float budget (surface_grid.h)
  CHECK(differ <= samples / 2000);  // as the single-face masks (test_trim_texture.cpp)
  CHECK(outside_nonzero == 0);      // nothing leaks between slots
  MESSAGE(faces.size() << " faces in " << plans.size() << " atlases: GPU-CPU error / size " << worst << ", " << differ
                       << " of " << samples << " mask samples differ");
}

TEST_CASE("face atlas: untrimmed faces get the mask the polygon fill gives, without the fill") {
  // An atlas of faces without trim loops uploads its slots' rectangles as the mask; the fill of
  // their window polygons (what every atlas took before) must give the same texels.
  gpgpu::Gpu& gpu = test::gpu();
  AtlasFaces set;
  for (uint64_t seed = 0; seed < 12; ++seed) {
    nurbs::TrimmedSurface f;  // no loops
    f.surface = models::random_surface(seed + 300, 1 + int(seed % 3), 1 + int(seed / 3 % 3), seed % 2);
    set.add(std::move(f), 5 + int(seed * 7 % 30), 4 + int(seed * 11 % 25));
  }
  const auto& [faces, grids, sizes, flatten] = set;
  std::vector<int> unpacked;
  const auto plans = queries::plan_atlases(sizes, 64, 1 << 20, unpacked);
  REQUIRE(unpacked.empty());
  int inside = 0, differ = 0;
  for (const auto& plan : plans) {
    const queries::FaceAtlas atlas = queries::evaluate_atlas(gpu, plan, faces, grids, flatten);
    std::vector<std::vector<glm::vec2>> polygons;
    for (const auto& sl : plan.slots)
      for (auto poly :
           queries::trim_window_polygons(faces[size_t(sl.face)], grids[size_t(sl.face)], flatten[size_t(sl.face)])) {
        // The domain rectangle grown past the samples, clipped to the slot (as evaluate_atlas
        // clips every polygon; for an axis-aligned rectangle clamping its corners is the clip).
        const glm::vec2 lo(float(sl.x), float(sl.y)), hi(float(sl.x + sl.width), float(sl.y + sl.height));
        for (glm::vec2& v : poly) v = glm::clamp(v + lo, lo, hi);
        polygons.push_back(std::move(poly));
      }
    gpgpu::Texture filled(plan.width, plan.height, gpgpu::Format::R8);
    gpgpu::fill_polygons_even_odd(gpu, polygons, filled);
    const auto got = atlas.mask.read(), want = filled.read();
    REQUIRE(got.size() == want.size());
    for (size_t t = 0; t < got.size(); ++t) {
      inside += want[t] > 0.5f ? 1 : 0;
      differ += (got[t] > 0.5f) != (want[t] > 0.5f) ? 1 : 0;
    }
  }
  CHECK(inside > 1000);
  CHECK(differ == 0);
  MESSAGE(plans.size() << " atlases, " << inside << " material texels, " << differ << " differ");
}
