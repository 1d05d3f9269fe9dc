#include "cli/ray_engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <iostream>
#include <sstream>
#include <thread>

#include "cli/validators.h"
#include "nurbs/model_ops.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace ray_engine_impl {

std::vector<nurbs::ray::Ray> parse_rays(std::istream& in, const std::string& name, double limit) {
  std::vector<nurbs::ray::Ray> rays;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::replace(line.begin(), line.end(), '\t', ' ');
    const size_t first = line.find_first_not_of(" \r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[6];
    int n = 0;
    std::string word;
    while (fields >> word) {
      size_t used = 0;
      double x = 0.0;
      try {
        x = std::stod(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || !std::isfinite(x))
        throw BadInput(fmt::format("{}: line {}: '{}' is not a finite number", name, number, word));
      if (n == 6) throw BadInput(fmt::format("{}: line {}: more than 6 numbers (ox oy oz dx dy dz)", name, number));
      v[n++] = x;
    }
    if (n != 6) throw BadInput(fmt::format("{}: line {}: {} numbers, expected 6 (ox oy oz dx dy dz)", name, number, n));
    const glm::dvec3 origin(v[0], v[1], v[2]);
    if (!nurbs::within_coordinate_limit(origin, limit))
      throw BadInput(fmt::format("{}: line {}: the origin ({}, {}, {}) lies beyond {:.3g}, the coordinates double "
                                 "arithmetic carries for this model",
                                 name, number, v[0], v[1], v[2], limit));
    // Scaled by its largest component first: a length of 1e200-sized components would overflow.
    const double largest = std::max({std::abs(v[3]), std::abs(v[4]), std::abs(v[5])});
    const glm::dvec3 d = largest > 0.0 ? glm::dvec3(v[3], v[4], v[5]) / largest : glm::dvec3(0.0);
    const double len = glm::length(d);
    if (!(len > 0.0) || !std::isfinite(len))
      throw BadInput(
          fmt::format("{}: line {}: the direction ({}, {}, {}) has no length", name, number, v[3], v[4], v[5]));
    rays.push_back({origin, d / len});
  }
  if (rays.empty()) throw BadInput(fmt::format("--rays {}: no rays in the file", name));
  return rays;
}

}  // namespace ray_engine_impl

std::vector<nurbs::ray::Ray> read_rays(const std::string& path, double coordinate_limit) {
  using namespace ray_engine_impl;
  std::istringstream in(read_input_text(path, "--rays"));
  return parse_rays(in, path == "-" ? "stdin" : path, coordinate_limit);
}

void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args) {
  using namespace ray_engine_impl;
  cmd->add_option("--method", args.method,
                  "bvh: Morton BVH with stackless traversal (Lemasson et al. §3.2); dacrt: divide-and-conquer "
                  "ray tracing without a kept structure (§3.2)")
      ->check(CLI::IsMember({"bvh", "dacrt"}))
      ->capture_default_str();
  cmd->add_option("--device", args.device,
                  "cpu: the double-precision path on every core; gpu: the fragment-shader pass (Lemasson et al. "
                  "§3.2-3.4 in float), hits finished in double on the CPU (bvh only)")
      ->check(CLI::IsMember({"cpu", "gpu"}))
      ->capture_default_str();
  cmd->add_option("--bvh-build", args.bvh_build,
                  "--device gpu: build the Morton BVH on the cpu, or on the gpu in fragment passes (Morton codes, "
                  "bitonic sort, Karras' nodes: Lemasson et al. §3.2)")
      ->check(CLI::IsMember({"cpu", "gpu"}))
      ->capture_default_str();
  cmd->add_option("--threads", args.threads, "CPU threads (0: all)")->check(CLI::Range(0, 1024));
  cmd->add_option("--dacrt-patches", args.dacrt_patches,
                  "dacrt: test every ray against every patch once a patch set is this small (Figs. 8-9)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  cmd->add_option("--dacrt-rays", args.dacrt_rays, "dacrt: ... or once a ray set is this small")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  cmd->add_option("--tolerance", args.tolerance,
                  "bicubic approximation tolerance, relative to the model size (hits are then moved onto the "
                  "exact face)")
      ->check(finite_range(1e-9, 1e-2))
      ->capture_default_str();
}

RayEngine::RayEngine(const nurbs::Model& model, const RayEngineArgs& args, const GlobalOptions& global)
    : args_(args), global_(global) {
  const bool gpu = args.device == "gpu";
  if (gpu && args.method != "bvh") throw BadInput("--device gpu: only --method bvh runs on the GPU");
  if (!gpu && args.bvh_build == "gpu") throw BadInput("--bvh-build gpu needs --device gpu");
  if (gpu) gpu_ = start_gpu(global);
  queries::RayCasterOptions o;
  o.method = args.method == "dacrt" ? queries::RayMethod::Dacrt : queries::RayMethod::Bvh;
  o.threads = args.threads;
  o.tolerance = args.tolerance;
  o.dacrt.patch_leaf = args.dacrt_patches;
  o.dacrt.ray_leaf = args.dacrt_rays;
  o.bvh_build = args.bvh_build == "gpu" ? queries::BvhBuild::Gpu : queries::BvhBuild::Cpu;
  caster_ = std::make_unique<queries::RayCaster>(nurbs::world_faces(model), o, gpu_.get());
}

RayEngine::~RayEngine() {
  using namespace ray_engine_impl;
  caster_.reset();  // its textures before the context
  if (gpu_) report_profile(*gpu_, global_);
}

std::vector<nurbs::ray::Hit> RayEngine::cast(const std::vector<nurbs::ray::Ray>& rays, double t_min, const char* what) {
  using namespace ray_engine_impl;
  Progress progress(what, "rays");
  return caster_->cast(rays, t_min, [&](long long done, long long total) { progress.update(done, total); });
}

nlohmann::json RayEngine::figures() const {
  const queries::RayCasterFigures& f = caster_->figures();
  const double per_ray = f.rays > 0 ? 1.0 / double(f.rays) : 0.0;
  nlohmann::json gpu = nullptr;
  if (gpu_)
    gpu = {{"renderer", gpu_->info().renderer},
           {"gpu_seconds", f.gpu_seconds},
           {"cpu_seconds", f.finish_seconds},
           {"fallbacks", f.fallbacks},
           {"near_guard", f.near_guard},
           {"bvh_build", args_.bvh_build},
           {"bvh_build_gpu_seconds", f.bvh_gpu_seconds},
           {"bvh_build_gpu_passes", f.bvh_gpu_passes}};
  nlohmann::json dacrt = nullptr;
  if (args_.method == "dacrt") dacrt = {{"patch_leaf", args_.dacrt_patches}, {"ray_leaf", args_.dacrt_rays}};
  return {{"method", args_.method},
          {"dacrt", dacrt},
          {"device", args_.device},
          {"gpu", gpu},
          {"threads", args_.threads > 0 ? args_.threads : int(std::thread::hardware_concurrency())},
          {"faces", scene().faces.size()},
          {"patches", scene().patches.size()},
          {"bicubic_tolerance", args_.tolerance * scene().size},
          {"seconds_build", f.build_seconds},
          {"seconds_cast", f.cast_seconds},
          {"rays_per_second", f.cast_seconds > 0 ? double(f.rays) / f.cast_seconds : 0.0},
          {"tests_per_ray", {{"box", double(f.box_tests) * per_ray}, {"patch", double(f.patch_tests) * per_ray}}},
          {"memory_bytes", {{"bvh", f.bytes_bvh}, {"patches", f.bytes_patches}, {"trims", f.bytes_trims}}}};
}

}  // namespace cli
