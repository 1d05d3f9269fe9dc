// `nurbsgl raycast MODEL --rays FILE [--method mesh|bvh|dacrt] [--json]`: the nearest hit of every ray
// on the trimmed faces from the library's front door (queries/raycast/raycast_query.h: the certified
// mesh method, or Lemasson et al. §3's BVH or DACRT, whose nearest hits are not certified: exit 1).
#include <fmt/format.h>

#include <iterator>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/ray_engine.h"
#include "cli/validators.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "queries/raycast/raycast_query.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_raycast_impl {

struct RaycastArgs {
  std::string model, rays;
  RayEngineArgs engine;
  PaperPreset preset;  ///< --paper
  bool json = false;
  std::string csv;  ///< --csv: one row per ray, instead of the JSON's results
};

/// One row per ray (the fields of the JSON's results; numbers in their shortest exact form), written to a
/// temporary file and renamed.
void write_csv(const std::string& path, const std::vector<nurbs::ray::Hit>& hits) {
  write_rows(path, "ray,hit,t,face,u,v,x,y,z\n", hits.size(), [&](fmt::memory_buffer& buf, size_t k) {
    const nurbs::ray::Hit& h = hits[k];
    if (h.face >= 0)
      fmt::format_to(std::back_inserter(buf), "{},true,{},{},{},{},{},{},{}\n", k, h.t, h.face, h.uv.x, h.uv.y,
                     h.point.x, h.point.y, h.point.z);
    else
      fmt::format_to(std::back_inserter(buf), "{},false,,-1,,,,,\n", k);
  });
}

