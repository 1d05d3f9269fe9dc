/// \file half_edge_trim.cpp
/// §6 of Balázs, Guthe and Klein (2004): building the directed half-edge graph from the cells and the
/// trim polylines, the hole bridges, and the entry point trim_cells. The traversal itself is in
/// half_edge_trim_traverse.cpp.
#include "nurbs/tessellation/half_edge_trim.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <map>

#include "nurbs/tessellation/half_edge_trim_graph.h"
#include "nurbs/trim_classify.h"

namespace nurbs::tess {
namespace {

/// Rounds of cutting the cells under holes left unjoined (trim_cells): one suffices when the holes
/// do not overlap in u; each further round handles holes that the first cuts missed.
constexpr int kHoleCutRounds = 4;

using detail::Cycle;
using detail::TrimGraph;
using Line = std::map<double, std::vector<std::pair<double, int>>>;  // coordinate -> (other coord, id)

/// Sutherland–Hodgman against one half-plane {p : sign * (p[axis] - c) <= 0}; the crossing point gets
/// the coordinate c exactly, so clipped loops run exactly along R's boundary.
std::vector<glm::dvec2> clip_half_plane(const std::vector<glm::dvec2>& in, int axis, double c, double sign) {
  std::vector<glm::dvec2> out;
  const std::size_t n = in.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec2 p = in[i], q = in[(i + 1) % n];
    const double dp = sign * (p[axis] - c), dq = sign * (q[axis] - c);
    if (dp <= 0.0) out.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) {
      glm::dvec2 x = p + (q - p) * (dp / (dp - dq));
      x[axis] = c;
      out.push_back(x);
    }
  }
  return out;
}

/// Moves v onto the nearest value of the sorted `lines` when closer than eps.
double snap(double v, const std::vector<double>& lines, double eps, int& count) {
  auto it = std::lower_bound(lines.begin(), lines.end(), v);
  double best = v, dist = eps;
  if (it != lines.end() && std::abs(*it - v) <= dist) best = *it, dist = std::abs(*it - v);
  if (it != lines.begin() && std::abs(*(it - 1) - v) <= dist) best = *(it - 1);
  if (best != v) ++count;
  return best;
}

/// True when t lies on one of the (unmerged) cell-edge intervals of a line, within eps.
bool on_intervals(const std::vector<std::pair<double, double>>& iv, double t, double eps) {
  return std::any_of(iv.begin(), iv.end(), [&](auto s) { return t >= s.first - eps && t <= s.second + eps; });
}

struct Builder {
  TrimGraph g;
  std::map<std::pair<double, double>, int> ids;
  int vertex(glm::dvec2 p, bool trim) {
    auto [it, inserted] = ids.emplace(std::make_pair(p.x, p.y), static_cast<int>(g.pos.size()));
    if (inserted) g.pos.push_back(p), g.on_trim.push_back(false);
    if (trim) g.on_trim[static_cast<std::size_t>(it->second)] = true;
    return it->second;
  }
};

/// Ids of the vertices on line `at` of `lines` between a and b, ordered from a to b.
std::vector<int> on_line(Line& lines, double at, double a, double b) {
  std::vector<int> out;
  const auto& l = lines[at];
  auto first = std::lower_bound(l.begin(), l.end(), std::make_pair(std::min(a, b), -1));
  for (auto it = first; it != l.end() && it->first <= std::max(a, b); ++it) out.push_back(it->second);
  if (a > b) std::reverse(out.begin(), out.end());
  return out;
}

