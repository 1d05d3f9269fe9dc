/// \file triangulate.cpp
/// §7 of Balázs, Guthe and Klein (2004): convexity check, the linear-time zipper for convex polygons
/// and the dispatch of triangulate_polygons. The monotone method is in triangulate_monotone.cpp.
#include "nurbs/tessellation/triangulate.h"

#include <glm/geometric.hpp>
#include <map>

#include "nurbs/tessellation/triangulate_detail.h"

namespace nurbs::tess {

namespace detail {

void emit_triangle(const std::vector<glm::dvec2>& /*v*/, int a, int b, int c, std::vector<glm::ivec3>& out,
                   TriangulationStats* /*stats*/) {
  out.emplace_back(a, b, c);
}

void remove_degenerate(const std::vector<glm::dvec2>& v, std::vector<glm::ivec3>& out, std::size_t first,
                       TriangulationStats* stats) {
  auto pt = [&](int i) { return v[static_cast<std::size_t>(i)]; };
  auto zero = [&](glm::ivec3 t) { return orient_sign(pt(t.x), pt(t.y), pt(t.z)) == 0; };
  std::map<std::pair<int, int>, std::size_t> owner;  // directed edge -> triangle
  for (std::size_t i = first; i < out.size(); ++i)
    for (int k = 0; k < 3; ++k) owner[{out[i][k], out[i][(k + 1) % 3]}] = i;
  // A zero-area triangle (a, b, c) with b between a and c is flipped with the triangle (a, c, d) across
  // its long edge into (a, b, d) and (b, c, d): same union, both counter-clockwise when d is off the line.
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    for (std::size_t i = first; i < out.size(); ++i) {
      if (!zero(out[i])) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = out[i][(k + 2) % 3], b = out[i][k], c = out[i][(k + 1) % 3];
        if (glm::dot(pt(a) - pt(b), pt(c) - pt(b)) >= 0.0) continue;  // b is not between a and c
        auto it = owner.find({a, c});
        if (it == owner.end() || it->second == i) break;
        const std::size_t j = it->second;
        int d = -1;
        for (int m = 0; m < 3; ++m)
          if (out[j][m] != a && out[j][m] != c) d = out[j][m];
        if (d < 0 || orient_sign(pt(a), pt(b), pt(d)) <= 0 || orient_sign(pt(b), pt(c), pt(d)) <= 0) break;
        for (std::size_t t : {i, j})
          for (int m = 0; m < 3; ++m) owner.erase({out[t][m], out[t][(m + 1) % 3]});
        out[i] = glm::ivec3(a, b, d), out[j] = glm::ivec3(b, c, d);
        for (std::size_t t : {i, j})
          for (int m = 0; m < 3; ++m) owner[{out[t][m], out[t][(m + 1) % 3]}] = t;
        changed = true;
        break;
      }
    }
    if (!changed) break;
  }
  if (stats)
    for (std::size_t i = first; i < out.size(); ++i) stats->degenerate_triangles += zero(out[i]);
}

}  // namespace detail

bool is_convex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon) {
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec2 a = vertices[static_cast<std::size_t>(polygon[i])];
    const glm::dvec2 b = vertices[static_cast<std::size_t>(polygon[(i + 1) % n])];
    const glm::dvec2 c = vertices[static_cast<std::size_t>(polygon[(i + 2) % n])];
    const int o = detail::orient_sign(a, b, c);
    if (o > 0) continue;
    if (o < 0) return false;
    // Unknown sign: only an exact zero (axis-parallel runs of cell edges: both products are 0) that
    // goes on forward counts as convex; a turn too thin to tell in double may be reflex (a 1e-24
    // dent of a trim line) and goes to the monotone method, which never cuts at such a vertex.
    const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
    if (l != 0.0 || r != 0.0 || glm::dot(b - a, c - b) < 0.0) return false;
  }
  return true;
}

void triangulate_convex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon,
                        std::vector<glm::ivec3>& out, TriangulationStats* stats) {
  const int n = static_cast<int>(polygon.size());
  if (n < 3) return;
  if (stats) ++stats->convex_polygons;
  const std::size_t first = out.size();
  auto at = [&](int i) {
    return vertices[static_cast<std::size_t>(polygon[static_cast<std::size_t>(((i % n) + n) % n)])];
  };
  auto id = [&](int i) { return polygon[static_cast<std::size_t>(((i % n) + n) % n)]; };
  int k = 0;
  for (int i = 1; i < n; ++i)
    if (detail::above(at(i), at(k))) k = i;
  // Chord (a, b): the part a, a + 1, ..., b of the polygon is left; a runs forward, b backward.
  int a = k + 1, b = k - 1 + n;
  detail::emit_triangle(vertices, id(k), id(a), id(b), out, stats);
  while (a + 1 < b) {
    const bool take_a_first = a + 1 == b - 1 || detail::above(at(a + 1), at(b - 1));
    const int oa = detail::orient_sign(at(a), at(a + 1), at(b)), ob = detail::orient_sign(at(b - 1), at(b), at(a));
    const bool take_a = take_a_first ? (oa != 0 || ob == 0) : (ob == 0 && oa != 0);
    if (take_a) {
      detail::emit_triangle(vertices, id(a), id(a + 1), id(b), out, stats);
      ++a;
    } else {
      detail::emit_triangle(vertices, id(b - 1), id(b), id(a), out, stats);
      --b;
    }
  }
  detail::remove_degenerate(vertices, out, first, stats);
}

std::vector<glm::ivec3> triangulate_polygons(const TrimmedPolygons& polys, TriangulationStats* stats) {
  std::vector<glm::ivec3> out;
  for (std::size_t i = 0; i < polys.polygons.size(); ++i) {
    const auto& p = polys.polygons[i];
    const bool marked = i < polys.has_trim_edge.size() && polys.has_trim_edge[i];
    if (!marked || is_convex(polys.vertices, p))
      triangulate_convex(polys.vertices, p, out, stats);
    else
      triangulate_nonconvex(polys.vertices, p, out, stats);
  }
  return out;
}

}  // namespace nurbs::tess
