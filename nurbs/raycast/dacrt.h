#pragma once
/// \file dacrt.h
/// Lemasson et al. §3.2 "DACRT method": divide-and-conquer ray tracing after Mora (2011) and Áfra
/// (2012), with no acceleration structure kept. A set of patches and a set of rays: the patches
/// are split in two at the centroid median on the largest axis of their box; for each half the rays
/// that cross its box are moved to the front of the ray range by an in-place partition and the half
/// is processed with them; below either threshold every ray is tested against every patch
/// (brute force). The CPU twin of the GPU version.
#include <vector>

#include "nurbs/raycast/raycast_cpu.h"

namespace nurbs::ray {

struct DacrtOptions {
  int patch_leaf = 8;  ///< brute force when a patch set is at most this large ...
  int ray_leaf = 8;    ///< ... or a ray set is at most this large (Mora's two thresholds)
};

struct DacrtStats {
  long box_tests = 0;    ///< ray / patch-set box tests
  long patch_tests = 0;  ///< ray / patch tests in the brute-force leaves
};

/// Nearest hits (t > t_min) of every ray, as cast_ray would find them.
[[nodiscard]] std::vector<Hit> cast_rays_dacrt(const Scene& scene, const std::vector<Ray>& rays, double t_min,
                                               const DacrtOptions& options = {}, DacrtStats* stats = nullptr);

}  // namespace nurbs::ray
