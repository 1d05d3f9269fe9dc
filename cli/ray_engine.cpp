#include "cli/ray_engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <iostream>
#include <sstream>
#include <thread>

#include "nurbs/model_ops.h"
#include "nurbs/raycast/dacrt.h"
#include "nurbs/raycast/thickness.h"

namespace cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::vector<nurbs::ray::Ray> parse_rays(std::istream& in, const std::string& name) {
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
    const glm::dvec3 d(v[3], v[4], v[5]);
    const double len = glm::length(d);
    if (!(len > 0.0) || !std::isfinite(len))
      throw BadInput(
          fmt::format("{}: line {}: the direction ({}, {}, {}) has no length", name, number, v[3], v[4], v[5]));
    rays.push_back({{v[0], v[1], v[2]}, d / len});
  }
  return rays;
}

}  // namespace

std::vector<nurbs::ray::Ray> read_rays(const std::string& path) {
  if (path == "-") return parse_rays(std::cin, "stdin");
  std::ifstream in(path);
  if (!in) throw BadInput(fmt::format("{}: cannot open the ray file", path));
  return parse_rays(in, path);
}

void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args) {
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
  cmd->add_option("--threads", args.threads, "CPU threads (0: all)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--tolerance", args.tolerance,
                  "bicubic approximation tolerance, relative to the model size (hits are then moved onto the "
                  "exact face)")
      ->check(CLI::Range(1e-9, 1e-2))
      ->capture_default_str();
}

RayEngine::RayEngine(const nurbs::Model& model, const RayEngineArgs& args, const GlobalOptions& global)
    : args_(args), global_(global) {
  const bool gpu = args.device == "gpu";
  if (gpu && args.method != "bvh") throw BadInput("--device gpu: only --method bvh runs on the GPU");
  const auto start = std::chrono::steady_clock::now();
  nurbs::ray::SceneOptions o;
  o.tolerance = args.tolerance;
  // The GPU pass tests trims on the §3.4 cubics; the CPU path on the exact flattened loops.
  if (gpu) o.trim = nurbs::ray::SceneOptions::Trim::Cubics;
  scene_ = nurbs::ray::build_scene(nurbs::world_faces(model), o);
  if (gpu) {
    gpu_ = start_gpu(global);
    gpu_caster_ = std::make_unique<queries::GpuRaycaster>(*gpu_, scene_);
  }
  build_seconds_ = seconds_since(start);
}

void RayEngine::rays_start_on_surfaces() {
  if (!gpu_caster_) return;
  near_guard_ = 4.0 * args_.tolerance * scene_.size;
  gpu_caster_->set_near_guard(near_guard_);
}

RayEngine::~RayEngine() {
  gpu_caster_.reset();  // its textures before the context
  if (gpu_) report_profile(*gpu_, global_);
}

