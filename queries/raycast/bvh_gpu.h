#pragma once
/// \file bvh_gpu.h
/// Lemasson et al. §3.2: the Morton BVH built on the GPU in fragment passes (the paper builds it
/// in CUDA after Karras 2012; nurbs/raycast/morton_bvh.cpp is the CPU build). Passes, for n leaf
/// boxes (RGBA32F, relative to the caller's centre), N = n rounded up to a power of two:
///  0. centroids, and their box by two min / max reductions (gpgpu/reduce.h): 2 read-backs of
///     one texel, the only ones;
///  1. Morton codes, one fragment per leaf (glsl/raycast/bvh_morton.frag), keys (code, index);
///  2. a bitonic sort of the N keys (glsl/raycast/bvh_sort.frag), log2 N (log2 N + 1) / 2 passes;
///  3. Karras' internal nodes, one fragment each (glsl/raycast/bvh_karras.frag);
///  4. parents, gathered from the key ranges (glsl/raycast/bvh_parent.frag);
///  5. node boxes from a sparse table of the leaf boxes, 2 floor(log2 n) + 2 passes
///     (glsl/raycast/bvh_boxes.frag: no atomics, no walk up the tree);
///  6. the ray caster's node table (glsl/raycast/bvh_pack.frag), and optionally a per-leaf table
///     permuted into key order (glsl/raycast/bvh_gather.frag: the patches).
/// CPU twin: bvh_twin() = the float Morton codes of step 1 computed on the CPU, then
/// nurbs::ray::build_bvh_codes; the tests check that the GPU tree equals it node for node.
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/raycast/morton_bvh.h"

namespace queries {

struct GpuBvh {
  int leaves = 0;
  gpgpu::Texture keys;   ///< sorted keys (code >> 15, code & 32767, index, 0), N texels
  gpgpu::Texture nodes;  ///< the ray caster's node table: 4 texels per node, 2n - 1 nodes
  int passes = 0;        ///< fragment passes run (the reductions' included)
  double seconds = 0;    ///< waited for (glFinish)
};

/// Builds the BVH over leaf boxes (float, at most 2^24 leaves so ids stay exact in float).
[[nodiscard]] GpuBvh build_bvh_gpu(gpgpu::Gpu& gpu, std::span<const glm::vec3> box_min,
                                   std::span<const glm::vec3> box_max);

/// A table of 2^shift texels per leaf (RGBA32F, the ray caster's upload layout), input order,
/// permuted into the BVH's leaf order on the GPU (one pass).
[[nodiscard]] gpgpu::Texture gather_leaves(gpgpu::Gpu& gpu, const GpuBvh& bvh, const gpgpu::Texture& table, int shift);

/// The leaf order read back: order[k] = input index of leaf k (one read-back of N texels).
[[nodiscard]] std::vector<int> read_order(const GpuBvh& bvh);

/// The tree read back from the node table (parent, children, leaf ranges, boxes; codes and order
/// from the keys), for the tests.
[[nodiscard]] nurbs::ray::Bvh read_bvh(const GpuBvh& bvh);

/// The Morton codes step 1 computes, in the same float steps, on the CPU.
[[nodiscard]] std::vector<std::uint32_t> morton_codes_float(std::span<const glm::vec3> box_min,
                                                            std::span<const glm::vec3> box_max);

/// CPU twin: build_bvh_codes on morton_codes_float, boxes as the floats widened.
[[nodiscard]] nurbs::ray::Bvh bvh_twin(std::span<const glm::vec3> box_min, std::span<const glm::vec3> box_max);

}  // namespace queries
