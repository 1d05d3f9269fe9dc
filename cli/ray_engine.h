#pragma once
/// \file ray_engine.h
/// What `raycast` and `thickness` share: the ray file reader, the options that choose how rays are
/// cast (--method bvh|dacrt, --threads) and the engine that builds the scene of a model and casts
/// rays through it with progress on stderr.
#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/common.h"
#include "nurbs/model.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "queries/raycast_gpu.h"

namespace cli {

/// Rays from a text file (or stdin for "-"): `ox oy oz dx dy dz` per line, separated by spaces,
/// tabs or commas; blank lines and lines starting with '#' are skipped. Directions are normalised.
/// Throws BadInput naming the file and line for a malformed line or a zero direction.
[[nodiscard]] std::vector<nurbs::ray::Ray> read_rays(const std::string& path);

struct RayEngineArgs {
  std::string method = "bvh";  ///< bvh: Morton BVH, stackless traversal; dacrt: divide and conquer
  std::string device = "cpu";  ///< cpu: the double-precision path; gpu: the fragment-shader pass (bvh only)
  int threads = 0;             ///< 0 = every hardware thread
  double tolerance = 1e-5;     ///< bicubic tolerance relative to the model size
};
void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args);

/// Builds the scene once (bicubic patches, trims, BVH) and casts batches of rays.
class RayEngine {
 public:
  /// With device gpu, starts the GPU (exit 3 when none starts) and uploads the scene.
  RayEngine(const nurbs::Model& model, const RayEngineArgs& args, const GlobalOptions& global);
  ~RayEngine();
  /// Nearest hits (t > t_min) of every ray; `what` names the work in the progress line.
  std::vector<nurbs::ray::Hit> cast(const std::vector<nurbs::ray::Ray>& rays, double t_min, const char* what);
  [[nodiscard]] const nurbs::ray::Scene& scene() const { return scene_; }
  /// For rays that start on the surface (thickness): the GPU pass ignores hits within 4 x the
  /// bicubic tolerance of the origin (its own face; raycast_gpu.h), else every such ray would go
  /// back to the CPU. Walls thinner than that guard are not seen on the GPU. No effect on the CPU.
  void rays_start_on_surfaces();
  /// Figures: build and cast seconds, rays, tests per ray (the paper's Fig. 7), memory (Fig. 11).
  [[nodiscard]] nlohmann::json figures() const;
  [[nodiscard]] double cast_seconds() const { return cast_seconds_; }
  [[nodiscard]] long long rays_cast() const { return rays_; }

 private:
  RayEngineArgs args_;
  const GlobalOptions& global_;
  nurbs::ray::Scene scene_;
  std::unique_ptr<gpgpu::Gpu> gpu_;
  std::unique_ptr<queries::GpuRaycaster> gpu_caster_;
  double build_seconds_ = 0.0, cast_seconds_ = 0.0, near_guard_ = 0.0;
  double gpu_seconds_ = 0.0, finish_seconds_ = 0.0;  ///< GPU: the passes, and the CPU finishing
  long long rays_ = 0, box_tests_ = 0, patch_tests_ = 0, fallbacks_ = 0;
};

}  // namespace cli
