#include "nurbs/tessellation/loop_repair.h"

#include <algorithm>
#include <glm/geometric.hpp>

#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace nurbs::tess {
namespace {

struct Edge {
  size_t loop, index;  ///< edge from vertex index to index + 1 (mod size) of loop
  glm::dvec2 a, b;
};

struct Hit {
  size_t loop, index;
  double t;  ///< parameter along the edge
  glm::dvec2 p;
};

double orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// All proper crossings, by a sweep over u: edges sorted by min u; the active list holds the edges
/// whose u range still reaches the current one. Each pair whose u and v ranges overlap is tested
/// exactly once (O((n + k) log n) plus the pairs sharing a u slab).
std::vector<Hit> find_crossings(const std::vector<LoopPolyline>& loops) {
  std::vector<Edge> edges;
  for (size_t l = 0; l < loops.size(); ++l) {
    const auto& uv = loops[l].uv;
    for (size_t i = 0; i < uv.size() && uv.size() > 1; ++i) edges.push_back({l, i, uv[i], uv[(i + 1) % uv.size()]});
  }
  std::sort(edges.begin(), edges.end(),
            [](const Edge& x, const Edge& y) { return std::min(x.a.x, x.b.x) < std::min(y.a.x, y.b.x); });
  std::vector<Hit> hits;
  std::vector<const Edge*> active;
  for (const Edge& e : edges) {
    const double umin = std::min(e.a.x, e.b.x);
    std::erase_if(active, [&](const Edge* o) { return std::max(o->a.x, o->b.x) < umin; });
    for (const Edge* o : active) {
      if (std::max(e.a.y, e.b.y) < std::min(o->a.y, o->b.y) || std::max(o->a.y, o->b.y) < std::min(e.a.y, e.b.y))
        continue;
      const double d1 = orient(e.a, e.b, o->a), d2 = orient(e.a, e.b, o->b);
      const double d3 = orient(o->a, o->b, e.a), d4 = orient(o->a, o->b, e.b);
      if (!((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) || !((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) continue;
      const double t = d3 / (d3 - d4), s = d1 / (d1 - d2);  // along e, along o
      const glm::dvec2 p = e.a + t * (e.b - e.a);
      hits.push_back({e.loop, e.index, t, p});
      hits.push_back({o->loop, o->index, s, p});
    }
    active.push_back(&e);
  }
  return hits;
}

/// Twice the signed area of a closed polyline, about its first vertex (slivers keep their sign).
double area2(const std::vector<glm::dvec2>& uv) {
  double a = 0.0;
  for (size_t i = 1; i + 1 < uv.size(); ++i) a += orient(uv[0], uv[i], uv[i + 1]);
  return a;
}

/// The vertices [first, last) of `l` (indices mod its size) as a loop of their own.
LoopPolyline piece(const LoopPolyline& l, size_t first, size_t last) {
  LoopPolyline out;
  out.outer = l.outer;
  const bool edges = l.edge.size() == l.uv.size();
  for (size_t k = first; k != last; k = (k + 1) % l.uv.size()) {
    out.uv.push_back(l.uv[k]);
    out.xyz.push_back(l.xyz[k]);
    if (edges) out.edge.push_back(l.edge[k]);
  }
  return out;
}

/// Twice a closed polyline's area in space over its length: the width of a thin lobe.
double width_in_space(const std::vector<glm::dvec3>& xyz) {
  glm::dvec3 area(0.0);
  double length = 0.0;
  for (size_t k = 0; k < xyz.size(); ++k) {
    const glm::dvec3 a = xyz[k] - xyz[0], b = xyz[(k + 1) % xyz.size()] - xyz[0];
    area += glm::cross(a, b);
    length += glm::length(b - a);
  }
  return length > 0.0 ? glm::length(area) / length : 0.0;
}

/// A loop that crosses itself (a crossing vertex twice in it) cut there into simple pieces, each
/// appended to `out` with its signed area's sign relative to `sign` (the whole loop's).
void untangle(const LoopPolyline& l, double sign, std::vector<std::pair<LoopPolyline, double>>& out) {
  for (size_t i = 0; i < l.uv.size(); ++i)
    for (size_t j = i + 1; j < l.uv.size(); ++j)
      if (l.uv[i] == l.uv[j]) {
        untangle(piece(l, i, j), sign, out);
        untangle(piece(l, j, i), sign, out);
        return;
      }
  if (l.uv.size() >= 3) out.emplace_back(l, area2(l.uv) * sign);
}

/// The pieces of a self-crossing loop that are kept (repair_crossings): those turning as the loop
/// does; those turning against it that are wider in space than `fold_width` and lie inside one of
/// the former (a hole the loop reaches through a slit), as loops of the other kind. The others are
/// folds of the polylines' error, or have no area.
void keep_pieces(std::vector<std::pair<LoopPolyline, double>>& pieces, double fold_width,
                 std::vector<LoopPolyline>& out) {
  const size_t first = out.size();
  for (auto& [piece, turn] : pieces)
    if (turn > 0.0) out.push_back(piece);
  const size_t kept = out.size();
  for (auto& [piece, turn] : pieces) {
    if (!(turn < 0.0) || width_in_space(piece.xyz) <= fold_width) continue;
    glm::dvec2 centre(0.0);
    for (const glm::dvec2& p : piece.uv) centre += p / double(piece.uv.size());
    bool inside = false;
    for (size_t k = first; k < kept && !inside; ++k) inside = winding_number(out[k].uv, centre) != 0;
    if (!inside) continue;
    piece.outer = !piece.outer;
    out.push_back(std::move(piece));
  }
}

}  // namespace

size_t count_crossings(const std::vector<LoopPolyline>& loops) { return find_crossings(loops).size() / 2; }

size_t repair_crossings(std::vector<LoopPolyline>& loops, const Surface& surface, double fold_width) {
  std::vector<Hit> hits = find_crossings(loops);
  if (hits.empty()) return 0;
  // find_crossings gives each crossing as two consecutive hits: a loop crossing itself has both.
  std::vector<bool> self(loops.size(), false);
  for (size_t k = 0; k + 1 < hits.size(); k += 2)
    if (hits[k].loop == hits[k + 1].loop) self[hits[k].loop] = true;
  std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
    return x.loop != y.loop ? x.loop < y.loop : (x.index != y.index ? x.index < y.index : x.t < y.t);
  });
  size_t h = 0;
  for (size_t l = 0; l < loops.size(); ++l) {
    LoopPolyline out;
    out.outer = loops[l].outer;
    const bool edges = loops[l].edge.size() == loops[l].uv.size();
    for (size_t i = 0; i < loops[l].uv.size(); ++i) {
      out.uv.push_back(loops[l].uv[i]);
      out.xyz.push_back(loops[l].xyz[i]);
      if (edges) out.edge.push_back(loops[l].edge[i]);
      for (; h < hits.size() && hits[h].loop == l && hits[h].index == i; ++h) {
        if (hits[h].p == out.uv.back()) continue;
        out.uv.push_back(hits[h].p);
        out.xyz.push_back(surface_point(surface, hits[h].p.x, hits[h].p.y));
        if (edges) out.edge.push_back(loops[l].edge[i]);  // on segment i: its edge
      }
    }
    loops[l] = std::move(out);
  }
  // Self-crossings: each such loop is cut at its crossings and its folded lobes dropped.
  std::vector<LoopPolyline> untangled;
  for (size_t l = 0; l < loops.size(); ++l) {
    if (self[l]) {
      std::vector<std::pair<LoopPolyline, double>> pieces;
      untangle(loops[l], area2(loops[l].uv), pieces);
      keep_pieces(pieces, fold_width, untangled);
    } else {
      untangled.push_back(std::move(loops[l]));
    }
  }
  loops = std::move(untangled);
  return hits.size() / 2;
}

}  // namespace nurbs::tess
