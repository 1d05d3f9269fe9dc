// `nurbsgl thickness MODEL [--samples N | --spacing S] [--min-wall T] [-o OUT.ply] [--csv F] [--exr DIR]`:
// wall thickness by ray casting (Lemasson et al.): from samples on every face a ray along the inward
// normal, the thickness is the distance to the nearest valid hit, through the library's front door
// queries::thickness_map (queries/raycast/thickness_map.h).
#include <fmt/format.h>

#include <filesystem>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/ball_json.h"
#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/ray_engine.h"
#include "cli/validators.h"
#include "gpgpu/exr_dump.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/output_file.h"
#include "queries/raycast/thickness_map.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_thickness_impl {

struct ThicknessArgs {
  std::string model, output, csv, exr;
  queries::ThicknessMapOptions map;
  bool samples_given = false, spacing_given = false, min_wall_given = false, json = false;
  RayEngineArgs engine;
  PaperPreset preset;  ///< --paper
  std::string ball_engine = "auto";
  std::string colour = "ray";
};

using Thickness = nurbs::ray::SampleThickness;

void write_csv(const std::string& path, const nurbs::ray::ThicknessSamples& s, const Thickness& th,
               const std::vector<nurbs::ray::Hit>& hits, const nurbs::ray::ThicknessRays& rays,
               const queries::BallMap* ball) {
  const std::string header =
      std::string("face,u,v,x,y,z,thickness,hit_face") + (ball ? ",ball_thickness,ball_bound" : "") + "\n";
  write_rows(path, header, rays.rays.size(), [&](fmt::memory_buffer& buf, size_t r) {
    const auto [f, k] = rays.source[r];
    const auto& g = s.faces[size_t(f)];
    const glm::dvec2 uv = g.uv[size_t(k)];
    const glm::dvec3 p = g.point[size_t(k)];
    fmt::format_to(std::back_inserter(buf), "{},{},{},{},{},{},{},{}", g.face, uv.x, uv.y, p.x, p.y, p.z,
                   th[size_t(f)][size_t(k)], hits[r].face);
    if (ball) fmt::format_to(std::back_inserter(buf), ",{},{:.3g}", ball->samples[r].thickness, ball->samples[r].bound);
    buf.push_back('\n');
  });
}

void write_exr_maps(const std::string& dir, const nurbs::ray::ThicknessSamples& s, const Thickness& th,
                    const char* what) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw BadInput(fmt::format("--exr: cannot create {}: {}", dir, ec.message()));
  for (size_t f = 0; f < s.faces.size(); ++f) {
    const auto& g = s.faces[f];
    gpgpu::ExrImage img{g.nu, g.nv, {"R"}, {}};
    img.values.assign(th[f].begin(), th[f].end());
    gpgpu::write_exr(std::filesystem::path(dir) / fmt::format("face_{:04d}_{}.exr", g.face, what), img);
  }
}

/// The JSON object of a map (the fields are a contract: README.md).
nlohmann::json map_json(const ThicknessArgs& a, const queries::ThicknessMap& m, const nlohmann::json& figures) {
  const long long n = static_cast<long long>(m.rays.rays.size());
  nlohmann::json j = {
      {"model", a.model},
      {"model_size", m.size},
      {"spacing", m.spacing},
      {"rays", n},
      {"hits", m.hit_count},
      {"misses", n - m.hit_count},
      {"thickness", summary_json(m.summary)},
      {"orientation",
       {{"faces_flipped_from_file", m.samples.orientation_flips}, {"faces_unsure", m.samples.orientation_unsure}}},
      {"seconds", {{"orientation", m.orientation_seconds}, {"cast", m.cast_seconds}, {"total", m.seconds}}},
      {"thickness_rays_per_second", m.cast_seconds > 0 ? double(n) / m.cast_seconds : 0.0}};
  if (a.min_wall_given) j["min_wall"] = a.map.min_wall, j["below_min_wall"] = m.below_min_wall;
  if (m.ball) j["ball"] = ball_json(*m.ball, m.hits, a.min_wall_given ? a.map.min_wall : 0.0);
  if (m.hit_count) {
    const auto [tf, tk] = m.rays.source[m.thinnest];
    const auto& g = m.samples.faces[size_t(tf)];
    j["thinnest"] = {{"face", g.face},
                     {"uv", {g.uv[size_t(tk)].x, g.uv[size_t(tk)].y}},
                     {"point", {g.point[size_t(tk)].x, g.point[size_t(tk)].y, g.point[size_t(tk)].z}},
                     {"thickness", m.lo},
                     {"hit_face", m.hits[m.thinnest].face}};
  }
  j.update(figures);
  j["preset"] = a.preset.json();
  j["hit_residual"] = m.hit_residual;
  if (const std::string why = m.doubt(); !why.empty()) j["uncertified"] = why;
  return j;
}

