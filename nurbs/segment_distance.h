#pragma once
/// \file segment_distance.h
/// Distance from a point to a segment, in (u, v) or in space.
#include <algorithm>
#include <glm/geometric.hpp>

namespace nurbs {

/// Distance from p to the segment a b.
template <int D>
[[nodiscard]] double segment_distance(const glm::vec<D, double>& p, const glm::vec<D, double>& a,
                                      const glm::vec<D, double>& b) {
  const glm::vec<D, double> d = b - a;
  const double l2 = glm::dot(d, d);
  const double lam = l2 > 0.0 ? std::clamp(glm::dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
  return glm::length(p - a - lam * d);
}

}  // namespace nurbs
