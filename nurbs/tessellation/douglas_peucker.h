#pragma once
/// \file douglas_peucker.h
/// The Douglas-Peucker refinement shared by the polyline simplifications of the tessellation: §5's
/// loop simplification (trim_polyline.h) and the thinning of dense polyline trim curves before §4
/// (trim_thinning.h).
#include <algorithm>
#include <cstddef>
#include <glm/geometric.hpp>
#include <utility>
#include <vector>

#include "nurbs/segment_distance.h"

namespace nurbs::tess {

/// Refines `keep` (one flag per vertex of a polyline of keep.size() vertices; the vertices kept at
/// the start, vertex 0 among them, and for an open polyline the last one too): every chain between
/// two kept vertices a < b (for a closed polyline the last chain runs back to vertex 0, passed as b =
/// 0) whose worst inner vertex k has ratio(k, a, b) > 1 keeps that vertex, and both halves are
/// checked again. ratio is the vertex's distance from the chord a b over the tolerance.
template <class Ratio>
void douglas_peucker(std::vector<bool>& keep, bool closed, Ratio ratio) {
  const size_t m = keep.size();
  std::vector<std::pair<size_t, size_t>> stack;  // chains (a, b), b = m for the closing one
  for (size_t a = 0; a < m;) {
    size_t b = a + 1;
    while (b < m && !keep[b]) ++b;
    if (b < m || closed) stack.push_back({a, b});
    a = b;
  }
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = 0.0;
    size_t wk = a;
    for (size_t k = a + 1; k < b; ++k)
      if (const double r = ratio(k, a, b % m); r > worst) worst = r, wk = k;
    if (worst <= 1.0) continue;
    keep[wk] = true;
    stack.push_back({a, wk});
    stack.push_back({wk, b});
  }
}

}  // namespace nurbs::tess
