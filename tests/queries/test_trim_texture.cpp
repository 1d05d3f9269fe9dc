// Trim textures against the CPU winding-number classification on the random trimmed family and
// the paper's trimmed 100x105 surface: equal everywhere except within one grid cell of a trim curve.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "../gpgpu/gl_fixture.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/trim_texture.h"

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

void check_face(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, int n, int m, int& differ, int& material) {
  const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
  const double hu = du.width() / n, hv = dv.width() / m, tol = 0.1 * std::min(hu, hv);
  const auto gpu_mask = queries::trim_texture(gpu, face, n, m, tol).read();
  const auto cpu_mask = queries::trim_mask_cpu(face, n, m, tol);
  const nurbs::TrimPolygons t = nurbs::flatten_trim(face, tol);
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) {
      const size_t k = size_t(j) * size_t(n + 1) + size_t(i);
      material += cpu_mask[k];
      if ((gpu_mask[k] > 0.5f) != (cpu_mask[k] != 0)) {
        ++differ;
        const glm::dvec2 uv(du.min + hu * i, dv.min + hv * j);
        CHECK(cells_to_trim(t, uv, hu, hv) <= 1.0);
      }
    }
}

}  // namespace

TEST_CASE("trim texture: agrees with the CPU classification on random trimmed faces") {
  gpgpu::Gpu& gpu = test::gpu();
  int differ = 0, material = 0;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    CAPTURE(seed);
    check_face(gpu, models::random_trimmed_surface(seed), 64 + int(seed % 5) * 17, 48 + int(seed % 3) * 31, differ,
               material);
  }
  CHECK(material > 0);
  MESSAGE("random faces: " << differ << " samples differ (all within one cell of a trim curve), " << material
                           << " material samples");
}

TEST_CASE("trim texture: the paper's trimmed 100x105 surface") {
  gpgpu::Gpu& gpu = test::gpu();
  int differ = 0, material = 0;
  check_face(gpu, models::trimmed_wavy_surface_100x105(), 256, 256, differ, material);
  CHECK(material > 256 * 256 / 4);
  CHECK(material < 257 * 257);  // the holes remove something
  MESSAGE("trimmed 100x105 at 257^2: " << differ << " samples differ, " << material << " material");
}
