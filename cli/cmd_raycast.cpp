// `nurbsgl raycast MODEL --rays FILE [--method bvh|dacrt] [--json]`: the nearest hit of every ray on
// the trimmed faces (Lemasson et al. §3: bicubic patches, BVH or DACRT, Newton ray/patch, trimming),
// moved onto the exact NURBS face in double.
#include <fmt/format.h>

#include <iterator>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/ray_engine.h"
#include "cli/validators.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"

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
  (void)nurbs::checked_model_size(model, a.model);
  // The reader's doubts (nurbs/model_report.h): a face with an invalid trim may hide or add a hit
  // anywhere; an edge gap widens where a hit near an edge lies.
  const double gap = loaded.report.largest_gap();
  const std::string doubt = loaded.report.invalid_trim_reason();
  if (!a.csv.empty()) check_output(a.csv, "--csv");
  const std::vector<nurbs::ray::Ray> rays = read_rays(a.rays, nurbs::coordinate_limit(nurbs::model_box(model)));
  RayEngine engine(model, a.engine, global);
  const std::vector<nurbs::ray::Hit> hits = engine.cast(rays, 0.0, "raycast");
  if (!a.csv.empty()) write_csv(a.csv, hits);
  long long hit_count = 0;
  for (const auto& h : hits) hit_count += h.face >= 0 ? 1 : 0;
  // Residual of the exact step (raycast_cpu.h): the hit point is on the face within it.
  const double bound = engine.scene().options.exact_residual * engine.scene().size + gap;
  const auto certify = [&] {
    require_certified(loaded.report, global);
    if (!doubt.empty()) throw CommandFailed("the hits are not certified: " + doubt);
  };

  if (a.json) {
    // One object per ray in input order, as distance gives one per point: the ray echoed, hit, and
    // for a hit t (along the unit direction), the face, (u, v), the point and t_bicubic (the hit on
    // the bicubic patches before the exact step, Fig. 13 accuracy).
    nlohmann::json results = nlohmann::json::array();
    for (size_t k = 0; k < (a.csv.empty() ? hits.size() : 0); ++k) {
      const auto& h = hits[k];
      const auto& r = rays[k];
      nlohmann::json one = {{"ray", k},
                            {"origin", {r.origin.x, r.origin.y, r.origin.z}},
                            {"direction", {r.direction.x, r.direction.y, r.direction.z}},
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
                        {"hits", hit_count},
                        {"seconds", engine.cast_seconds()},
                        {"hit_residual", bound}};
    if (a.csv.empty())
      j["results"] = std::move(results);  // moved, not copied: a result holds ~1 kB of JSON
    else
      j["results_file"] = a.csv;
    j.update(engine.figures());
    j["preset"] = a.preset.json();
    if (!doubt.empty()) j["uncertified"] = doubt;
    add_model_json(j, loaded.report, global);
    print_json(j);
    certify();
    return;
  }
  const nlohmann::json f = engine.figures();
  a.preset.print_text();
  fmt::print("model     {} ({} faces, {} bicubic patches)\n", a.model, engine.scene().faces.size(),
             engine.scene().patches.size());
  fmt::print("rays      {}  hits {}  misses {}\n", rays.size(), hit_count, (long long)rays.size() - hit_count);
  fmt::print("time      build {:.3f} s, cast {:.3f} s ({:.0f} rays/s, {} on the {})\n",
             f["seconds_build"].get<double>(), engine.cast_seconds(), f["rays_per_second"].get<double>(),
             method_used(a.engine), a.engine.device);
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
      "and (u, v); t = -1 and face = -1 for a miss. Hits are on the exact face within hit_residual.");
  cmd->add_option("MODEL", args->model, "Model file (.igs/.iges/.bpt)")->required();
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
