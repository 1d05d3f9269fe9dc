#pragma once
/// \file ray_caster.h
/// Ray casting of a model, as the CLI, the viewer and the experiments use it: the scene
/// built once (Lemasson et al. §3.1-3.2: bicubic patches, trims, BVH), then batches of rays cast
/// by the BVH or DACRT method on the CPU (double, every core; nurbs/raycast/) or by the fragment-
/// shader pass (raycast_gpu.h, BVH only), in chunks, with progress and the paper's figures (tests
/// per ray, Fig. 7; memory, Fig. 11).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/raycast/dacrt.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "queries/distance/mesh_distance.h"
#include "queries/raycast/raycast_gpu.h"

namespace queries {

/// Bvh and Dacrt: Lemasson et al. §3.2. Mesh (beyond the paper, CPU only): a guaranteed
/// tessellation within the bicubic tolerance, the slab around it that holds the faces
/// (queries/distance/mesh_distance.h, Embree's BVH); each ray's crossings of the slab's shells in
/// order, from each the same Newton step on the exact face and the same trim test, until the next
/// crossing lies beyond the nearest exact hit: that hit is the answer. A ray through one face's
/// slab meets the face an odd number of times when it leaves on the other side, an even number
/// (none, or a grazing pair) when it leaves on the side it entered: the first hit on the way
/// through is then sought from starts along it, and so is a long way inside a slab (a grazing
/// ray). A ray that starts inside slabs or tubes (MeshDistance::slabs_at) may meet their faces
/// before any crossing: each is searched from the start to its face's first crossing. A ray that
/// passes near a face's mesh boundary first, whose step at a crossing fails or lands far from it,
/// or that needs more than 8 crossings, is cast by the BVH method, beside the hits Newton finds
/// along its next crossings (near_boundaries).
enum class RayMethod { Bvh, Dacrt, Mesh };

/// The method's name as the command line and Python give it: "bvh", "dacrt" or "mesh".
[[nodiscard]] const char* method_name(RayMethod method);

/// Why the nearest hits of `method` are not certified, for people; empty for the mesh method. The
/// BVH and DACRT (on the CPU or the GPU) find a ray's candidates on the faces' bicubic
/// approximations (Lemasson et al. §3.1) and take the nearest exact hit Newton reaches from them: a
/// ray that grazes a face within the approximation's tolerance may cross the face where it passes
/// beside the approximation, and that hit is then missed (a hit behind it, or none, is answered).
/// The mesh method's slab holds the faces themselves (mesh_distance.h).
[[nodiscard]] std::string nearest_hits_doubt(RayMethod method);

struct RayCasterOptions {
  RayMethod method = RayMethod::Mesh;
  int threads = 0;                     ///< CPU threads, 0 = every hardware thread
  double tolerance = 1e-5;             ///< bicubic tolerance relative to the model size
  /// The bicubic tolerances the command line and Python accept.
  static constexpr double kMinTolerance = 1e-9, kMaxTolerance = 1e-2;
  /// RayMethod::Mesh: the guaranteed tessellation's eps relative to the model size. The mesh only
  /// finds where each ray meets the slab around it (the hits are the exact faces'): a coarser mesh
  /// is quicker to make, a finer one sends fewer rays near edges to the BVH. The command line and
  /// Python accept it within [kMinMeshTolerance, kMaxMeshTolerance].
  double mesh_tolerance = 1e-4;
  static constexpr double kMinMeshTolerance = 1e-6, kMaxMeshTolerance = 1e-2;
  nurbs::ray::DacrtOptions dacrt;      ///< DACRT's two brute-force thresholds (patches, rays)
  BvhBuild bvh_build = BvhBuild::Cpu;  ///< GPU path: the scene's BVH, or one built on the GPU (§3.2)
};

/// Totals over every cast so far.
struct RayCasterFigures {
  double build_seconds = 0.0, cast_seconds = 0.0;
  double gpu_seconds = 0.0, finish_seconds = 0.0;  ///< GPU: the passes, and the finishing in double
  double near_guard = 0.0;                         ///< see rays_start_on_surfaces
  double bvh_gpu_seconds = 0.0;                    ///< BvhBuild::Gpu: the build on the GPU (in build_seconds)
  int bvh_gpu_passes = 0;
  long long rays = 0, box_tests = 0, patch_tests = 0, fallbacks = 0;
  long long mesh_triangles = 0;  ///< RayMethod::Mesh: the mesh's triangles (fallbacks: rays cast by the BVH)
  size_t bytes_bvh = 0, bytes_patches = 0, bytes_trims = 0;  ///< GPU textures, or the CPU tables
};

class RayCaster {
 public:
  /// The CPU path when `gpu` is null, else the GPU pass (which must outlive this object; Mesh runs
  /// there as Bvh); the GPU tests trims on the §3.4 cubics, the CPU on the exact flattened loops.
  /// Throws std::invalid_argument for DACRT on the GPU.
  RayCaster(std::vector<nurbs::TrimmedSurface> faces, const RayCasterOptions& options, gpgpu::Gpu* gpu = nullptr);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Nearest hits (t > t_min) of every ray (unit directions), input order kept. `progress`
  /// (optional) is called with (rays done, rays) after every chunk. The CPU's BVH and mesh methods
  /// cast a batch of more than a chunk along a Morton curve of the rays' origins (64 cells an axis),
  /// whose neighbours share nodes, triangles and patches in the caches; no hit depends on the order.
  std::vector<nurbs::ray::Hit> cast(const std::vector<nurbs::ray::Ray>& rays, double t_min,
                                    const std::function<void(long long, long long)>& progress = {});

