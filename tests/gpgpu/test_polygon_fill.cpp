// Even-odd stencil fill against its CPU twin: random star polygons, nested loops (holes), and
// self-intersecting polygons; texels may differ only where an edge passes (numerically) through
// the texel centre.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "gl_fixture.h"
#include "gpgpu/polygon_fill.h"

namespace {

double distance_to_edges(const std::vector<std::vector<glm::vec2>>& polys, glm::dvec2 p) {
  double best = 1e30;
  for (const auto& poly : polys)
    for (size_t a = 0, b = poly.size() - 1; a < poly.size(); b = a++) {
      const glm::dvec2 A(poly[a]), B(poly[b]);
      const glm::dvec2 d = B - A;
      const double t = std::clamp(glm::dot(p - A, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
      const glm::dvec2 q = A + t * d - p;
      best = std::min(best, std::sqrt(glm::dot(q, q)));
    }
  return best;
}

std::vector<glm::vec2> star(std::mt19937_64& rng, glm::vec2 c, float r, int k, bool clockwise) {
  std::vector<glm::vec2> p;
  const auto u = test::random_floats(rng, size_t(k), 0.4f, 1.0f);
  for (int i = 0; i < k; ++i) {
    const float a = (clockwise ? -1.0f : 1.0f) * 6.2831853f * float(i) / float(k);
    p.push_back(c + r * u[size_t(i)] * glm::vec2(std::cos(a), std::sin(a)));
  }
  return p;
}

}  // namespace

TEST_CASE("polygon fill: even-odd stencil fill matches the CPU twin") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(21);
  for (int trial = 0; trial < 12; ++trial) {
    const int w = 37 + trial * 29, h = 23 + trial * 17;
    std::vector<std::vector<glm::vec2>> polys;
    polys.push_back(star(rng, {w * 0.5f, h * 0.5f}, 0.48f * float(std::min(w, h)), 5 + trial, false));
    polys.push_back(star(rng, {w * 0.5f, h * 0.5f}, 0.15f * float(std::min(w, h)), 7, true));  // a hole
    if (trial % 3 == 0)
      polys.push_back({{0.f, 0.f}, {float(w), float(h)}, {float(w), 0.f}, {0.f, float(h)}});  // bow tie
    if (trial % 4 == 1) polys.push_back({{2.f, 2.f}, {9.f, 2.f}});  // degenerate: ignored by both
    gpgpu::Texture mask(w, h, gpgpu::Format::R8);
    gpgpu::fill_polygons_even_odd(gpu, polys, mask);
    const auto got = mask.read();
    const auto want = gpgpu::fill_polygons_even_odd_cpu(polys, w, h);
    int differ = 0, inside = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const size_t k = size_t(j) * size_t(w) + size_t(i);
        inside += want[k];
        if ((got[k] > 0.5f) != (want[k] != 0)) {
          ++differ;
          CHECK(distance_to_edges(polys, {i + 0.5, j + 0.5}) < 1e-3);  // float rounding of an edge on a centre
        }
      }
    CAPTURE(trial);
    CHECK(inside > w * h / 20);  // the case is not vacuous
    CHECK(differ <= 2);
  }
}
