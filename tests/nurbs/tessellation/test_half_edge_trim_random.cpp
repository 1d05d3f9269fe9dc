// Tests of §6 + §7 (Balázs, Guthe, Klein 2004) on randomized inputs with fixed seeds: kd tilings with
// star-shaped loops, and grid-aligned loops with near-misses. Oracle: test_half_edge_trim_oracle.h.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "test_half_edge_trim_oracle.h"

using namespace half_edge_trim_test;

TEST_CASE("half-edge trim: randomized kd tilings, star outer loops and holes (fixed seed)") {
  std::mt19937_64 rng(20040201);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int polygons = 0, triangles = 0, bridges = 0, fallback = 0, nonconvex = 0, degenerate = 0;
  double seconds = 0.0;
  const int cases = 300;
  for (int k = 0; k < cases; ++k) {
    std::vector<Cell> cells;
    const glm::dvec2 lo{u01(rng) - 0.5, u01(rng) - 0.5}, size{0.5 + u01(rng), 0.5 + u01(rng)};
    kd_split(cell(lo.x, lo.x + size.x, lo.y, lo.y + size.y), 3 + k % 6, rng, cells);
    const glm::dvec2 c = lo + 0.5 * size;
    const double rm = 0.5 * std::min(size.x, size.y);
    // Star-shaped outer loop: radii in [0.6, 1] * rm, angular gaps <= 1.8 * 2pi / n, so it contains
    // the disk of radius 0.6 cos(0.9 pi / 12) rm > 0.57 rm around c.
    const int n = 12 + static_cast<int>(u01(rng) * 60);
    std::vector<glm::dvec2> star;
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * (i + 0.4 * (u01(rng) - 0.5)) / n, rad = rm * (0.6 + 0.4 * u01(rng));
      star.push_back(c + rad * glm::dvec2(std::cos(a), std::sin(a)));
    }
    std::vector<LoopPolyline> loops{loop(star, true)};
    const int holes = k % 4;  // 0..3 holes at distance 0.3 rm, radius <= 0.12 rm: disjoint, inside
    for (int h = 0; h < holes; ++h) {
      const double a = 2.0 * kPi * h / 3.0, hr = (k % 5 == 0 ? 1e-4 : 0.12) * rm;
      const glm::dvec2 hc = c + 0.3 * rm * glm::dvec2(std::cos(a), std::sin(a));
      const int m = 3 + static_cast<int>(u01(rng) * 20);
      std::vector<glm::dvec2> p;
      for (int i = 0; i < m; ++i) {
        const double b = -2.0 * kPi * (i + 0.4 * (u01(rng) - 0.5)) / m;
        p.push_back(hc + hr * (0.4 + 0.6 * u01(rng)) * glm::dvec2(std::cos(b), std::sin(b)));
      }
      loops.push_back(loop(p, false));
    }
    Result r = run_and_check(cells, loops, loops_area(loops));
    seconds += r.seconds;
    polygons += static_cast<int>(r.polys.polygons.size());
    triangles += static_cast<int>(r.tris.size());
    bridges += r.polys.stats.paper_bridges;
    fallback += r.polys.stats.fallback_bridges;
    nonconvex += r.tstats.nonconvex_polygons;
    degenerate += r.tstats.degenerate_triangles;
  }
  MESSAGE(cases << " cases: " << polygons << " polygons (" << nonconvex << " non-convex), " << triangles
                << " triangles (" << degenerate << " zero-area), " << bridges << " paper bridges, " << fallback
                << " fallback bridges, " << seconds << " s in trim_cells + triangulate_polygons");
  CHECK(bridges > 0);
}

namespace {

bool segments_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  auto o = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
    const double v = (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    return (v > 0.0) - (v < 0.0);
  };
  const bool box =
      std::max(std::min(a.x, b.x), std::min(c.x, d.x)) <= std::min(std::max(a.x, b.x), std::max(c.x, d.x)) &&
      std::max(std::min(a.y, b.y), std::min(c.y, d.y)) <= std::min(std::max(a.y, b.y), std::max(c.y, d.y));
  return box && o(a, b, c) * o(a, b, d) <= 0 && o(c, d, a) * o(c, d, b) <= 0;
}

/// Simple polygon: non-adjacent edges do not meet, adjacent ones only at their shared vertex.
bool simple(const std::vector<glm::dvec2>& p) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      if (adjacent) {
        const glm::dvec2 s = j == i + 1 ? p[i] : p[j], m = j == i + 1 ? p[j] : p[i],
                         e = j == i + 1 ? p[(j + 1) % n] : p[1];
        const double o = (m.x - s.x) * (e.y - m.y) - (m.y - s.y) * (e.x - m.x);
        if (o == 0.0 && glm::dot(m - s, e - m) < 0.0) return false;  // folds back on itself
      } else if (segments_cross(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) {
        return false;
      }
    }
  return true;
}

}  // namespace

