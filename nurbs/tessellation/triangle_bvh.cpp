#include "nurbs/tessellation/triangle_bvh.h"

#include <algorithm>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

namespace nurbs::tess {
namespace {

glm::dvec3 closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (!(len2 > 0.0)) return a;
  return a + std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) * ab;
}

}  // namespace

glm::dvec3 closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                     const glm::dvec3& c) {
  // Inside the triangle's prism: the projection onto its plane; otherwise (or when the triangle is
  // degenerate) the closest point of its three edges.
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  const double scale = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
  if (n2 > 1e-24 * scale * scale) {
    const glm::dvec3 q = p - (glm::dot(p - a, n) / n2) * n;
    const double wa = glm::dot(glm::cross(c - b, q - b), n), wb = glm::dot(glm::cross(a - c, q - c), n),
                 wc = glm::dot(glm::cross(b - a, q - a), n);
    if (wa >= 0 && wb >= 0 && wc >= 0) return q;
  }
  glm::dvec3 best = closest_on_segment(p, a, b);
  for (const glm::dvec3& e : {closest_on_segment(p, b, c), closest_on_segment(p, c, a)})
    if (glm::dot(e - p, e - p) < glm::dot(best - p, best - p)) best = e;
  return best;
}

TriangleBvh::TriangleBvh(std::vector<std::array<glm::dvec3, 3>> triangles)
    : tris_(std::move(triangles)),
      tree_(
          int(tris_.size()),
          [&](int t, auto add) {
            for (const glm::dvec3& v : tris_[size_t(t)]) add(v);
          },
          [&](int t, int axis) {
            const auto& tri = tris_[size_t(t)];
            return tri[0][axis] + tri[1][axis] + tri[2][axis];
          }) {}

TriangleBvh::Hit TriangleBvh::closest(const glm::dvec3& p, double max_distance) const {
  Hit hit{std::numeric_limits<double>::infinity(), p, -1};
  double best = max_distance;
  for_each_near(p, best, [&](int t) {
    const auto& tri = tris_[size_t(t)];
    const glm::dvec3 q = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
    const double d = glm::length(q - p);
    if (d < best) best = d, hit = {d, q, t};
  });
  return hit;
}

bool TriangleBvh::any_within(const glm::dvec3& p, double radius) const {
  if (tree_.nodes.empty() || !(radius >= 0.0)) return false;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const MedianTree::Node& n = tree_.nodes[size_t(stack[--top])];
    if (box_distance(p, n.lo, n.hi) > radius) continue;
    if (n.count > 0) {
      for (int k = n.first; k < n.first + n.count; ++k) {
        const auto& tri = tris_[size_t(tree_.order[size_t(k)])];
        if (glm::length(closest_point_on_triangle(p, tri[0], tri[1], tri[2]) - p) <= radius) return true;
      }
      continue;
    }
    const MedianTree::Node &l = tree_.nodes[size_t(n.left)], &r = tree_.nodes[size_t(n.right)];
    const bool left_first = box_distance(p, l.lo, l.hi) <= box_distance(p, r.lo, r.hi);
    stack[top++] = left_first ? n.right : n.left;
    stack[top++] = left_first ? n.left : n.right;
  }
  return false;
}

}  // namespace nurbs::tess
