/// \file half_edge_trim_traverse.cpp
/// §6 of Balázs, Guthe and Klein (2004): the traversal of the half-edge graph (findDirectedEdge,
/// handleEdge, getNextEdge, getOutGoingEdge) and the bridge edges that make holes reachable.
#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "nurbs/segment_distance.h"
#include "nurbs/tessellation/half_edge_trim_graph.h"
#include "nurbs/trim_classify.h"

namespace nurbs::tess::detail {
namespace {

/// Counter-clockwise angular order of directions, exact for doubles (half-plane, then cross product).
bool angle_less(glm::dvec2 p, glm::dvec2 q) {
  const bool hp = p.y < 0.0 || (p.y == 0.0 && p.x < 0.0), hq = q.y < 0.0 || (q.y == 0.0 && q.x < 0.0);
  if (hp != hq) return !hp;
  return p.x * q.y - p.y * q.x > 0.0;
}

/// Strictly inside the counter-clockwise wedge from direction a to direction b.
bool in_wedge(glm::dvec2 a, glm::dvec2 b, glm::dvec2 d) {
  auto cross = [](glm::dvec2 p, glm::dvec2 q) { return p.x * q.y - p.y * q.x; };
  if (cross(a, b) > 0.0) return cross(a, d) > 0.0 && cross(d, b) > 0.0;
  return cross(a, d) > 0.0 || cross(d, b) > 0.0;
}

double cycle_area(const TrimGraph& g, const std::vector<int>& ids) {
  std::vector<glm::dvec2> p;
  for (int id : ids) p.push_back(g.pos[static_cast<std::size_t>(id)]);
  return local_area(p);
}

void emit(const TrimGraph& g, std::vector<int> ids, std::vector<Cycle>& out, TrimStats& stats) {
  Cycle c;
  c.area = ids.size() < 3 ? 0.0 : cycle_area(g, ids);
  if (c.area == 0.0) {
    ++stats.dropped_cycles;
    return;
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    auto e = g.edge_index.find(std::minmax(ids[i], ids[(i + 1) % ids.size()]));
    if (e != g.edge_index.end() && g.edges[static_cast<std::size_t>(e->second)].marked) c.marked = true;
  }
  c.ids = std::move(ids);
  out.push_back(std::move(c));
}

}  // namespace

std::vector<Cycle> traverse(const TrimGraph& g, TrimStats& stats) {
  const std::size_t nv = g.pos.size(), ne = g.edges.size();
  // Around each node, the incident edges in counter-clockwise order: (neighbour, edge id).
  std::vector<std::vector<std::pair<int, int>>> around(nv);
  for (std::size_t e = 0; e < ne; ++e) {
    around[static_cast<std::size_t>(g.edges[e].a)].emplace_back(g.edges[e].b, static_cast<int>(e));
    around[static_cast<std::size_t>(g.edges[e].b)].emplace_back(g.edges[e].a, static_cast<int>(e));
  }
  for (std::size_t v = 0; v < nv; ++v)
    std::sort(around[v].begin(), around[v].end(), [&](auto p, auto q) {
      return angle_less(g.pos[static_cast<std::size_t>(p.first)] - g.pos[v],
                        g.pos[static_cast<std::size_t>(q.first)] - g.pos[v]);
    });
  // Edge state: +1 directed a -> b, -1 directed b -> a, 0 undirected, 2 deleted.
  std::vector<int> state(ne);
  std::vector<std::pair<int, int>> directed;  // (edge, +1 / -1): candidates of findDirectedEdge
  for (std::size_t e = 0; e < ne; ++e) {
    state[e] = g.edges[e].net > 0 ? 1 : (g.edges[e].net < 0 ? -1 : 0);
    if (state[e] != 0) directed.emplace_back(static_cast<int>(e), state[e]);
  }
  // getNextEdge: arriving at v from u, the leftmost turn is the clockwise neighbour of u around v.
  auto next_node = [&](int u, int v) {
    const auto& l = around[static_cast<std::size_t>(v)];
    std::size_t i = 0;
    while (l[i].first != u) ++i;
    return l[(i + l.size() - 1) % l.size()];
  };
  std::vector<Cycle> out;
  std::vector<int> slot(nv, -1);
  while (!directed.empty()) {  // findDirectedEdge
    auto [e0, dir0] = directed.back();
    directed.pop_back();
    if (state[static_cast<std::size_t>(e0)] != dir0) continue;
    const int start_u = dir0 > 0 ? g.edges[static_cast<std::size_t>(e0)].a : g.edges[static_cast<std::size_t>(e0)].b;
    const int start_v = dir0 > 0 ? g.edges[static_cast<std::size_t>(e0)].b : g.edges[static_cast<std::size_t>(e0)].a;
    std::vector<int> walk;
    int u = start_u, v = start_v, e = e0;
    for (std::size_t steps = 0; steps <= 2 * ne; ++steps) {
      walk.push_back(u);
      // handleEdge: a directed edge is deleted, an undirected one is directed the opposite way.
      auto& s = state[static_cast<std::size_t>(e)];
      const int along = (g.edges[static_cast<std::size_t>(e)].a == u) ? 1 : -1;
      if (s == along) {
        s = 2;
      } else if (s == 0 && !g.edges[static_cast<std::size_t>(e)].on_boundary) {
        s = -along;
        directed.emplace_back(e, s);
      } else if (s == 0) {
        s = 2;  // R's boundary: the other side is outside R
      } else {
        ++stats.inconsistent_edges, s = 2;
      }
      auto [w, en] = next_node(u, v);
      u = v, v = w, e = en;
      if (u == start_u && v == start_v) break;  // back at the start: the polygon is closed
    }
    // Split the closed walk at repeated nodes (holes touching the boundary, edges walked twice).
    std::vector<int> stack;
    for (int id : walk) {
      const int at = slot[static_cast<std::size_t>(id)];
      if (at >= 0) {
        std::vector<int> sub(stack.begin() + at, stack.end());
        for (std::size_t k = static_cast<std::size_t>(at) + 1; k < stack.size(); ++k)
          slot[static_cast<std::size_t>(stack[k])] = -1;
        stack.resize(static_cast<std::size_t>(at) + 1);
        emit(g, std::move(sub), out, stats);
      } else {
        slot[static_cast<std::size_t>(id)] = static_cast<int>(stack.size());
        stack.push_back(id);
      }
    }
    for (int id : stack) slot[static_cast<std::size_t>(id)] = -1;
    emit(g, std::move(stack), out, stats);
  }
  return out;
}

int add_bridge(TrimGraph& g, int from, int from_prev, int from_next, const std::vector<int>& targets,
               const std::vector<std::pair<int, int>>& target_neighbours) {
  const glm::dvec2 p = g.pos[static_cast<std::size_t>(from)];
  std::vector<std::size_t> order(targets.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto dist = [&](std::size_t i) { return glm::length(g.pos[static_cast<std::size_t>(targets[i])] - p); };
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return dist(i) < dist(j); });
  for (std::size_t i : order) {
    const int t = targets[i];
    const glm::dvec2 q = g.pos[static_cast<std::size_t>(t)];
    if (t == from || g.edge_index.count(std::minmax(from, t))) continue;
    auto at = [&](int id) { return g.pos[static_cast<std::size_t>(id)]; };
    if (from_prev >= 0 && !in_wedge(at(from_next) - p, at(from_prev) - p, q - p)) continue;
    const auto [tp, tn] = target_neighbours[i];
    if (tp >= 0 && !in_wedge(at(tn) - q, at(tp) - q, p - q)) continue;
    const glm::dvec2 lo = glm::min(p, q), hi = glm::max(p, q);
    bool blocked = false;
    for (const auto& e : g.edges) {
      const glm::dvec2 a = at(e.a), b = at(e.b);
      if (std::max(a.x, b.x) < lo.x || std::min(a.x, b.x) > hi.x || std::max(a.y, b.y) < lo.y ||
          std::min(a.y, b.y) > hi.y)
        continue;
      const double o1 = orient(p, q, a), o2 = orient(p, q, b);
      const bool shares = e.a == from || e.b == from || e.a == t || e.b == t;
      // Within the snapping tolerance is on: a bridge along a hole's side that lies a rounding off
      // the bridge's line (the holes of a row, their sides on one line) would cut the hole.
      const auto on_bridge = [&](glm::dvec2 x) {
        return segment_distance(x, p, q) <= g.eps && glm::length(x - p) > g.eps && glm::length(x - q) > g.eps;
      };
      if (shares) {
        // Only an overlap along the bridge blocks it: the other endpoint on the bridge.
        if (on_bridge(at((e.a == from || e.a == t) ? e.b : e.a))) blocked = true;
      } else if ((o1 * o2 <= 0.0 && orient(a, b, p) * orient(a, b, q) <= 0.0) || on_bridge(a) || on_bridge(b) ||
                 segment_distance(p, a, b) <= g.eps || segment_distance(q, a, b) <= g.eps) {
        blocked = true;
      }
      if (blocked) break;
    }
    if (blocked) continue;
    g.add_edge(from, t, 0, true);
    return t;
  }
  return -1;
}