/// One build and traversal of the graph (trim_cells' steps 1-6). The bounding boxes of the holes
/// that no bridge joined (negative cycles, left out of the output) go to `unresolved`.
TrimmedPolygons trim_once(const std::vector<Cell>& cells, const std::vector<LoopPolyline>& loops,
                          const TrimOptions& options, std::vector<std::pair<glm::dvec2, glm::dvec2>>& unresolved) {
  TrimmedPolygons result;
  TrimStats& stats = result.stats;
  if (cells.empty()) return result;
  Builder bld;
  TrimGraph& g = bld.g;
  g.lo = {cells[0].u.min, cells[0].v.min};
  g.hi = {cells[0].u.max, cells[0].v.max};
  std::vector<double> xs, ys;
  std::map<double, std::vector<std::pair<double, double>>> vseg, hseg;  // cell edges per line
  for (const Cell& c : cells) {
    g.lo = glm::min(g.lo, glm::dvec2(c.u.min, c.v.min));
    g.hi = glm::max(g.hi, glm::dvec2(c.u.max, c.v.max));
    xs.insert(xs.end(), {c.u.min, c.u.max});
    ys.insert(ys.end(), {c.v.min, c.v.max});
    for (double x : {c.u.min, c.u.max}) vseg[x].emplace_back(c.v.min, c.v.max);
    for (double y : {c.v.min, c.v.max}) hseg[y].emplace_back(c.u.min, c.u.max);
    for (double x : {c.u.min, c.u.max})
      for (double y : {c.v.min, c.v.max}) bld.vertex({x, y}, false);
  }
  std::sort(xs.begin(), xs.end()), xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::sort(ys.begin(), ys.end()), ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  g.eps = options.snap_relative * std::max(g.hi.x - g.lo.x, g.hi.y - g.lo.y);

  // Loops: clip to R, snap onto cell lines, drop repeated points and degenerate loops.
  std::vector<std::vector<glm::dvec2>> rings;
  std::vector<bool> ring_outer;
  bool any_outer = false;
  for (const LoopPolyline& loop : loops) {
    any_outer = any_outer || loop.outer;
    std::vector<glm::dvec2> p;
    bool outside = false;
    for (glm::dvec2 q : loop.uv) {
      q.x = snap(q.x, xs, g.eps, stats.snapped_coordinates);
      q.y = snap(q.y, ys, g.eps, stats.snapped_coordinates);
      outside = outside || q.x < g.lo.x || q.y < g.lo.y || q.x > g.hi.x || q.y > g.hi.y;
      p.push_back(q);
    }
    if (outside) {
      ++stats.clipped_loops;
      p = clip_half_plane(p, 0, g.lo.x, -1.0), p = clip_half_plane(p, 0, g.hi.x, 1.0);
      p = clip_half_plane(p, 1, g.lo.y, -1.0), p = clip_half_plane(p, 1, g.hi.y, 1.0);
    }
    std::vector<glm::dvec2> r;
    for (glm::dvec2 q : p)
      if (r.empty() || q != r.back()) r.push_back(q);
    while (r.size() > 1 && r.front() == r.back()) r.pop_back();
    if (r.size() < 3 || detail::local_area(r) == 0.0) continue;
    rings.push_back(std::move(r));
    ring_outer.push_back(loop.outer);
  }
  if (!any_outer) {  // no outer loop: R's boundary is the outer loop
    rings.push_back({g.lo, {g.hi.x, g.lo.y}, g.hi, {g.lo.x, g.hi.y}});
    ring_outer.push_back(true);
  }

  // Vertices: cell corners (above), loop vertices, then crossings of loop segments with cell edges.
  std::vector<std::vector<int>> ring_ids(rings.size());
  Line col_x, col_y;
  for (std::size_t k = 0; k < rings.size(); ++k)
    for (glm::dvec2 q : rings[k]) ring_ids[k].push_back(bld.vertex(q, true));
  for (std::size_t i = 0; i < g.pos.size(); ++i) {
    col_x[g.pos[i].x].emplace_back(g.pos[i].y, static_cast<int>(i));
    col_y[g.pos[i].y].emplace_back(g.pos[i].x, static_cast<int>(i));
  }
  for (auto* l : {&col_x, &col_y})
    for (auto& [c, v] : *l) std::sort(v.begin(), v.end());
  // A crossing point within eps of a vertex already on the line (a corner, a loop vertex) becomes it.
  auto snap_on_line = [&](Line& l, double at, double t) {
    const auto& v = l[at];
    auto it = std::lower_bound(v.begin(), v.end(), std::make_pair(t, -1));
    double best = t, dist = g.eps;
    if (it != v.end() && std::abs(it->first - t) <= dist) best = it->first, dist = std::abs(it->first - t);
    if (it != v.begin() && std::abs((it - 1)->first - t) <= dist) best = (it - 1)->first;
    return best;
  };
  std::vector<std::vector<std::vector<int>>> crossings(rings.size());
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const auto& r = rings[k];
    crossings[k].resize(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
      const glm::dvec2 a = r[i], b = r[(i + 1) % r.size()];
      for (auto it = std::upper_bound(xs.begin(), xs.end(), std::min(a.x, b.x));
           it != xs.end() && *it < std::max(a.x, b.x); ++it) {
        const double y = snap_on_line(col_x, *it, a.y + (*it - a.x) * (b.y - a.y) / (b.x - a.x));
        if (on_intervals(vseg[*it], y, g.eps)) crossings[k][i].push_back(bld.vertex({*it, y}, true));
      }
      for (auto it = std::upper_bound(ys.begin(), ys.end(), std::min(a.y, b.y));
           it != ys.end() && *it < std::max(a.y, b.y); ++it) {
        const double x = snap_on_line(col_y, *it, a.x + (*it - a.y) * (b.x - a.x) / (b.y - a.y));
        if (on_intervals(hseg[*it], x, g.eps)) crossings[k][i].push_back(bld.vertex({x, *it}, true));
      }
    }
  }
  col_x.clear(), col_y.clear();
  for (std::size_t i = 0; i < g.pos.size(); ++i) {
    col_x[g.pos[i].x].emplace_back(g.pos[i].y, static_cast<int>(i));
    col_y[g.pos[i].y].emplace_back(g.pos[i].x, static_cast<int>(i));
  }
  for (auto* l : {&col_x, &col_y})
    for (auto& [c, v] : *l) std::sort(v.begin(), v.end());

  // Edges: cell sides with every vertex on them (the paper's "rectangles with additional points
  // inserted along the edges"), then loop segments split at their crossings, as directed half-edges.
  auto chain = [&](const std::vector<int>& v, int net, bool marked) {
    for (std::size_t i = 0; i + 1 < v.size(); ++i) g.add_edge(v[i], v[i + 1], net, marked);
  };
  for (const Cell& c : cells) {
    chain(on_line(col_y, c.v.min, c.u.min, c.u.max), 0, false);
    chain(on_line(col_y, c.v.max, c.u.min, c.u.max), 0, false);
    chain(on_line(col_x, c.u.min, c.v.min, c.v.max), 0, false);
    chain(on_line(col_x, c.u.max, c.v.min, c.v.max), 0, false);
  }
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const auto& r = rings[k];
    for (std::size_t i = 0; i < r.size(); ++i) {
      const glm::dvec2 a = r[i], b = r[(i + 1) % r.size()];
      std::vector<int> v;
      if (a.x == b.x) {
        v = on_line(col_x, a.x, a.y, b.y);
      } else if (a.y == b.y) {
        v = on_line(col_y, a.y, a.x, b.x);
      } else {
        v = crossings[k][i];
        std::sort(v.begin(), v.end(), [&](int p, int q) {
          return glm::dot(g.pos[static_cast<std::size_t>(p)] - a, b - a) <
                 glm::dot(g.pos[static_cast<std::size_t>(q)] - a, b - a);
        });
        v.insert(v.begin(), ring_ids[k][i]);
        v.push_back(ring_ids[k][(i + 1) % r.size()]);
      }
      chain(v, 1, true);
    }
  }
  for (auto& e : g.edges) {
    const glm::dvec2 p = g.pos[static_cast<std::size_t>(e.a)], q = g.pos[static_cast<std::size_t>(e.b)];
    e.on_boundary =
        (p.x == q.x && (p.x == g.lo.x || p.x == g.hi.x)) || (p.y == q.y && (p.y == g.lo.y || p.y == g.hi.y));
    if (e.net != 0) {
      ++stats.trim_edges;
      g.on_trim[static_cast<std::size_t>(e.a)] = g.on_trim[static_cast<std::size_t>(e.b)] = true;
    }
  }

  // §6 hole bridges: a clockwise loop strictly inside one cell is joined to the cell's upper-left and
  // lower-right corners by two undirected edge pairs, to the nearest loop vertex each can see.
  for (std::size_t k = 0; k < rings.size(); ++k) {
    if (ring_outer[k] || detail::local_area(rings[k]) >= 0.0) continue;
    const auto& r = rings[k];
    auto inside = [&](const Cell& c, glm::dvec2 p) {
      return p.x > c.u.min && p.x < c.u.max && p.y > c.v.min && p.y < c.v.max;
    };
    auto cell = std::find_if(cells.begin(), cells.end(), [&](const Cell& c) { return inside(c, r[0]); });
    if (cell == cells.end() || !std::all_of(r.begin(), r.end(), [&](glm::dvec2 p) { return inside(*cell, p); }))
      continue;
    std::vector<std::pair<int, int>> nb;
    for (std::size_t i = 0; i < r.size(); ++i)
      nb.emplace_back(ring_ids[k][(i + r.size() - 1) % r.size()], ring_ids[k][(i + 1) % r.size()]);
    const int ul = bld.vertex({cell->u.min, cell->v.max}, false);
    const int lr = bld.vertex({cell->u.max, cell->v.min}, false);
    const int t1 = detail::add_bridge(g, ul, -1, -1, ring_ids[k], nb);
    std::vector<int> rest;
    std::vector<std::pair<int, int>> rest_nb;
    for (std::size_t i = 0; i < r.size(); ++i)
      if (ring_ids[k][i] != t1) rest.push_back(ring_ids[k][i]), rest_nb.push_back(nb[i]);
    const int t2 = t1 < 0 ? -1 : detail::add_bridge(g, lr, -1, -1, rest, rest_nb);
    stats.paper_bridges += (t1 >= 0) + (t2 >= 0);
  }

  // Traversal; holes no §6 bridge reached (several holes in a cell, a hole touching a cell edge...)
  // get two bridges to the boundary of the polygon around them, then the traversal is run again.
  std::vector<Cycle> cycles;
  for (int round = 0; round < 8; ++round) {
    stats.traversal_rounds = round + 1;
    cycles = detail::traverse(g, stats);
    if (!detail::bridge_holes(g, cycles, stats)) break;
  }

  // Output: positive cycles, with the vertices they use renumbered compactly.
  std::vector<int> remap(g.pos.size(), -1);
  for (const Cycle& c : cycles) {
    if (c.area < 0.0) {
      glm::dvec2 lo(HUGE_VAL), hi(-HUGE_VAL);
      for (int id : c.ids) {
        lo = glm::min(lo, g.pos[static_cast<std::size_t>(id)]);
        hi = glm::max(hi, g.pos[static_cast<std::size_t>(id)]);
      }
      unresolved.emplace_back(lo, hi);
    }
    if (c.area <= 0.0) {
      ++stats.dropped_cycles;
      continue;
    }
    std::vector<int> poly;
    for (int id : c.ids) {
      int& r = remap[static_cast<std::size_t>(id)];
      if (r < 0) {
        r = static_cast<int>(result.vertices.size());
        result.vertices.push_back(g.pos[static_cast<std::size_t>(id)]);
        result.on_trim.push_back(g.on_trim[static_cast<std::size_t>(id)]);
      }
      poly.push_back(r);
    }
    result.polygons.push_back(std::move(poly));
    result.has_trim_edge.push_back(c.marked);
  }
  stats.graph_vertices = static_cast<int>(g.pos.size());
  stats.graph_edges = static_cast<int>(g.edges.size());
  return result;
}

}  // namespace

