#pragma once
/// \file raycast_gpu.h
/// The GPU ray caster of Lemasson et al. (§3.2-3.4): one fragment per ray
/// (glsl/raycast/raycast.frag) walks the scene's Morton BVH without a stack, intersects the bicubic patches
/// of the reached leaves by the two-plane Newton iteration and tests hits against the faces' cubic
/// trims, all in float, relative to the scene centre. The double-precision twin and test oracle is
/// nurbs::ray::cast_ray (Trim::Cubics, Traversal::Stackless).
///
/// Data, uploaded once (RGBA32F, power-of-two widths, element i at (i & (w-1), i >> log2 w); ids as
/// floats, exact below 2^24):
///  - patches: 16 texels each, control point p[4 j + i] relative to the centre; the w channels hold
///    the face (texel 0), the control box diagonal (1) and range_u, range_v (2-5);
///  - BVH nodes: 4 texels each: (box min, parent), (box max, left), then (2 x the left box centre -
///    the right's, right) for an internal node, (first, last, 0, -1) for a leaf, then the parent's
///    such vector and the sibling (-1 - sibling for a right child);
///  - trim cubics: 3 texels each: (p0, p1), (p2, p3) in (u, v), (next, prev, 0, 0), faces one after
///    the other; faces: 2 texels each: (first cubic, count, 0, 0), (domain u min/max, v min/max).
/// One pass per chunk of rays (up to 1024 x 1024, 16 consecutive rays per 4 x 4 tile so SIMD lanes
/// hold neighbours) with two colour attachments: (t, patch, s, t) and (box tests, patch tests, trim
/// tests, flags: 1 doubt, 2 cut). Then per ray on the CPU, in double (every hardware thread): the hit's face
/// parameters from the patch's ranges, refine_on_surface on the exact face and is_material on the
/// flattened trim; a ray whose refinement fails, whose hit is not material, or whose pass flagged a
/// doubt (a nearer hit rejected by the float trim test within reach of the curve) or a cut walk is
/// cast again by cast_ray (a fallback).
///
/// Float (the kernel's allowances): the pass moves each patch into the ray's frame (N1, N2, d) once,
/// so Newton evaluates R (Eq. 2) and its Jacobian (Eq. 4) by de Casteljau on two coordinates. A
/// pass hit counts as converged when |R| <= max(1e-7 patch diagonal (the twin's), eps3), eps3 =
/// float_floor(o) = kUlps ulp of (|o - centre| + radius()), what float can reach; its (s, t) margin
/// grows by eps3 / |S_s|, eps3 / |S_t|. Its t is within eps3 / |cos incidence| of the twin's
/// bicubic t (the tests measure <= 0.25 of that). Hits the twin's stricter residual test leaves
/// unconverged after 7 steps may count for the pass (then cast() keeps them if the exact step
/// confirms them).
#include <span>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/raycast/raycast_cpu.h"

namespace queries {

/// Figures of the last cast (summed over its passes).
struct RaycastGpuStats {
  long long rays = 0, box_tests = 0, patch_tests = 0, fallbacks = 0;
  double gpu_seconds = 0;                                    ///< uploads, passes and read-backs (waited for)
  double cpu_seconds = 0;                                    ///< the double-precision finishing and fallbacks
  size_t bytes_bvh = 0, bytes_patches = 0, bytes_trims = 0;  ///< texture memory (trims: cubics + face table)
};

/// Where the BVH of the pass comes from: the scene's (built on the CPU by build_scene), or built
/// again on the GPU from the patch boxes (queries/raycast/bvh_gpu.h, the paper's way; its leaf order may
/// differ from the scene's where float rounding moves a centroid across a Morton cell).
enum class BvhBuild { Cpu, Gpu };

/// Figures of the GPU build (BvhBuild::Gpu).
struct BvhBuildStats {
  int passes = 0;
  double seconds = 0;  ///< the build passes, the patch gather and the read-back of the leaf order
};

/// One ray's answer from the pass alone: float t (along the unit direction), patch (index into
/// scene.patches; -1: miss), local (s, t) on the patch; the per-ray counts of the twin's TraversalStats;
/// trim_tests = §3.4 tests run; doubt: see the file comment; cut: the walk did not finish (llvmpipe
/// ends an invocation's loops after 65535 iterations in all; a walk through ~10^5 overlapping
/// patches gets there), so the answer may miss a nearer hit. cast() casts doubt and cut rays again.
struct RawRayHit {
  float t = -1;
  int patch = -1;
  float s = 0, t_param = 0;
  int box_tests = 0, patch_tests = 0;
  int trim_tests = 0;
  bool doubt = false;
  bool cut = false;
};

class GpuRaycaster {
 public:
  /// Uploads the scene's tables once. `scene` must be built with Trim::Cubics (else
  /// std::invalid_argument) and must outlive this object.
  GpuRaycaster(gpgpu::Gpu& gpu, const nurbs::ray::Scene& scene, BvhBuild build = BvhBuild::Cpu);

