#include "cli/ray_engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <iostream>
#include <sstream>

#include "cli/validators.h"
#include "nurbs/io/query_text.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/system_memory.h"
#include "queries/raycast/thickness_map.h"

namespace cli {

std::vector<nurbs::ray::Ray> read_rays(const std::string& path, double coordinate_limit) {
  std::vector<nurbs::ray::Ray> rays;
  for (const auto& r :
       nurbs::io::parse_rays(read_input_text(path, "--rays"), path == "-" ? "stdin" : path, coordinate_limit))
    rays.push_back({r.origin, r.direction});
  return rays;
}

void add_ray_engine_options(CLI::App* cmd, RayEngineArgs& args, PaperPreset& preset) {
  auto* method =
      cmd->add_option("--method", args.method,
                      "bvh: Morton BVH with stackless traversal (Lemasson et al. §3.2); dacrt: divide-and-conquer "
                      "ray tracing without a kept structure (§3.2); mesh: each ray's crossings of the slab around a "
                      "guaranteed tessellation within --mesh-tolerance from Embree's BVH, then the same Newton step "
                      "on the exact face and trim test (beyond the paper; the BVH for the rays it cannot finish); "
                      "auto: mesh on the cpu, bvh on the gpu")
          ->check(CLI::IsMember({"auto", "mesh", "bvh", "dacrt"}))
          ->capture_default_str();
  auto* device =
      cmd->add_option("--engine,--device", args.device,
                      "cpu: the double-precision path on every core; gpu: the fragment-shader pass (Lemasson et al. "
                      "§3.2-3.4 in float), hits finished in double on the CPU (bvh only). --device is another name of "
                      "--engine, the switch's name on every command")
          ->check(CLI::IsMember({"cpu", "gpu"}))
          ->capture_default_str();
  auto* bvh_build =
      cmd->add_option("--bvh-build", args.bvh_build,
                      "--engine gpu: build the Morton BVH on the cpu, or on the gpu in fragment passes (Morton codes, "
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
      ->check(finite_range(queries::RayCasterOptions::kMinTolerance, queries::RayCasterOptions::kMaxTolerance))
      ->capture_default_str();
  cmd->add_option("--mesh-tolerance", args.mesh_tolerance,
                  "mesh: the guaranteed tessellation's eps, relative to the model size. The hits are the exact "
                  "faces' whatever it is; a finer mesh takes longer to build and sends fewer rays that pass near "
                  "the faces' edges to the BVH: for batches of millions of rays")
      ->check(finite_range(queries::RayCasterOptions::kMinMeshTolerance, queries::RayCasterOptions::kMaxMeshTolerance))
      ->capture_default_str();
  // --paper: the BVH method on the GPU (3.2: the faster and more accurate of the paper's two GPU
  // methods; DACRT has no GPU pass here), its tree built there from Morton keys (3.2).
  preset.add_flag(cmd, "Lemasson et al.");
  const queries::ThicknessMapOptions paper = queries::ThicknessMapOptions{}.paper();
  const auto section = [](const char* option) {
    return nurbs::paper_section(queries::ThicknessMapOptions::paper_switches(), option);
  };
  preset.govern(method, args.method, std::string(paper.caster.method == queries::RayMethod::Bvh ? "bvh" : "dacrt"),
                section("method"));
  preset.govern(device, args.device, std::string(paper.gpu ? "gpu" : "cpu"), section("engine"));
  preset.govern(bvh_build, args.bvh_build, std::string(paper.caster.bvh_build == queries::BvhBuild::Gpu ? "gpu" : "cpu"),
                section("bvh-build"));
}

queries::RayCasterOptions caster_options(const RayEngineArgs& args) {
  queries::RayCasterOptions o;
  o.method = args.method == "dacrt"                                     ? queries::RayMethod::Dacrt
             : args.method == "bvh" || (args.method == "auto" && args.device == "gpu") ? queries::RayMethod::Bvh
                                                                                        : queries::RayMethod::Mesh;
  o.threads = args.threads;
  o.tolerance = args.tolerance;
  o.mesh_tolerance = args.mesh_tolerance;
  o.dacrt.patch_leaf = args.dacrt_patches;
  o.dacrt.ray_leaf = args.dacrt_rays;
  o.bvh_build = args.bvh_build == "gpu" ? queries::BvhBuild::Gpu : queries::BvhBuild::Cpu;
  return o;
}

std::string method_used(const RayEngineArgs& args) {
  return queries::method_name(caster_options(args).method);
}

nlohmann::json ray_figures_json(const queries::RayCasterFigures& f, const RayEngineArgs& args, const gpgpu::Gpu* gpu,
                                size_t faces, size_t patches, double size, long long peak_memory) {
  const double per_ray = f.rays > 0 ? 1.0 / double(f.rays) : 0.0;
  nlohmann::json g = nullptr;
  if (gpu)
    g = {{"renderer", gpu->info().renderer},
         {"gpu_seconds", f.gpu_seconds},
         {"cpu_seconds", f.finish_seconds},
         {"fallbacks", f.fallbacks},
         {"near_guard", f.near_guard},
         {"bvh_build", args.bvh_build},
         {"bvh_build_gpu_seconds", f.bvh_gpu_seconds},
         {"bvh_build_gpu_passes", f.bvh_gpu_passes}};
  nlohmann::json dacrt = nullptr;
  if (args.method == "dacrt") dacrt = {{"patch_leaf", args.dacrt_patches}, {"ray_leaf", args.dacrt_rays}};
  return {{"method", method_used(args)},
          {"mesh_triangles", f.mesh_triangles},
          {"mesh_tolerance", method_used(args) == "mesh" ? nlohmann::json(args.mesh_tolerance) : nlohmann::json()},
          {"fallbacks", f.fallbacks},
          {"dacrt", dacrt},
          {"engine", args.device},
          {"device", args.device},  // the engine under the switch's other name
          {"gpu", g},
          {"threads", nurbs::thread_count(args.threads)},
          {"faces", faces},
          {"patches", patches},
          {"bicubic_tolerance", args.tolerance * size},
          {"seconds_build", f.build_seconds},
          {"seconds_cast", f.cast_seconds},
          {"rays_per_second", f.cast_seconds > 0 ? double(f.rays) / f.cast_seconds : 0.0},
          {"tests_per_ray", {{"box", double(f.box_tests) * per_ray}, {"patch", double(f.patch_tests) * per_ray}}},
          {"memory_bytes",
           {{"bvh", f.bytes_bvh}, {"patches", f.bytes_patches}, {"trims", f.bytes_trims}, {"process_peak", peak_memory}}}};
}

}  // namespace cli
