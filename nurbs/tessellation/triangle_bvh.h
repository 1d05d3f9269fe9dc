#pragma once
/// \file triangle_bvh.h
/// Closest point on a set of triangles (or segments: triangles with a repeated corner), with a
/// bounding volume hierarchy of axis-aligned boxes split at the median centroid (nurbs/median_tree.h).
/// The deviation check of the tessellation (mesh_check.h) asks it millions of times.
#include <array>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/median_tree.h"

namespace nurbs::tess {

/// Closest point of triangle (a, b, c) to p, in double. Degenerate triangles (segments, points) work:
/// the closest point of their edges is taken.
[[nodiscard]] glm::dvec3 closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                                   const glm::dvec3& c);

class TriangleBvh {
 public:
  /// Triangles as corner triples; an empty set answers +inf.
  explicit TriangleBvh(std::vector<std::array<glm::dvec3, 3>> triangles);
  struct Hit {
    double distance;
    glm::dvec3 point;
    int triangle;  ///< index in the input, -1 when empty
  };
  /// The closest point of all triangles to p (exact up to rounding), searching only boxes closer
  /// than `max_distance`.
  [[nodiscard]] Hit closest(const glm::dvec3& p, double max_distance = 1e300) const;
  /// Whether some triangle lies within `radius` of p (the search stops at the first): a maximum of
  /// distances over many points needs the exact distance only of points that would raise it.
  [[nodiscard]] bool any_within(const glm::dvec3& p, double radius) const;
  [[nodiscard]] size_t size() const { return tris_.size(); }
  /// Calls visit(index) for every triangle in a leaf whose box lies closer to p than `radius`,
  /// nearer boxes first; `radius` is read again at every box, so the visits may shrink it.
  template <class Visit>
  void for_each_near(const glm::dvec3& p, const double& radius, Visit&& visit) const {
    const auto& nodes = tree_.nodes;
    if (nodes.empty()) return;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const MedianTree::Node& n = nodes[size_t(stack[--top])];
      if (box_distance(p, n.lo, n.hi) >= radius) continue;
      if (n.count > 0) {
        for (int k = n.first; k < n.first + n.count; ++k) visit(tree_.order[size_t(k)]);
        continue;
      }
      const MedianTree::Node &l = nodes[size_t(n.left)], &r = nodes[size_t(n.right)];
      const bool left_first = box_distance(p, l.lo, l.hi) <= box_distance(p, r.lo, r.hi);
      stack[top++] = left_first ? n.right : n.left;
      stack[top++] = left_first ? n.left : n.right;
    }
  }
  /// Distance from p to the box [lo, hi] (0 inside).
  [[nodiscard]] static double box_distance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
  }

 private:
  std::vector<std::array<glm::dvec3, 3>> tris_;
  MedianTree tree_;
};

}  // namespace nurbs::tess