void print_text(const ThicknessArgs& a, const queries::ThicknessMap& m, const nlohmann::json& f) {
  const long long n = static_cast<long long>(m.rays.rays.size());
  a.preset.print_text();
  fmt::print("model      {} ({} faces, {} bicubic patches, size {:.6g})\n", a.model, m.scene_faces, m.scene_patches,
             m.size);
  fmt::print("samples    {} rays at spacing {:.4g}; {} hits, {} misses\n", n, m.spacing, m.hit_count, n - m.hit_count);
  if (m.hit_count) {
    const auto [tf, tk] = m.rays.source[m.thinnest];
    const auto& g = m.samples.faces[size_t(tf)];
    fmt::print("thickness  min {:.6g} (face {} at ({:.4g}, {:.4g}, {:.4g})), median {:.6g}, mean {:.6g}, max {:.6g}\n",
               m.lo, g.face, g.point[size_t(tk)].x, g.point[size_t(tk)].y, g.point[size_t(tk)].z, m.summary.median,
               m.summary.mean, m.summary.max);
  }
  if (a.min_wall_given) fmt::print("below      {} samples thinner than {:.6g}\n", m.below_min_wall, a.map.min_wall);
  if (m.ball) {
    const nlohmann::json b = ball_json(*m.ball, m.hits, a.min_wall_given ? a.map.min_wall : 0.0);
    fmt::print(
        "ball       min {:.6g}, median {:.6g}, mean {:.6g}, max {:.6g} (+- {:.2g}); thinner than the ray at {} "
        "samples; {} rounds, {} point queries ({} walks cut, searched on the CPU), {} unconverged; descent on the {}; "
        "{:.3f} s (+ {:.3f} s preparing the point query)\n",
        b["thickness"]["min"].get<double>(), b["thickness"]["median"].get<double>(),
        b["thickness"]["mean"].get<double>(), b["thickness"]["max"].get<double>(), b["bound"].get<double>(),
        b["thinner_than_ray"].get<long long>(), b["rounds"].get<int>(), b["queries"].get<long long>(),
        b["walks_cut"].get<long long>(), b["unconverged"].get<long long>(),
        m.ball->engine == queries::BatchEngine::Cpu ? "CPU in double" : "GPU", m.ball->seconds,
        m.ball->prepare_seconds);
    if (a.min_wall_given)
      fmt::print("ball below {} samples thinner than {:.6g}\n", b["below_min_wall"].get<long long>(), a.map.min_wall);
  }
  fmt::print("orientation {} faces flipped from the file's flags by ray parity, {} unsure\n",
             m.samples.orientation_flips, m.samples.orientation_unsure);
  fmt::print("time       {:.3f} s (build {:.3f}, orientation {:.3f}, rays {:.3f} = {:.0f} rays/s, {}, {})\n", m.seconds,
             f["seconds_build"].get<double>(), m.orientation_seconds, m.cast_seconds,
             m.cast_seconds > 0 ? double(n) / m.cast_seconds : 0.0, method_used(a.engine), a.engine.device);
  fmt::print("tests      {:.1f} boxes and {:.1f} patches per ray\n", f["tests_per_ray"]["box"].get<double>(),
             f["tests_per_ray"]["patch"].get<double>());
}