  /// For rays that start on the surface (thickness): the GPU pass ignores hits within 4 x the
  /// bicubic tolerance of the origin (its own face; raycast_gpu.h), else every such ray would go
  /// back to the CPU; a ray it finds no hit for is cast again on the CPU (a ray from inside a solid
  /// must leave it: a grazing hit at an edge can hide from the float pass). Walls thinner than the
  /// guard are not seen on the GPU where a farther hit exists. No effect on the CPU.
  void rays_start_on_surfaces();

  [[nodiscard]] const nurbs::ray::Scene& scene() const { return scene_; }
  [[nodiscard]] bool on_gpu() const { return gpu_caster_ != nullptr; }
  /// The method cast: the options' method, the BVH for the mesh method on the GPU.
  [[nodiscard]] RayMethod method() const { return gpu_caster_ ? RayMethod::Bvh : options_.method; }
  [[nodiscard]] const RayCasterFigures& figures() const { return figures_; }

 private:
  RayCasterOptions options_;
  nurbs::ray::Scene scene_;
  std::unique_ptr<GpuRaycaster> gpu_caster_;
  std::unique_ptr<MeshDistance> mesh_;  ///< RayMethod::Mesh
  /// RayMethod::Mesh: the rays of `chunk` cast through the mesh, the BVH for the rest.
  std::vector<nurbs::ray::Hit> cast_mesh(const std::vector<nurbs::ray::Ray>& chunk, double t_min, int threads);
  /// RayMethod::Mesh: a stretch of a ray inside one face's slab, from t = begin to end; `uv` is
  /// where the ray meets the slab at t = at, `to_uv` (optional) where it meets it at `end`.
  struct OnWay {
    int face;
    double begin, end;
    glm::dvec2 uv;
    double at;
    const glm::dvec2* to_uv;
  };
  /// RayMethod::Mesh: the first material hit on the way's face within it, by Newton from starts
  /// along it (between uv and to_uv, and along the ray's (u, v) rate from uv); none: face -1.
  nurbs::ray::Hit first_on_way(const OnWay& way, const nurbs::ray::Ray& ray, const nurbs::ray::RayPlanes& planes,
                               double t_min, double slack) const;
  /// RayMethod::Mesh: from the ray's first tube or ball `b` on, the crossings up to the nearest hit
  /// found (at most 32): the nearest material hit Newton finds near the mesh edges the ray passes,
  /// in the slabs it enters, in those it reaches by a tube, and in `from_start` (slabs that hold the
  /// ray's start, each to its face's first crossing) (face -1: none), beside the BVH's answer.
  nurbs::ray::Hit near_boundaries(MeshRayHit b, const nurbs::ray::Ray& ray, const nurbs::ray::RayPlanes& planes,
                                  double t_min, double step, const std::vector<OnWay>& from_start) const;
  /// RayMethod::Mesh: the exact step on `face` from `uv` (the scene's iterations), when it lands on
  /// a material point with t in [lo, hi] and after t_min, as earliest gives it; face -1 otherwise.
  nurbs::ray::Hit step_within(int face, glm::dvec2 uv, double lo, double hi, const nurbs::ray::Ray& ray,
                              const nurbs::ray::RayPlanes& planes, double t_min, double t_crossing) const;
  /// `found` (an exact material hit on `face`, or none: ok false) or the first of a grazing pair
  /// before it (Scene::look_back), as a hit; face -1 for none.
  nurbs::ray::Hit earliest(int face, const nurbs::ray::ExactHit& found, const nurbs::ray::Ray& ray,
                           const nurbs::ray::RayPlanes& planes, double t_min, double t_crossing) const;
  RayCasterFigures figures_;
};

}  // namespace queries
