#pragma once
/// \file median_tree.h
/// The bounding-box hierarchy the searches share (the tessellation's TriangleBvh, the watertight
/// stitching's segment tree, the file gaps' boundary runs of model_report.h): items' axis-aligned
/// boxes, split at the median of a key along the box's longest axis, at most four items a leaf.
/// Built once; each user walks it its own way.
#include <algorithm>
#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <numeric>
#include <vector>

namespace nurbs {

struct MedianTree {
  struct Node {
    glm::dvec3 lo, hi;
    int first, count;  ///< leaf: items order[first, first + count); inner: count = 0
    int left = -1, right = -1;
  };
  std::vector<Node> nodes;  ///< nodes[0] is the root (none for no items)
  std::vector<int> order;   ///< item indices, each leaf's a contiguous run

  /// `n` items; points(i, add) calls add(point) for every point of item i (its box is theirs);
  /// key(i, axis) orders the items along an axis (a centroid, or a multiple of it).
  template <class Points, class Key>
  MedianTree(int n, Points&& points, Key&& key) : order(size_t(n)) {
    std::iota(order.begin(), order.end(), 0);
    nodes.reserve(2 * size_t(n) / 4 + 2);
    if (n > 0) build(0, n, points, key);
  }

 private:
  template <class Points, class Key>
  int build(int first, int count, Points& points, Key& key) {
    Node node{glm::dvec3(std::numeric_limits<double>::infinity()),
              glm::dvec3(-std::numeric_limits<double>::infinity()), first, count};
    for (int k = first; k < first + count; ++k)
      points(order[size_t(k)], [&](const glm::dvec3& v) { node.lo = glm::min(node.lo, v), node.hi = glm::max(node.hi, v); });
    const int index = int(nodes.size());
    nodes.push_back(node);
    if (count <= 4) return index;
    const glm::dvec3 extent = node.hi - node.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int mid = first + count / 2;
    std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + first + count,
                     [&](int x, int y) { return key(x, axis) < key(y, axis); });
    const int left = build(first, mid - first, points, key);
    const int right = build(mid, first + count - mid, points, key);
    nodes[size_t(index)].count = 0;
    nodes[size_t(index)].left = left;
    nodes[size_t(index)].right = right;
    return index;
  }
};

}  // namespace nurbs