std::vector<nurbs::ray::Hit> RayEngine::cast(const std::vector<nurbs::ray::Ray>& rays, double t_min, const char* what) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<nurbs::ray::Hit> out;
  out.reserve(rays.size());
  Progress progress(what, "rays");
  const size_t kChunk = gpu_caster_ ? gpu_caster_->rays_per_pass() : size_t(1) << 14;
  const int threads = std::max(1, args_.threads > 0 ? args_.threads : int(std::thread::hardware_concurrency()));
  for (size_t first = 0; first < rays.size(); first += kChunk) {
    const std::vector<nurbs::ray::Ray> chunk(rays.begin() + long(first),
                                             rays.begin() + long(std::min(rays.size(), first + kChunk)));
    std::vector<nurbs::ray::Hit> hits;
    if (gpu_caster_) {
      hits = gpu_caster_->cast(chunk, t_min);
      const queries::RaycastGpuStats& g = gpu_caster_->stats();  // of this cast
      box_tests_ += g.box_tests;
      patch_tests_ += g.patch_tests;
      gpu_seconds_ += g.gpu_seconds;
      finish_seconds_ += g.cpu_seconds;
      fallbacks_ += g.fallbacks;
    } else if (args_.method == "dacrt") {
      // DACRT keeps no structure: each thread takes a contiguous part of the rays.
      std::vector<std::vector<nurbs::ray::Hit>> parts(static_cast<size_t>(threads));
      std::vector<nurbs::ray::DacrtStats> stats(static_cast<size_t>(threads));
      std::vector<std::thread> pool;
      const size_t per = (chunk.size() + size_t(threads) - 1) / size_t(threads);
      for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
          const size_t a = std::min(chunk.size(), size_t(t) * per), b = std::min(chunk.size(), a + per);
          const std::vector<nurbs::ray::Ray> part(chunk.begin() + long(a), chunk.begin() + long(b));
          parts[size_t(t)] = nurbs::ray::cast_rays_dacrt(scene_, part, t_min, {}, &stats[size_t(t)]);
        });
      for (auto& t : pool) t.join();
      for (int t = 0; t < threads; ++t) {
        hits.insert(hits.end(), parts[size_t(t)].begin(), parts[size_t(t)].end());
        box_tests_ += stats[size_t(t)].box_tests;
        patch_tests_ += stats[size_t(t)].patch_tests;
      }
    } else {
      nurbs::ray::TraversalStats stats;
      hits = nurbs::ray::cast_rays_parallel(scene_, chunk, t_min, nurbs::ray::Traversal::Stackless, threads, &stats);
      box_tests_ += stats.box_tests;
      patch_tests_ += stats.patch_tests;
    }
    out.insert(out.end(), hits.begin(), hits.end());
    progress.update(static_cast<long long>(out.size()), static_cast<long long>(rays.size()));
  }
  rays_ += static_cast<long long>(rays.size());
  cast_seconds_ += seconds_since(start);
  return out;
}

nlohmann::json RayEngine::figures() const {
  size_t trim_bytes = 0;
  for (const auto& t : scene_.trims)
    for (const auto& l : t.loops) trim_bytes += l.size() * sizeof(glm::dvec2);
  for (const auto& c : scene_.cubics) trim_bytes += c.cubics.size() * sizeof(nurbs::ray::TrimCubic);
  const double per_ray = rays_ > 0 ? 1.0 / double(rays_) : 0.0;
  nlohmann::json gpu = nullptr;
  if (gpu_caster_) {
    const queries::RaycastGpuStats& g = gpu_caster_->stats();
    gpu = {{"renderer", gpu_->info().renderer},
           {"gpu_seconds", gpu_seconds_},
           {"cpu_seconds", finish_seconds_},
           {"fallbacks", fallbacks_},
           {"near_guard", near_guard_},
           {"texture_bytes", {{"bvh", g.bytes_bvh}, {"patches", g.bytes_patches}, {"trims", g.bytes_trims}}}};
  }
  return {{"method", args_.method},
          {"device", args_.device},
          {"gpu", gpu},
          {"threads", args_.threads > 0 ? args_.threads : int(std::thread::hardware_concurrency())},
          {"faces", scene_.faces.size()},
          {"patches", scene_.patches.size()},
          {"bicubic_tolerance", args_.tolerance * scene_.size},
          {"seconds_build", build_seconds_},
          {"seconds_cast", cast_seconds_},
          {"rays_per_second", cast_seconds_ > 0 ? double(rays_) / cast_seconds_ : 0.0},
          {"tests_per_ray", {{"box", double(box_tests_) * per_ray}, {"patch", double(patch_tests_) * per_ray}}},
          {"memory_bytes",
           {{"bvh", args_.method == "bvh" ? scene_.bvh.nodes.size() * sizeof(nurbs::ray::BvhNode) : 0},
            {"patches", scene_.patches.size() * sizeof(nurbs::ray::BicubicPatch)},
            {"trims", trim_bytes}}}};
}

}  // namespace cli
