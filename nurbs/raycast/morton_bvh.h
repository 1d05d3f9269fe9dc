#pragma once
/// \file morton_bvh.h
/// Lemasson et al. §3.2 "BVH method": a linear BVH over patch boxes. Morton codes of the box
/// centroids in the scene box (30 bits, 10 per axis), sorted; the binary radix tree of Karras
/// (HPG 2012, "Maximizing parallelism in the construction of BVHs, octrees and k-d trees"), each
/// internal node built independently from the longest common prefixes (a loop here, one fragment
/// per node on the GPU); node boxes by a bottom-up pass with visit counters (as the GPU does it);
/// traversal without a stack by Hapala, Davidovič, Wald, Havran and Slusallek (SCCG 2011): parent
/// pointers and the three-state automaton (from parent / from sibling / from child).
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/raycast/ray_patch.h"

namespace nurbs::ray {

/// 30-bit Morton code of a point with coordinates in [0, 1]^3 (10 bits per axis, x highest).
[[nodiscard]] std::uint32_t morton3(glm::dvec3 unit_point);
/// The same from the cell indices (each in [0, 1023]): their bits interleaved, x highest.
[[nodiscard]] std::uint32_t morton3_cells(std::uint32_t x, std::uint32_t y, std::uint32_t z);

/// Node layout: internal nodes 0 .. n-2 (root 0), leaf k at n - 1 + k holds the k-th patch in
/// Morton order; one patch per leaf (the paper's leaves hold a first/last range: here first = last).
struct BvhNode {
  glm::dvec3 box_min{0.0}, box_max{0.0};
  int parent = -1;            ///< -1 at the root
  int left = -1, right = -1;  ///< children (internal nodes only)
  int first = -1, last = -1;  ///< patch range in `order`, inclusive (leaves only)
  [[nodiscard]] bool leaf() const { return left < 0; }
};

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<int> order;            ///< order[k] = caller's index of the k-th patch in Morton order
  std::vector<std::uint32_t> codes;  ///< sorted Morton codes, codes[k] of order[k]
  [[nodiscard]] int leaf_count() const { return static_cast<int>(order.size()); }
  [[nodiscard]] int root() const { return 0; }
};

/// Builds the tree over boxes (box_min[i], box_max[i]) (§3.2; Karras Fig. 4 / Alg. on §4).
[[nodiscard]] Bvh build_bvh(const std::vector<glm::dvec3>& box_min, const std::vector<glm::dvec3>& box_max);
/// The same from given Morton codes (codes[i] of box i): keys = code << 32 | i, sorted, then
/// Karras' internal nodes and the bottom-up boxes. The twin of the GPU build, whose codes come
/// from float arithmetic (queries/raycast/bvh_gpu.h).
[[nodiscard]] Bvh build_bvh_codes(const std::vector<std::uint32_t>& codes, const std::vector<glm::dvec3>& box_min,
                                  const std::vector<glm::dvec3>& box_max);

/// Slab test of a box against a ray for t in [t_min, t_max].
[[nodiscard]] bool ray_box(const Ray& ray, const glm::dvec3& inv_dir, const glm::dvec3& lo, const glm::dvec3& hi,
                           double t_min, double t_max);

/// Per-ray counters (Fig. 7 of the paper: intersection tests per ray).
struct TraversalStats {
  long box_tests = 0;
  long patch_tests = 0;
};

/// Stackless traversal (Hapala et al. 2011). The near child of a node is the one whose box centre
/// lies first along the ray. `visit(first, last)` is called for each reached leaf's patch range and
/// returns the current t_max (the nearest hit so far, so farther boxes get pruned).
template <class Visit>
void traverse_stackless(const Bvh& bvh, const Ray& ray, double t_min, double t_max, Visit&& visit,
                        TraversalStats* stats = nullptr);

/// The same traversal with an explicit stack, for tests (near child first).
template <class Visit>
void traverse_stack(const Bvh& bvh, const Ray& ray, double t_min, double t_max, Visit&& visit,
                    TraversalStats* stats = nullptr);

}  // namespace nurbs::ray

#include "nurbs/raycast/morton_bvh_traverse.h"
