#pragma once
// Shared by test_half_edge_trim*.cpp: builders of cells and loops, and the oracle that checks §6 + §7
// (Balázs, Guthe, Klein 2004) independently of the graph: the loops' shoelace area, nurbs::winding_number
// at triangle centroids, and the edge-use count of the triangle mesh.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <map>
#include <random>

#include "nurbs/tessellation/half_edge_trim.h"
#include "nurbs/tessellation/triangulate.h"
#include "nurbs/trim_classify.h"

namespace half_edge_trim_test {

using nurbs::tess::Cell;
using nurbs::tess::LoopPolyline;
using nurbs::tess::TrimmedPolygons;

inline constexpr double kPi = 3.14159265358979323846;

inline Cell cell(double u0, double u1, double v0, double v1) { return Cell{{u0, u1}, {v0, v1}}; }

inline std::vector<Cell> grid(double u0, double u1, double v0, double v1, int nu, int nv) {
  std::vector<Cell> out;
  // Cell coordinates from one formula so that shared sides are bit-identical.
  auto x = [&](int i) { return i == nu ? u1 : u0 + (u1 - u0) * i / nu; };
  auto y = [&](int j) { return j == nv ? v1 : v0 + (v1 - v0) * j / nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) out.push_back(cell(x(i), x(i + 1), y(j), y(j + 1)));
  return out;
}

/// kd-tree-like tiling: random axis and split position, random depth: T-junctions everywhere.
inline void kd_split(Cell c, int depth, std::mt19937_64& rng, std::vector<Cell>& out) {
  std::uniform_real_distribution<double> t(0.2, 0.8), coin(0.0, 1.0);
  if (depth == 0 || (depth < 5 && coin(rng) < 0.25)) {
    out.push_back(c);
    return;
  }
  Cell a = c, b = c;
  if (coin(rng) < 0.5) {
    const double s = c.u.min + t(rng) * c.u.width();
    a.u.max = s, b.u.min = s;
  } else {
    const double s = c.v.min + t(rng) * c.v.width();
    a.v.max = s, b.v.min = s;
  }
  kd_split(a, depth - 1, rng, out);
  kd_split(b, depth - 1, rng, out);
}

inline LoopPolyline loop(std::vector<glm::dvec2> uv, bool outer) {
  LoopPolyline l;
  l.uv = std::move(uv);
  l.outer = outer;
  return l;
}

inline LoopPolyline circle(glm::dvec2 c, double r, int n, bool outer) {
  std::vector<glm::dvec2> p;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n * (outer ? 1.0 : -1.0);
    p.push_back(c + r * glm::dvec2(std::cos(a), std::sin(a)));
  }
  return loop(p, outer);
}

struct Bounds {
  glm::dvec2 lo, hi;
};
inline Bounds bounds(const std::vector<Cell>& cells) {
  Bounds b{{cells[0].u.min, cells[0].v.min}, {cells[0].u.max, cells[0].v.max}};
  for (const Cell& c : cells) {
    b.lo = glm::min(b.lo, glm::dvec2(c.u.min, c.v.min));
    b.hi = glm::max(b.hi, glm::dvec2(c.u.max, c.v.max));
  }
  return b;
}