TrimmedPolygons trim_cells(const std::vector<Cell>& cells, const std::vector<LoopPolyline>& loops,
                           const TrimOptions& options) {
  // A hole that the bridges cannot join (the nearest vertices of the polygon around it hidden by
  // other holes, say a row of pin holes in one cell whose corners the outer loop cuts off) would be
  // left covered by that polygon. The cells under it are cut at the middle of its u range instead:
  // the hole then crosses a cell edge and joins the graph as any loop crossing cells does. A piece
  // of a cell keeps the cell's bound, and T-junctions are handled as everywhere else.
  std::vector<Cell> cut = cells;
  std::vector<std::pair<glm::dvec2, glm::dvec2>> unresolved;
  TrimmedPolygons result = trim_once(cut, loops, options, unresolved);
  int cut_cells = 0;
  for (int round = 0; round < kHoleCutRounds && !unresolved.empty(); ++round) {
    const int before = cut_cells;
    for (const auto& [lo, hi] : unresolved) {
      const double mid = 0.5 * (lo.x + hi.x);
      const std::size_t n = cut.size();
      for (std::size_t i = 0; i < n; ++i) {
        Cell& c = cut[i];
        if (!(c.u.min < mid && mid < c.u.max && c.v.min < hi.y && lo.y < c.v.max)) continue;
        Cell right = c;
        c.u.max = right.u.min = mid;
        cut.push_back(right);
        ++cut_cells;
      }
    }
    if (cut_cells == before) break;  // cell lines already run through them: not a bridging problem
    unresolved.clear();
    result = trim_once(cut, loops, options, unresolved);
  }
  result.stats.cut_cells = cut_cells;
  result.stats.unresolved_holes = static_cast<int>(unresolved.size());
  return result;
}

}  // namespace nurbs::tess