bool bridge_holes(TrimGraph& g, const std::vector<Cycle>& cycles, TrimStats& stats) {
  bool added = false;
  for (const Cycle& h : cycles) {
    if (h.area >= 0.0) continue;
    const glm::dvec2 mid =
        0.5 * (g.pos[static_cast<std::size_t>(h.ids[0])] + g.pos[static_cast<std::size_t>(h.ids[1])]);
    const Cycle* around = nullptr;
    for (const Cycle& c : cycles) {
      if (c.area <= 0.0 || (around && around->area <= c.area)) continue;
      std::vector<glm::dvec2> poly;
      for (int id : c.ids) poly.push_back(g.pos[static_cast<std::size_t>(id)]);
      if (winding_number(poly, mid) != 0) around = &c;
    }
    if (!around) continue;
    const std::size_t n = h.ids.size(), m = around->ids.size();
    std::vector<std::pair<int, int>> nb;
    for (std::size_t i = 0; i < m; ++i) nb.emplace_back(around->ids[(i + m - 1) % m], around->ids[(i + 1) % m]);
    std::size_t i_min = 0, i_max = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (g.pos[static_cast<std::size_t>(h.ids[i])].x < g.pos[static_cast<std::size_t>(h.ids[i_min])].x) i_min = i;
      if (g.pos[static_cast<std::size_t>(h.ids[i])].x > g.pos[static_cast<std::size_t>(h.ids[i_max])].x) i_max = i;
    }
    int first_target = -1;
    for (std::size_t i : {i_min, i_max}) {
      std::vector<int> targets;
      std::vector<std::pair<int, int>> tnb;
      for (std::size_t j = 0; j < m; ++j)
        if (around->ids[j] != first_target) targets.push_back(around->ids[j]), tnb.push_back(nb[j]);
      const int t = add_bridge(g, h.ids[i], h.ids[(i + n - 1) % n], h.ids[(i + 1) % n], targets, tnb);
      if (t >= 0) ++stats.fallback_bridges, added = true;
      if (first_target < 0) first_target = t;
    }
  }
  return added;
}

}  // namespace nurbs::tess::detail
