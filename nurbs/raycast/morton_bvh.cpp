#include "nurbs/raycast/morton_bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

namespace nurbs::ray {
namespace {

/// Spreads the low 10 bits of x to every third bit (Karras' "expandBits").
std::uint32_t expand_bits(std::uint32_t x) {
  x = (x * 0x00010001u) & 0xFF0000FFu;
  x = (x * 0x00000101u) & 0x0F00F00Fu;
  x = (x * 0x00000011u) & 0xC30C30C3u;
  x = (x * 0x00000005u) & 0x49249249u;
  return x;
}

/// Karras' δ(i, j): length of the common prefix of keys i and j, -1 outside [0, n). Keys are the
/// Morton code with the index appended (Karras §4: equal codes then still differ).
struct Prefix {
  const std::vector<std::uint64_t>& keys;
  int operator()(int i, int j) const {
    if (j < 0 || j >= static_cast<int>(keys.size())) return -1;
    return std::countl_zero(keys[i] ^ keys[j]);
  }
};

}  // namespace

std::uint32_t morton3(glm::dvec3 p) {
  auto q = [](double x) { return static_cast<std::uint32_t>(std::clamp(std::floor(x * 1024.0), 0.0, 1023.0)); };
  return morton3_cells(q(p.x), q(p.y), q(p.z));
}

std::uint32_t morton3_cells(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return (expand_bits(x) << 2) | (expand_bits(y) << 1) | expand_bits(z);
}

bool ray_box(const Ray& ray, const glm::dvec3& inv, const glm::dvec3& lo, const glm::dvec3& hi, double t_min,
             double t_max) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (lo[a] - ray.origin[a]) * inv[a], t1 = (hi[a] - ray.origin[a]) * inv[a];
    if (std::isnan(t0) || std::isnan(t1)) {  // direction 0 with the origin on a slab plane: inside
      if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return false;
      continue;
    }
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return false;
  }
  return true;
}

Bvh build_bvh(const std::vector<glm::dvec3>& box_min, const std::vector<glm::dvec3>& box_max) {
  const int n = static_cast<int>(box_min.size());
  if (n == 0) return {};
  // Morton codes of the centroids in the box of the centroids (§3.2).
  glm::dvec3 lo(box_min[0]), hi(box_min[0]);
  std::vector<glm::dvec3> c(n);
  for (int i = 0; i < n; ++i) {
    c[i] = 0.5 * (box_min[i] + box_max[i]);
    lo = glm::min(lo, c[i]);
    hi = glm::max(hi, c[i]);
  }
  const glm::dvec3 ext = glm::max(hi - lo, glm::dvec3(1e-300));
  std::vector<std::uint32_t> codes(n);
  for (int i = 0; i < n; ++i) codes[i] = morton3((c[i] - lo) / ext);
  return build_bvh_codes(codes, box_min, box_max);
}

Bvh build_bvh_codes(const std::vector<std::uint32_t>& codes, const std::vector<glm::dvec3>& box_min,
                    const std::vector<glm::dvec3>& box_max) {
  Bvh bvh;
  const int n = static_cast<int>(codes.size());
  if (n == 0) return bvh;
  std::vector<std::uint64_t> keys(n);
  for (int i = 0; i < n; ++i) keys[i] = (static_cast<std::uint64_t>(codes[i]) << 32) | static_cast<std::uint32_t>(i);
  std::sort(keys.begin(), keys.end());
  bvh.order.resize(n);
  bvh.codes.resize(n);
  for (int k = 0; k < n; ++k) {
    bvh.order[k] = static_cast<int>(keys[k] & 0xFFFFFFFFu);
    bvh.codes[k] = static_cast<std::uint32_t>(keys[k] >> 32);
  }
  bvh.nodes.assign(static_cast<size_t>(2 * n - 1), BvhNode{});
  for (int k = 0; k < n; ++k) {
    BvhNode& leaf = bvh.nodes[n - 1 + k];
    leaf.first = leaf.last = k;
    leaf.box_min = box_min[bvh.order[k]];
    leaf.box_max = box_max[bvh.order[k]];
  }
  // Karras 2012 §4: every internal node i independently (one GPU thread / fragment each).
  const Prefix delta{keys};
  for (int i = 0; i < n - 1; ++i) {
    const int d = delta(i, i + 1) - delta(i, i - 1) >= 0 ? 1 : -1;  // direction of the range
    const int dmin = delta(i, i - d);
    int lmax = 2;
    while (delta(i, i + lmax * d) > dmin) lmax *= 2;
    int l = 0;  // binary search for the other end
    for (int t = lmax / 2; t >= 1; t /= 2)
      if (delta(i, i + (l + t) * d) > dmin) l += t;
    const int j = i + l * d;
    const int dnode = delta(i, j);
    int s = 0;  // binary search for the split
    for (int div = 2;; div *= 2) {
      const int t = (l + div - 1) / div;
      if (delta(i, i + (s + t) * d) > dnode) s += t;
      if (t <= 1) break;
    }
    const int gamma = i + s * d + std::min(d, 0);
    BvhNode& node = bvh.nodes[i];
    node.left = std::min(i, j) == gamma ? n - 1 + gamma : gamma;
    node.right = std::max(i, j) == gamma + 1 ? n - 1 + gamma + 1 : gamma + 1;
    bvh.nodes[node.left].parent = i;
    bvh.nodes[node.right].parent = i;
  }
  // Bottom-up boxes: each leaf walks up; the second child to arrive at a node computes its box.
  std::vector<int> visits(static_cast<size_t>(std::max(n - 1, 0)), 0);
  for (int k = 0; k < n; ++k) {
    int p = bvh.nodes[n - 1 + k].parent;
    while (p >= 0 && ++visits[p] == 2) {
      BvhNode& node = bvh.nodes[p];
      node.box_min = glm::min(bvh.nodes[node.left].box_min, bvh.nodes[node.right].box_min);
      node.box_max = glm::max(bvh.nodes[node.left].box_max, bvh.nodes[node.right].box_max);
      node.first = bvh.nodes[node.left].first;  // ranges for the invariant tests; leaf() uses left
      node.last = bvh.nodes[node.right].last;
      p = node.parent;
    }
  }
  return bvh;
}

}  // namespace nurbs::ray
