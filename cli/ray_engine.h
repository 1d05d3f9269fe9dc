#pragma once
/// \file ray_engine.h
/// What `raycast` and `thickness` share: the ray file reader, the options that choose how rays are
/// cast (--method bvh|dacrt, --threads) and the engine that builds the scene of a model and casts
/// rays through it with progress on stderr.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/common.h"
#include "nurbs/model.h"
#include "nurbs/raycast/raycast_cpu.h"

namespace cli {

/// Rays from a text file (or stdin for "-"): `ox oy oz dx dy dz` per line, separated by spaces,
/// tabs or commas; blank lines and lines starting with '#' are skipped. Directions are normalised.
/// Throws BadInput naming the file and line for a malformed line or a zero direction.
[[nodiscard]] std::vector<nurbs::ray::Ray> read_rays(const std::string& path);

struct RayEngineArgs {
  std::string method = "bvh";  ///< bvh: Morton BVH, stackless traversal; dacrt: divide and conquer
  int threads = 0;             ///< 0 = every hardware thread
  double tolerance = 1e-5;     ///< bicubic tolerance relative to the model size
};
void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args);

/// Builds the scene once (bicubic patches, trims, BVH) and casts batches of rays.
class RayEngine {
 public:
  RayEngine(const nurbs::Model& model, const RayEngineArgs& args);
  /// Nearest hits (t > t_min) of every ray; `what` names the work in the progress line.
  std::vector<nurbs::ray::Hit> cast(const std::vector<nurbs::ray::Ray>& rays, double t_min, const char* what);
  [[nodiscard]] const nurbs::ray::Scene& scene() const { return scene_; }
  /// Figures: build and cast seconds, rays, tests per ray (the paper's Fig. 7), memory (Fig. 11).
  [[nodiscard]] nlohmann::json figures() const;
  [[nodiscard]] double cast_seconds() const { return cast_seconds_; }
  [[nodiscard]] long long rays_cast() const { return rays_; }

 private:
  RayEngineArgs args_;
  nurbs::ray::Scene scene_;
  double build_seconds_ = 0.0, cast_seconds_ = 0.0;
  long long rays_ = 0, box_tests_ = 0, patch_tests_ = 0;
};

}  // namespace cli