void run(const GlobalOptions& global, const ThicknessArgs& a) {
  if (a.samples_given && a.spacing_given) throw BadInput("--samples and --spacing: give one of them");
  if (a.colour == "ball" && !a.map.ball) throw BadInput("--colour ball needs --ball");
  const LoadedModel loaded = load_model(a.model, "thickness");
  if (!a.output.empty()) try {
      if (nurbs::io::mesh_format_of(a.output) != nurbs::io::MeshFormat::Ply)
        throw BadInput(fmt::format("-o {}: the coloured thickness mesh is written as .ply", a.output));
    } catch (const std::invalid_argument& e) {
      throw BadInput(fmt::format("-o: {}", e.what()));
    }
  check_output(a.output, "-o");
  check_output(a.csv, "--csv");
  queries::ThicknessMapOptions o = a.map;
  o.caster = caster_options(a.engine);
  o.gpu = a.engine.device == "gpu";
  o.ball_engine = queries::engine_choice(a.ball_engine);
  o.accept_partial = global.accept_partial;
  std::map<std::string, Progress> bars;  // one line per kind of cast, on stderr once it has taken a second
  o.progress = [&](const std::string& what, long long done, long long total) {
    bars.try_emplace(what, what, what == "thickness: rolling ball" ? "samples" : "rays").first->second.update(done, total);
  };
  std::unique_ptr<gpgpu::Gpu> gpu = o.gpu || o.ball ? start_gpu(global) : nullptr;
  const queries::ThicknessMap m = queries::thickness_map(loaded, o, gpu.get());
  bars.clear();
  const bool by_ball = a.colour == "ball";
  if (!a.output.empty())
    nurbs::io::write_mesh_file(a.output,
                               nurbs::ray::thickness_mesh(m.samples, by_ball ? m.ball_thickness : m.thickness, m.lo, m.hi));
  if (!a.csv.empty()) write_csv(a.csv, m.samples, m.thickness, m.hits, m.rays, m.ball ? &*m.ball : nullptr);
  if (!a.exr.empty()) {
    write_exr_maps(a.exr, m.samples, m.thickness, "thickness");
    if (m.ball) write_exr_maps(a.exr, m.samples, m.ball_thickness, "ball");
  }
  const nlohmann::json figures = ray_figures_json(m.figures, a.engine, o.gpu ? gpu.get() : nullptr, m.scene_faces,
                                                  m.scene_patches, m.scene_size, m.peak_memory);
  if (a.json) {
    nlohmann::json j = map_json(a, m, figures);
    add_model_json(j, loaded.report, global);
    print_json(j);
  } else {
    print_text(a, m, figures);
  }
  if (gpu) report_profile(*gpu, global);
  if (const std::string why = m.failure(); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_thickness_impl

void add_thickness(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_thickness_impl;
  auto a = std::make_shared<ThicknessArgs>();
  CLI::App* cmd = app.add_subcommand(
      "thickness",
      "Wall thickness by ray casting (Lemasson et al.): from samples on every face, the distance to the nearest "
      "hit along the inward normal (faces oriented by ray parity)");
  cmd->add_option("MODEL", a->model, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option_function<long long>(
         "--samples", [a](long long v) { a->map.samples = v, a->samples_given = true; },
         "About this many samples over the model's area (default 20000)")
      ->check(CLI::Range(1LL, queries::kMaxThicknessSamples));
  cmd->add_option_function<double>(
         "--spacing", [a](double v) { a->map.spacing = v, a->spacing_given = true; },
         "Sample spacing on the faces, in model units (instead of --samples)")
      ->check(positive_number("a positive distance"));
  cmd->add_option_function<double>(
         "--min-wall", [a](double v) { a->map.min_wall = v, a->min_wall_given = true; },
         "Count the samples thinner than T (model units)")
      ->check(positive_number("a positive distance"));
  add_ray_engine_options(cmd, a->engine, a->preset);
  cmd->add_flag("--ball", a->map.ball,
                "Also the rolling-ball thickness: the largest empty ball tangent at each sample (shrinking ball over "
                "the GPU batched point query; never above the ray's)");
  cmd->add_option("--ball-tolerance", a->map.ball_tolerance,
                  "--ball: the point query's grid bound K_e, relative to the model size")
      ->check(finite_range(1e-7, 1e-2))
      ->capture_default_str();
  auto* ball_engine = cmd->add_option("--ball-engine", a->ball_engine,
                  "--ball: where the batched point query descends, as distance --engine: gpu (the float pass), cpu "
                  "(its twin in double on every core), auto (cpu when the GL renderer is llvmpipe)")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--colour", a->colour, "-o: colour the mesh by the ray or the ball thickness (--ball)")
      ->check(CLI::IsMember({"ray", "ball"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", a->output,
                  "Write the samples as a PLY mesh coloured by thickness (red thin, yellow, green, blue thick, as the viewer) with the thickness as a float vertex property");
  cmd->add_option("--csv", a->csv, "Write face, u, v, x, y, z, thickness, hit_face per sample");
  cmd->add_option("--exr", a->exr, "Write each face's thickness grid as DIR/face_NNNN_thickness.exr (-1: none)");
  cmd->add_flag("--json", a->json, "One JSON object: rays, hits, thickness min/max/mean/median, figures");
  cmd->callback([&global, a, ball_engine] {
    a->preset.apply();
    if (ball_engine->count() > 0 && !a->map.ball) throw BadInput("--ball-engine needs --ball");
    run(global, *a);
  });
}

}  // namespace cli
