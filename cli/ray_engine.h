#pragma once
/// \file ray_engine.h
/// What `raycast` and `thickness` share: the ray file reader, the options that choose how rays are
/// cast (--method bvh|dacrt, --engine (also --device), --bvh-build, --threads; --paper sets the first three as
/// Lemasson et al.) and the caster's figures as JSON.
#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/common.h"
#include "cli/paper_preset.h"
#include "nurbs/model.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "queries/raycast/ray_caster.h"

namespace cli {

/// Rays from a text file (or stdin for "-"): `ox oy oz dx dy dz` per line, separated by spaces,
/// tabs or commas; blank lines and lines starting with '#' are skipped. Directions are normalised.
/// Throws BadInput naming the file when it cannot be read, and nurbs::io::ReadError (query_text.h)
/// naming the file and line for a malformed line, a zero direction or an origin coordinate of
/// magnitude above `coordinate_limit` (nurbs::coordinate_limit of the model), or a file without rays.
[[nodiscard]] std::vector<nurbs::ray::Ray> read_rays(const std::string& path, double coordinate_limit);

struct RayEngineArgs {
  std::string method = "auto";            ///< mesh (auto on the cpu), bvh (auto on the gpu): Morton BVH, stackless traversal; dacrt: divide and conquer
  std::string device = "cpu";             ///< --engine: cpu, the double-precision path; gpu, the fragment-shader pass (bvh only)
  std::string bvh_build = "cpu";          ///< --engine gpu: the BVH built on the cpu (build_scene) or the gpu
  int threads = 0;                        ///< 0 = every hardware thread
  double tolerance = 1e-5;                ///< bicubic tolerance relative to the model size
  /// mesh: the guaranteed tessellation's eps relative to the model size (RayCasterOptions)
  double mesh_tolerance = queries::RayCasterOptions{}.mesh_tolerance;
  int dacrt_patches = 8, dacrt_rays = 8;  ///< DACRT's brute-force thresholds
};
/// The options of RayEngineArgs on `cmd`, and --paper governing --method, --device and --bvh-build.
void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args, PaperPreset& preset);

/// The method the caster runs, as named on the command line: "mesh", "bvh" or "dacrt" (auto resolved).
[[nodiscard]] std::string method_used(const RayEngineArgs& args);

/// The caster's options as RayEngineArgs give them.
[[nodiscard]] queries::RayCasterOptions caster_options(const RayEngineArgs& args);

/// The figures of a caster as JSON: build and cast seconds, rays, tests per ray (the paper's Fig.
/// 7), memory (Fig. 11: the structures' bytes; process_peak, the process's peak resident bytes when
/// the last cast ended: reading, preparation and tracing, before any answer is written; for Fig.
/// 12). `gpu`: the GPU caster's context, else null.
[[nodiscard]] nlohmann::json ray_figures_json(const queries::RayCasterFigures& f, const RayEngineArgs& args,
                                              const gpgpu::Gpu* gpu, size_t faces, size_t patches, double size,
                                              long long peak_memory);

}  // namespace cli
