// Trim textures against the CPU winding-number classification on the random trimmed family and
// the paper's trimmed 100x105 surface: equal everywhere except within one grid cell of a trim curve.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "tests/gpgpu/gl_fixture.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/surface_grid.h"
#include "queries/distance/trim_texture.h"

namespace {

/// Distance from (u, v) to the flattened trim curves, measured in grid cells (u in units of h_u).
double cells_to_trim(const nurbs::TrimPolygons& t, glm::dvec2 uv, double hu, double hv) {
  double best = 1e30;
  for (const auto& loop : t.loops)
    for (size_t a = 0, b = loop.size() - 1; a < loop.size(); b = a++) {
      const glm::dvec2 A(loop[a].x / hu, loop[a].y / hv), B(loop[b].x / hu, loop[b].y / hv), P(uv.x / hu, uv.y / hv);
      const glm::dvec2 d = B - A;
      const double dd = d.x * d.x + d.y * d.y;
      const double t01 = dd > 0 ? std::clamp(((P - A).x * d.x + (P - A).y * d.y) / dd, 0.0, 1.0) : 0.0;
      const glm::dvec2 q = A + t01 * d - P;
      best = std::min(best, std::sqrt(q.x * q.x + q.y * q.y));
    }
  return best;
}

/// Counts of one comparison.
struct Counts {
  int differ = 0, material = 0, samples = 0;
};

/// GPU mask (in tiles of `tile_side`, reassembled) against the CPU classification on any grid;
/// every differing sample must lie within one cell (of its own size) of a trim curve.
void check_face(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, const nurbs::ParamGrid& g, int tile_side,
                Counts& c) {
  const double tol = queries::trim_flatten_tolerance(g);
  const auto tiles = queries::trim_masks(gpu, face, g, tile_side, tol);
  const auto starts_u = queries::tile_starts(int(g.u.size()), tile_side);
  const auto starts_v = queries::tile_starts(int(g.v.size()), tile_side);
  REQUIRE(tiles.size() == starts_u.size() * starts_v.size());
  const auto cpu_mask = queries::trim_mask_cpu(face, g, tol);
  const nurbs::TrimPolygons t = nurbs::flatten_trim(face, tol);
  for (size_t tv = 0; tv < starts_v.size(); ++tv)
    for (size_t tu = 0; tu < starts_u.size(); ++tu) {
      const gpgpu::Texture& tex = tiles[tv * starts_u.size() + tu];
      const auto mask = tex.read();
      for (int y = 0; y < tex.height(); ++y)
        for (int x = 0; x < tex.width(); ++x) {
          const size_t i = size_t(starts_u[tu] + x), j = size_t(starts_v[tv] + y);
          const size_t k = j * g.u.size() + i;
          c.material += cpu_mask[k];
          ++c.samples;
          if ((mask[size_t(y * tex.width() + x)] > 0.5f) != (cpu_mask[k] != 0)) {
            ++c.differ;
            const double hu = g.u[std::min(i + 1, g.u.size() - 1)] - g.u[std::min(i, g.u.size() - 2)];
            const double hv = g.v[std::min(j + 1, g.v.size() - 1)] - g.v[std::min(j, g.v.size() - 2)];
            CHECK(cells_to_trim(t, {g.u[i], g.v[j]}, hu, hv) <= 1.0);
          }
        }
    }
}

void check_face(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, int n, int m, Counts& c) {
  const auto g =
      nurbs::uniform_param_grid(nurbs::surface_domain_u(face.surface), nurbs::surface_domain_v(face.surface), n, m);
  check_face(gpu, face, g, 1 << 14, c);
}

}  // namespace

TEST_CASE("trim texture: agrees with the CPU classification on random trimmed faces") {
  gpgpu::Gpu& gpu = test::gpu();
  Counts c;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    CAPTURE(seed);
    check_face(gpu, models::random_trimmed_surface(seed), 64 + int(seed % 5) * 17, 48 + int(seed % 3) * 31, c);
  }
  CHECK(c.material > c.samples / 4);
  // Differences sit only next to trim curves (checked per sample); their count is bounded too:
  // measured 2 in 475200 (0.0004 %) here and 6 in 207360 on piecewise grids; allowed 0.05 %.
  CHECK(c.differ <= c.samples / 2000);
  MESSAGE("random faces: " << c.differ << " of " << c.samples
                           << " samples differ (all within one cell of a trim curve), " << c.material
                           << " material samples");
}

TEST_CASE("trim texture: the paper's trimmed 100x105 surface") {
  gpgpu::Gpu& gpu = test::gpu();
  Counts c;
  check_face(gpu, models::trimmed_wavy_surface_100x105(), 256, 256, c);
  CHECK(c.material > 256 * 256 / 4);
  CHECK(c.material < 257 * 257);        // the holes remove something
  CHECK(c.differ <= c.samples / 2000);  // as above
  MESSAGE("trimmed 100x105 at 257^2: " << c.differ << " samples differ, " << c.material << " material");
}

TEST_CASE("trim texture: knot-aligned grids and tiles, same samples as the evaluation") {
  gpgpu::Gpu& gpu = test::gpu();
  Counts c;
  for (uint64_t seed = 0; seed < 30; ++seed) {
    CAPTURE(seed);
    nurbs::TrimmedSurface face = models::random_trimmed_surface(seed);
    // Piecewise-uniform grid: three segments of different steps along each direction.
    const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
    nurbs::ParamGrid g;
    auto pieces = [](nurbs::Interval d, std::vector<double>& t, int a, int b, int c3) {
      const double l1 = d.min + 0.3 * d.width(), l2 = d.min + 0.45 * d.width();
      for (int k = 0; k < a; ++k) t.push_back(d.min + (l1 - d.min) * k / a);
      for (int k = 0; k < b; ++k) t.push_back(l1 + (l2 - l1) * k / b);
      for (int k = 0; k < c3; ++k) t.push_back(l2 + (d.max - l2) * k / c3);
      t.push_back(d.max);
    };
    pieces(du, g.u, 20, 60, 15);
    pieces(dv, g.v, 11, 7, 50);
    check_face(gpu, face, g, seed % 2 ? 1 << 14 : 23, c);
  }
  CHECK(c.material > c.samples / 4);
  CHECK(c.differ <= c.samples / 2000);  // as above
  MESSAGE("piecewise-uniform grids: " << c.differ << " of " << c.samples << " samples differ");
}
