#pragma once
/// \file point_batch_descent.h
/// Step 2 of the batched point projection (point_batch.h) on the CPU: the twin in double of the
/// GPU pass (glsl/distance/point_batch.frag, PointBatch::descend_gpu). The same pyramid (the
/// axis-aligned one rebuilt here from the read-back samples, bit for bit as aabb_leaf.frag and
/// aabb_merge.frag; the oriented one as uploaded), the same depth-first walk, nearest child first
/// after the pass's sorting network, the same pruning by the best distance plus the float slack,
/// and at the cells a trim edge crosses the same distance to their material part.
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "queries/distance/point_batch_geometry.h"

namespace queries {

/// Node expansions of one point's walk in the GPU pass before it is cut short and descended again
/// by the twin: a bound on one fragment's work on any GPU (a hardware watchdog ends long draws), below
/// llvmpipe's own end of an invocation's loops (65535 iterations in all).
inline constexpr int kWalkBudget = 1 << 13;

/// Indices of `points` sorted by the Morton code of their position in the cube of half side
/// `half` about `centre` (10 bits per axis, outside points clamped to its faces): the order the
/// pass lays the points out in, and the finishing walks them in.
[[nodiscard]] std::vector<uint32_t> morton_order(std::span<const glm::dvec3> points, const glm::dvec3& centre,
                                                 double half);

/// The axis-aligned pyramid of atlas `at` (the a-th of g) on the CPU, xyz per texel and level, into
/// at.cpu_lo and at.cpu_hi; nothing when it exists.
void build_cpu_pyramid(const BatchGeometry& g, size_t a, BatchAtlas& at);

/// The best cell of atlas a for point p, as the GPU pass finds it; `within` > 0: only a cell nearer
/// than it. `trim_on_gpu`: the material part of the cells a trim edge crosses (PointBatch's
/// set_trim_on_gpu). With PointBoxes::Aabb the CPU pyramid must exist (build_cpu_pyramid).
[[nodiscard]] BatchCell descend_cpu(const BatchGeometry& g, size_t a, const glm::dvec3& p, double within,
                                    bool trim_on_gpu);

}  // namespace queries