TEST_CASE("half-edge trim: randomized grid-aligned loops (vertices on cell lines and corners, collinear edges)") {
  // Dyadic kd tilings of [0, 1]^2 (splits at multiples of 1/16) and loops with vertices rounded to
  // multiples of 1/32: many loop vertices lie exactly on cell edges or corners, many loop edges run
  // along cell edges, and some touch R's boundary.
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int cases = 0, polygons = 0, triangles = 0, degenerate = 0, slivers = 0;
  double seconds = 0.0;
  for (int k = 0; k < 800; ++k) {
    // k >= 400: every loop coordinate moved by +-10^-e, e in 7..16: near-misses of cell lines and
    // corners, some within the snapping tolerance, some just outside it.
    const double jitter = k < 400 ? 0.0 : std::pow(10.0, -7.0 - (k % 10));
    std::vector<Cell> cells;
    std::vector<Cell> todo{cell(0, 1, 0, 1)};
    while (!todo.empty()) {
      Cell c = todo.back();
      todo.pop_back();
      const bool split_u = u01(rng) < 0.5;
      const double w = split_u ? c.u.width() : c.v.width();
      if (w <= 1.0 / 16 || u01(rng) < 0.15) {
        cells.push_back(c);
        continue;
      }
      const int steps = static_cast<int>(std::lround(w * 16));
      const double s = (split_u ? c.u.min : c.v.min) + (1 + static_cast<int>(u01(rng) * (steps - 1))) / 16.0;
      Cell a = c, b = c;
      (split_u ? a.u.max : a.v.max) = s;
      (split_u ? b.u.min : b.v.min) = s;
      todo.push_back(a), todo.push_back(b);
    }
    const int n = 4 + k % 9;
    const glm::dvec2 c{0.5 + (u01(rng) - 0.5) * 0.1, 0.5 + (u01(rng) - 0.5) * 0.1};
    std::vector<glm::dvec2> star;
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * (i + 0.4 * (u01(rng) - 0.5)) / n, rad = 0.3 + 0.3 * u01(rng);
      glm::dvec2 q = glm::round((c + rad * glm::dvec2(std::cos(a), std::sin(a))) * 32.0) / 32.0;
      star.push_back(glm::clamp(q, 0.0, 1.0));  // some vertices end on R's boundary
    }
    std::vector<glm::dvec2> d;
    for (auto q : star)
      if (d.empty() || q != d.back()) d.push_back(q);
    while (d.size() > 1 && d.front() == d.back()) d.pop_back();
    if (d.size() < 3 || nurbs::signed_area(d) <= 0.0 || !simple(d)) continue;
    std::vector<LoopPolyline> loops{loop(d, true)};
    // Hole: a grid diamond or square around the centre, well inside the star (radius >= ~0.23 there).
    const glm::dvec2 hc = glm::round(c * 16.0) / 16.0;
    const double h = 1.0 / 16;
    if (k % 3 == 1)
      loops.push_back(
          loop({hc + glm::dvec2(0, -h), hc + glm::dvec2(-h, 0), hc + glm::dvec2(0, h), hc + glm::dvec2(h, 0)}, false));
    if (k % 3 == 2)
      loops.push_back(loop(
          {hc + glm::dvec2(-h, -h), hc + glm::dvec2(-h, h), hc + glm::dvec2(h, h), hc + glm::dvec2(h, -h)}, false));
    for (auto& l : loops)
      for (auto& q : l.uv) {  // vertices on R's boundary stay there (else the expected area changes)
        const glm::dvec2 j = jitter * glm::dvec2(u01(rng) < 0.5 ? -1 : 1, u01(rng) < 0.5 ? -1 : 1);
        if (q.x != 0.0 && q.x != 1.0) q.x += j.x;
        if (q.y != 0.0 && q.y != 1.0) q.y += j.y;
      }
    ++cases;
    // Snapping moves a coordinate by <= 1e-12 (R is [0, 1]^2), which changes the area by at most
    // perimeter (< 8) * 1e-12 relative to an area > 0.05: 1e-9 bounds it.
    Result r = run_and_check(cells, loops, loops_area(loops), jitter > 0.0 ? 1e-9 : 1e-12);
    seconds += r.seconds;
    polygons += static_cast<int>(r.polys.polygons.size());
    triangles += static_cast<int>(r.tris.size());
    degenerate += r.tstats.degenerate_triangles;
    slivers += r.slivers;
  }
  MESSAGE(cases << " grid-aligned cases (" << slivers << " sliver centroids on a loop): " << polygons << " polygons, "
                << triangles << " triangles (" << degenerate << " zero-area), " << seconds << " s");
  CHECK(cases > 400);
}
