#pragma once
/// \file half_edge_trim_graph.h
/// Internal to half_edge_trim.cpp / half_edge_trim_traverse.cpp: the directed graph of §6 (Balázs,
/// Guthe, Klein 2004) and its traversal. Not part of the public API.
#include <glm/vec2.hpp>
#include <map>
#include <utility>
#include <vector>

#include "nurbs/tessellation/half_edge_trim.h"

namespace nurbs::tess::detail {

/// Planar graph of cell sub-edges, trim sub-edges and bridges. An edge {a, b} (a < b) carries the net
/// number of trim traversals a -> b minus b -> a: != 0 makes it a directed edge of §6 (material on
/// its left), 0 an undirected one (cell edges, bridges, trim overlaps that cancel).
struct TrimGraph {
  struct Edge {
    int a = 0, b = 0;
    int net = 0;               ///< trim traversals a -> b minus b -> a
    bool marked = false;       ///< §7 mark: a trim edge or a bridge (the polygon may be non-convex)
    bool on_boundary = false;  ///< on R's boundary: never traversed towards the outside of R
  };
  std::vector<glm::dvec2> pos;
  std::vector<bool> on_trim;
  std::vector<Edge> edges;
  std::map<std::pair<int, int>, int> edge_index;
  glm::dvec2 lo{0.0}, hi{0.0};  ///< R
  double eps = 0.0;             ///< absolute snapping tolerance

  /// Adds (or merges into) the undirected edge {a, b}; `net_ab` trim traversals from a to b.
  void add_edge(int a, int b, int net_ab, bool marked) {
    if (a == b) return;
    const int lo_id = a < b ? a : b, hi_id = a < b ? b : a;
    const int net = a < b ? net_ab : -net_ab;
    auto [it, inserted] = edge_index.emplace(std::make_pair(lo_id, hi_id), static_cast<int>(edges.size()));
    if (inserted) edges.push_back({lo_id, hi_id, 0, false, false});
    Edge& e = edges[static_cast<std::size_t>(it->second)];
    e.net += net;
    e.marked = e.marked || marked;
  }
};

/// A closed walk of vertex ids (last joins first) and its signed area (> 0: counter-clockwise).
struct Cycle {
  std::vector<int> ids;
  double area = 0.0;
  bool marked = false;  ///< contains a marked edge
};

/// The traversal of §6 (pseudo-code of the paper): findDirectedEdge takes a directed edge from a stack;
/// the walk follows getNextEdge (the leftmost turn at each node) until it is back at its first
/// half-edge, applying handleEdge to every edge walked (directed -> deleted, undirected -> directed
/// the other way and pushed on the stack, so the cell on its other side is walked later: this is how
/// material cells without any trim edge are reached). The paper's getOutGoingEdge only chooses where
/// to continue; the stack visits the same edges. Undirected edges on R's boundary are deleted instead
/// (their other side is outside R). Each closed walk is split at repeated nodes; returns the pieces
/// with non-zero area (negative ones are holes that no bridge connects yet).
[[nodiscard]] std::vector<Cycle> traverse(const TrimGraph& graph, TrimStats& stats);

/// Tries to connect vertex `from` to one of `targets` (nearest first) by an undirected marked edge
/// that crosses no edge of the graph, passes through no vertex and leaves both ends inside the
/// material wedges given by their cycle neighbours (prev, next; -1 = no wedge test). Returns the
/// chosen target or -1.
int add_bridge(TrimGraph& graph, int from, int from_prev, int from_next, const std::vector<int>& targets,
               const std::vector<std::pair<int, int>>& target_neighbours);

/// Fallback for holes the §6 rule did not bridge (several holes in one cell, a hole whose cell corners
/// are cut off by another loop, a hole touching its cell's boundary): each negative cycle of `cycles`
/// gets two bridges, from its leftmost and rightmost vertices to the nearest visible vertices of the
/// smallest positive cycle around it. Returns whether a bridge was added (then traverse again).
bool bridge_holes(TrimGraph& graph, const std::vector<Cycle>& cycles, TrimStats& stats);

/// Signed area (shoelace) about the first vertex: differences of nearby points are exact, so the sign
/// stays right for polygons far smaller than their distance from the origin (slivers of 1e-18).
[[nodiscard]] inline double local_area(const std::vector<glm::dvec2>& p) {
  double a = 0.0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const glm::dvec2 u = p[i] - p[0], w = p[i + 1] - p[0];
    a += u.x * w.y - u.y * w.x;
  }
  return 0.5 * a;
}

/// Twice the signed area of triangle (a, b, c).
[[nodiscard]] inline double orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

}  // namespace nurbs::tess::detail