void run(const GlobalOptions& global, const RaycastArgs& a) {
  const LoadedModel loaded = load_model(a.model, "raycast");
  const nurbs::Model& model = loaded.model;
  (void)nurbs::checked_model_size(model, a.model);  // before the rays' coordinate limit is taken from its box
  if (!a.csv.empty()) check_output(a.csv, "--csv");
  const std::vector<nurbs::ray::Ray> rays = read_rays(a.rays, nurbs::coordinate_limit(nurbs::model_box(model)));
  queries::RaycastOptions o;
  o.caster = caster_options(a.engine);
  o.gpu = a.engine.device == "gpu";
  o.accept_partial = global.accept_partial;
  std::optional<Progress> progress(std::in_place, "raycast", "rays");
  o.progress = [&](long long done, long long total) { progress->update(done, total); };
  std::unique_ptr<gpgpu::Gpu> gpu = o.gpu ? start_gpu(global) : nullptr;
  const queries::Raycast r = queries::raycast(loaded, rays, 0.0, o, gpu.get());
  progress.reset();
  const std::vector<nurbs::ray::Hit>& hits = r.hits;
  if (!a.csv.empty()) write_csv(a.csv, hits);
  const nlohmann::json f =
      ray_figures_json(r.figures, a.engine, gpu.get(), r.scene_faces, r.scene_patches, r.scene_size, r.peak_memory);
  const auto certify = [&] {
    if (gpu) report_profile(*gpu, global);
    if (const std::string why = r.failure(); !why.empty()) throw CommandFailed(why);
  };

  if (a.json) {
    // One object per ray in input order, as distance gives one per point: the ray echoed, hit, and
    // for a hit t (along the unit direction), the face, (u, v), the point and t_bicubic (the hit on
    // the bicubic patches before the exact step, Fig. 13 accuracy).
    nlohmann::json results = nlohmann::json::array();
    for (size_t k = 0; k < (a.csv.empty() ? hits.size() : 0); ++k) {
      const auto& h = hits[k];
      const auto& ray = rays[k];
      nlohmann::json one = {{"ray", k},
                            {"origin", {ray.origin.x, ray.origin.y, ray.origin.z}},
                            {"direction", {ray.direction.x, ray.direction.y, ray.direction.z}},
                            {"hit", h.face >= 0}};
      if (h.face >= 0) {
        one["t"] = h.t, one["t_bicubic"] = h.t_bicubic, one["face"] = h.face;
        one["uv"] = {h.uv.x, h.uv.y}, one["point"] = {h.point.x, h.point.y, h.point.z};
      } else {
        one["t"] = nullptr, one["face"] = -1;
      }
      results.push_back(one);
    }
    nlohmann::json j = {{"model", a.model},
                        {"rays", rays.size()},
                        {"hits", r.hit_count},
                        {"seconds", r.figures.cast_seconds},
                        {"hit_residual", r.hit_residual}};
    if (a.csv.empty())
      j["results"] = std::move(results);  // moved, not copied: a result holds ~1 kB of JSON
    else
      j["results_file"] = a.csv;
    j.update(f);
    j["preset"] = a.preset.json();
    if (const std::string why = r.doubt(); !why.empty()) j["uncertified"] = why;
    add_model_json(j, loaded.report, global);
    print_json(j);
    certify();
    return;
  }
  a.preset.print_text();
  fmt::print("model     {} ({} faces, {} bicubic patches)\n", a.model, r.scene_faces, r.scene_patches);
  fmt::print("rays      {}  hits {}  misses {}\n", rays.size(), r.hit_count, (long long)rays.size() - r.hit_count);
  fmt::print("time      build {:.3f} s, cast {:.3f} s ({:.0f} rays/s, {} on the {})\n",
             f["seconds_build"].get<double>(), r.figures.cast_seconds, f["rays_per_second"].get<double>(),
             queries::method_name(r.method), a.engine.device);
  if (a.engine.bvh_build == "gpu")
    fmt::print("bvh       built on the gpu: {} passes, {:.3f} s\n", f["gpu"]["bvh_build_gpu_passes"].get<int>(),
               f["gpu"]["bvh_build_gpu_seconds"].get<double>());
  fmt::print("tests     {:.1f} boxes and {:.1f} patches per ray\n", f["tests_per_ray"]["box"].get<double>(),
             f["tests_per_ray"]["patch"].get<double>());
  const size_t shown = a.csv.empty() ? std::min<size_t>(hits.size(), 20) : 0;
  fmt::print("{:>8} {:>14} {:>6} {:>12} {:>12}\n", "ray", "t", "face", "u", "v");
  for (size_t i = 0; i < shown; ++i) {
    const auto& h = hits[i];
    if (h.face < 0)
      fmt::print("{:>8} {:>14} {:>6}\n", i, "miss", -1);
    else
      fmt::print("{:>8} {:>14.9g} {:>6} {:>12.6g} {:>12.6g}\n", i, h.t, h.face, h.uv.x, h.uv.y);
  }
  if (!a.csv.empty())
    fmt::print("hits      written to {}\n", a.csv);
  else if (shown < hits.size())
    fmt::print("... {} more (--json or --csv lists all)\n", hits.size() - shown);
  certify();
}

}  // namespace cmd_raycast_impl

void add_raycast(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_raycast_impl;
  auto args = std::make_shared<RaycastArgs>();
  CLI::App* cmd = app.add_subcommand(
      "raycast",
      "Nearest hit of each ray on the model's trimmed faces (Lemasson et al.): t along the unit direction, face "
      "and (u, v); t = -1 and face = -1 for a miss. Hits are on the exact face within hit_residual; the mesh method "
      "certifies the nearest hits, the BVH and DACRT do not (exit 1).");
  cmd->add_option("MODEL", args->model, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option("--rays", args->rays, "ray file: 'ox oy oz dx dy dz' per line (spaces or commas, '-' for stdin)")
      ->required();
  add_ray_engine_options(cmd, args->engine, args->preset);
  cmd->add_flag("--json", args->json, "JSON: rays, seconds, t, face, uv (input order), and the figures");
  cmd->add_option("--csv", args->csv,
                  "Write one row per ray (ray, hit, t, face, u, v, x, y, z) as CSV; the JSON then names the file "
                  "(results_file) instead of listing the results")
      ->check(extension_is(".csv"));
  cmd->callback([&global, args] {
    args->preset.apply();
    run(global, *args);
  });
}

}  // namespace cli