inline double tri_area(const std::vector<glm::dvec2>& v, glm::ivec3 t) {
  const glm::dvec2 a = v[static_cast<std::size_t>(t.x)], b = v[static_cast<std::size_t>(t.y)],
                   c = v[static_cast<std::size_t>(t.z)];
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

/// The sign of the double determinant is unknown within 3.33e-16 * (|left| + |right|) (Shewchuk 1997,
/// first-stage error bound of orient2d): such slivers may come out either way and are counted instead.
inline bool thin(const std::vector<glm::dvec2>& v, glm::ivec3 t) {
  const glm::dvec2 a = v[static_cast<std::size_t>(t.x)], b = v[static_cast<std::size_t>(t.y)],
                   c = v[static_cast<std::size_t>(t.z)];
  const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
  return std::abs(l - r) <= 3.3306690738754716e-16 * (std::abs(l) + std::abs(r));
}

inline double seg_dist(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 d = b - a;
  const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(p - (a + t * d));
}

struct Result {
  TrimmedPolygons polys;
  std::vector<glm::ivec3> tris;
  nurbs::tess::TriangulationStats tstats;
  double seconds = 0.0;  ///< trim_cells + triangulate_polygons only
  int slivers = 0;       ///< triangles whose centroid is within 1e-10 * size of a loop, classified wrong
};

/// Runs §6 + §7 and checks the mesh against the oracle. `expected_area`: the material area of the
/// loops clipped to R, from the caller (shoelace of the loops, or a closed form when clipped).
inline Result run_and_check(const std::vector<Cell>& cells, const std::vector<LoopPolyline>& loops,
                            double expected_area, double area_tol = 1e-12) {
  Result r;
  const auto t0 = std::chrono::steady_clock::now();
  r.polys = nurbs::tess::trim_cells(cells, loops);
  r.tris = nurbs::tess::triangulate_polygons(r.polys, &r.tstats);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& v = r.polys.vertices;
  const Bounds b = bounds(cells);
  const double size = std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
  // Area: sums of O(10^4) terms of size <= R's area carry ~1e-16 relative rounding each.
  double area = 0.0;
  int zero = 0;
  for (glm::ivec3 t : r.tris) {
    const double a = tri_area(v, t);
    CHECK((a > 0.0 || thin(v, t)));  // counter-clockwise, never flipped
    zero += thin(v, t);
    area += a;
  }
  CHECK(zero <= r.tstats.degenerate_triangles);
  CHECK(area == doctest::Approx(expected_area).epsilon(area_tol));
  double poly_area = 0.0;
  for (const auto& p : r.polys.polygons) {
    std::vector<glm::dvec2> q;
    for (int id : p) q.push_back(v[static_cast<std::size_t>(id)]);
    // Shoelace about the first vertex: exact enough for the sign of slivers of area 1e-18.
    double a = 0.0;
    for (std::size_t i = 1; i + 1 < q.size(); ++i)
      a += 0.5 * ((q[i].x - q[0].x) * (q[i + 1].y - q[0].y) - (q[i].y - q[0].y) * (q[i + 1].x - q[0].x));
    CHECK(a > 0.0);
    poly_area += a;
  }
  CHECK(poly_area == doctest::Approx(expected_area).epsilon(area_tol));
  // Every centroid is material (winding test against the input loops, which for the clipped cases
  // differ from their clipped versions only outside R).
  bool any_outer = false;
  for (const auto& l : loops) any_outer = any_outer || l.outer;
  int wrong = 0;
  for (glm::ivec3 t : r.tris) {
    if (thin(v, t)) continue;
    const glm::dvec2 c =
        (v[static_cast<std::size_t>(t.x)] + v[static_cast<std::size_t>(t.y)] + v[static_cast<std::size_t>(t.z)]) / 3.0;
    int w = any_outer ? 0 : 1;
    for (const auto& l : loops) w += nurbs::winding_number(l.uv, c);
    const bool in_r = c.x > b.lo.x && c.x < b.hi.x && c.y > b.lo.y && c.y < b.hi.y;
    if (w > 0 && in_r) continue;
    // Slivers: snapping moves loops by <= 1e-12 * size and double orientation tests cannot resolve
    // features below ~1e-16 of the coordinates, so a centroid within 1e-10 * size of a loop may fall
    // either way; it is counted (Result::slivers), not failed.
    double d = 1e300;
    for (const auto& l : loops)
      for (std::size_t i = 0; i < l.uv.size(); ++i) d = std::min(d, seg_dist(c, l.uv[i], l.uv[(i + 1) % l.uv.size()]));
    r.slivers += d <= 1e-10 * size;
    wrong += d > 1e-10 * size;
  }
  CHECK(wrong == 0);
  // Crack-free: each directed edge used once; an edge without its twin is on a loop or on R's boundary
  // (within 1e-10 * size: snapping moves points by <= 1e-12 * size, intersections round to ~1e-16).
  std::map<std::pair<int, int>, int> use;
  // Zero-area triangles (counted in the stats) take part: they keep the mesh closed.
  for (glm::ivec3 t : r.tris)
    for (int k = 0; k < 3; ++k) ++use[{t[k], t[(k + 1) % 3]}];
  int twice = 0, stray = 0;
  for (auto [e, n] : use) {
    twice += n != 1;
    if (use.count({e.second, e.first})) continue;
    const glm::dvec2 m = 0.5 * (v[static_cast<std::size_t>(e.first)] + v[static_cast<std::size_t>(e.second)]);
    double d = std::min({m.x - b.lo.x, b.hi.x - m.x, m.y - b.lo.y, b.hi.y - m.y});
    for (const auto& l : loops)
      for (std::size_t i = 0; i < l.uv.size(); ++i) d = std::min(d, seg_dist(m, l.uv[i], l.uv[(i + 1) % l.uv.size()]));
    stray += d > 1e-10 * size;
  }
  CHECK(twice == 0);
  CHECK(stray == 0);
  CHECK(r.polys.stats.inconsistent_edges == 0);
  return r;
}

inline double loops_area(const std::vector<LoopPolyline>& loops) {
  double a = 0.0;
  for (const auto& l : loops) a += nurbs::signed_area(l.uv);
  return a;
}

}  // namespace half_edge_trim_test