  /// The pass alone for rays (unit directions) with hits at t > t_min, input order kept.
  std::vector<RawRayHit> cast_raw(std::span<const nurbs::ray::Ray> rays, double t_min);
  /// The pass and the CPU finishing: the twin's hits (t, face, uv, point on the exact face), with
  /// t_bicubic = the pass's float t. Misses: t = -1, face = -1.
  std::vector<nurbs::ray::Hit> cast(std::span<const nurbs::ray::Ray> rays, double t_min);

  [[nodiscard]] const RaycastGpuStats& stats() const { return stats_; }
  [[nodiscard]] const BvhBuildStats& build_stats() const { return build_stats_; }
  /// Rays per pass (default 1024 x 1024).
  [[nodiscard]] size_t rays_per_pass() const { return rays_per_pass_; }
  void set_rays_per_pass(size_t n) { rays_per_pass_ = n < 16 ? 16 : n; }
  /// CPU threads of cast()'s finishing in double (0: one per hardware thread).
  void set_threads(int n) { threads_ = n < 0 ? 0 : n; }

  /// Rays that start on a surface (thickness, Lemasson et al. §3.2) meet their own face at |t| up
  /// to the bicubic tolerance (x size, over the cosine): the twin drops that hit after its exact
  /// step, the float pass cannot, so cast() sends such rays to the CPU (a fallback). With a guard
  /// g > 0 the pass ignores hits with t <= t_min + g instead (4 x tolerance x size covers a normal
  /// ray's own face), at the price of walls thinner than g. Default 0: the twin's answers.
  void set_near_guard(double g) { near_guard_ = g; }
  [[nodiscard]] double near_guard() const { return near_guard_; }

  /// Rays that start inside a closed solid (thickness) must leave it: with this set, a ray the pass
  /// finds no hit for is cast again by cast_ray (a fallback). The guard above, or a grazing hit on
  /// the face beside the ray's own at an edge, can hide from the float pass the hit the twin finds.
  void set_recast_misses(bool on) { recast_misses_ = on; }

  /// Walk steps after which the pass gives a ray up as cut (it then goes to the CPU); 0 = the
  /// guard 4 x nodes + 16, which only an endless walk reaches. Tests lower it to force the cut
  /// path that llvmpipe's loop limit takes on scenes of ~10^5 overlapping patches.
  void set_max_steps(int steps) { max_steps_ = steps; }

  /// Stated float allowances (model units), shared by the kernel and the tests: the noise floor of
  /// a float point on a ray with origin o (kUlps ulp of |o - centre| + radius()), and the radius.
  static constexpr double kUlps = 16.0;
  [[nodiscard]] double float_floor(const glm::dvec3& origin) const;
  [[nodiscard]] double radius() const { return radius_; }

 private:
  void upload_bvh();     ///< the scene's tree, as its node table
  void build_gpu_bvh();  ///< BvhBuild::Gpu
  std::vector<RawRayHit> pass(std::span<const nurbs::ray::Ray> rays, double t_min);
  /// The CPU finishing of one ray; counts a fallback.
  nurbs::ray::Hit finish(const nurbs::ray::Ray& ray, const RawRayHit& raw, double t_min, long long& fallbacks) const;

  gpgpu::Gpu& gpu_;
  const nurbs::ray::Scene& scene_;
  glm::dvec3 centre_{0.0};
  double radius_ = 0.0;
  gpgpu::Texture patches_, nodes_, cubics_, faces_;
  RaycastGpuStats stats_;
  BvhBuildStats build_stats_;
  std::vector<int> leaf_patch_;  ///< BvhBuild::Gpu: scene patch of the pass's leaf k (empty: the same)
  size_t rays_per_pass_ = size_t(1) << 20;
  double near_guard_ = 0.0;
  bool recast_misses_ = false;
  int threads_ = 0;  ///< set_threads
  int max_steps_ = 0;
};

}  // namespace queries
