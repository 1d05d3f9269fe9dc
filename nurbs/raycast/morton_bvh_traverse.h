#pragma once
/// \file morton_bvh_traverse.h
/// Template bodies of the traversals declared in morton_bvh.h.
#include <glm/geometric.hpp>
#include <vector>

namespace nurbs::ray::detail {

inline glm::dvec3 inverse_direction(const glm::dvec3& d) { return 1.0 / d; }  // +-inf on zero components

inline bool near_is_left(const Bvh& bvh, const BvhNode& n, const Ray& ray) {
  const BvhNode &l = bvh.nodes[n.left], &r = bvh.nodes[n.right];
  return glm::dot((l.box_min + l.box_max) - (r.box_min + r.box_max), ray.direction) <= 0.0;
}
inline int near_child(const Bvh& bvh, int i, const Ray& ray) {
  const BvhNode& n = bvh.nodes[i];
  return near_is_left(bvh, n, ray) ? n.left : n.right;
}
inline int far_child(const Bvh& bvh, int i, const Ray& ray) {
  const BvhNode& n = bvh.nodes[i];
  return near_is_left(bvh, n, ray) ? n.right : n.left;
}
inline int sibling(const Bvh& bvh, int i) {
  const BvhNode& p = bvh.nodes[bvh.nodes[i].parent];
  return p.left == i ? p.right : p.left;
}

}  // namespace nurbs::ray::detail

namespace nurbs::ray {

template <class Visit>
void traverse_stackless(const Bvh& bvh, const Ray& ray, double t_min, double t_max, Visit&& visit,
                        TraversalStats* stats) {
  if (bvh.nodes.empty()) return;
  const glm::dvec3 inv = detail::inverse_direction(ray.direction);
  auto test = [&](int i) {
    if (stats) ++stats->box_tests;
    return ray_box(ray, inv, bvh.nodes[i].box_min, bvh.nodes[i].box_max, t_min, t_max);
  };
  auto leaf = [&](int i) {
    const BvhNode& n = bvh.nodes[i];
    if (stats) stats->patch_tests += n.last - n.first + 1;
    t_max = visit(n.first, n.last);
  };
  const int root = bvh.root();
  if (!test(root)) return;
  if (bvh.nodes[root].leaf()) return leaf(root);
  enum class From { Parent, Sibling, Child };
  int cur = detail::near_child(bvh, root, ray);
  From state = From::Parent;
  for (;;) {
    const BvhNode& n = bvh.nodes[cur];
    if (state == From::Child) {
      if (cur == root) return;
      const int parent = n.parent;
      if (cur == detail::near_child(bvh, parent, ray)) {
        cur = detail::sibling(bvh, cur);
        state = From::Sibling;
      } else {
        cur = parent;
        state = From::Child;
      }
    } else if (!test(cur)) {  // From::Parent goes on to the sibling, From::Sibling back up
      if (state == From::Parent) {
        cur = detail::sibling(bvh, cur);
        state = From::Sibling;
      } else {
        cur = n.parent;
        state = From::Child;
      }
    } else if (n.leaf()) {
      leaf(cur);
      if (state == From::Parent) {
        cur = detail::sibling(bvh, cur);
        state = From::Sibling;
      } else {
        cur = n.parent;
        state = From::Child;
      }
    } else {
      cur = detail::near_child(bvh, cur, ray);
      state = From::Parent;
    }
  }
}

template <class Visit>
void traverse_stack(const Bvh& bvh, const Ray& ray, double t_min, double t_max, Visit&& visit, TraversalStats* stats) {
  if (bvh.nodes.empty()) return;
  const glm::dvec3 inv = detail::inverse_direction(ray.direction);
  std::vector<int> stack{bvh.root()};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const BvhNode& n = bvh.nodes[i];
    if (stats) ++stats->box_tests;
    if (!ray_box(ray, inv, n.box_min, n.box_max, t_min, t_max)) continue;
    if (n.leaf()) {
      if (stats) stats->patch_tests += n.last - n.first + 1;
      t_max = visit(n.first, n.last);
      continue;
    }
    stack.push_back(detail::far_child(bvh, i, ray));
    stack.push_back(detail::near_child(bvh, i, ray));
  }
}

}  // namespace nurbs::ray
