// `nurbsgl thickness MODEL [--samples N | --spacing S] [--min-wall T] [-o OUT.ply] [--csv F] [--exr DIR]`:
// wall thickness by ray casting (Lemasson et al.): from samples on every face a ray along the inward
// normal, the thickness is the distance to the nearest valid hit (nurbs/raycast/thickness.h).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/ray_engine.h"
#include "cli/thickness_ball.h"
#include "cli/validators.h"
#include "gpgpu/exr_dump.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_model.h"
#include "nurbs/raycast/thickness.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_thickness_impl {

/// Most samples a thickness run takes (--samples, and the finest --spacing).
constexpr long long kMaxSamples = 100'000'000;

struct ThicknessArgs {
  std::string model, output, csv, exr;
  long long samples = 20000;
  double spacing = 0.0, min_wall = 0.0;
  bool samples_given = false, spacing_given = false, min_wall_given = false, json = false;
  RayEngineArgs engine;
  PaperPreset preset;  ///< --paper
  BallArgs ball;
  std::string colour = "ray";
};

using Thickness = nurbs::ray::SampleThickness;

void write_csv(const std::string& path, const nurbs::ray::ThicknessSamples& s, const Thickness& th,
               const std::vector<nurbs::ray::Hit>& hits, const nurbs::ray::ThicknessRays& rays,
               const BallResult* ball) {
  nurbs::io::write_file(path, [&](std::ostream& out) {
  out << "face,u,v,x,y,z,thickness,hit_face" << (ball ? ",ball_thickness,ball_bound" : "") << "\n";
  for (size_t r = 0; r < rays.rays.size(); ++r) {
    const auto [f, k] = rays.source[r];
    const auto& g = s.faces[size_t(f)];
    out << fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}", g.face, g.uv[size_t(k)].x,
                       g.uv[size_t(k)].y, g.point[size_t(k)].x, g.point[size_t(k)].y, g.point[size_t(k)].z,
                       th[size_t(f)][size_t(k)], hits[r].face);
    if (ball) out << fmt::format(",{:.17g},{:.3g}", ball->samples[r].thickness, ball->samples[r].bound);
    out << "\n";
  }
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

void run(const GlobalOptions& global, const ThicknessArgs& a) {
  if (a.samples_given && a.spacing_given) throw BadInput("--samples and --spacing: give one of them");
  if (a.colour == "ball" && !a.ball.enabled) throw BadInput("--colour ball needs --ball");
  const auto start = std::chrono::steady_clock::now();
  const LoadedModel loaded = load_model(a.model, "thickness");
  const nurbs::Model& model = loaded.model;
  const double size = checked_model_size(model, a.model);
  // The reader's doubts (nurbs/model_report.h): a face with an invalid trim may add or hide a wall
  // anywhere; an edge gap widens every thickness by the gap.
  const double gap = loaded.report.largest_gap();
  const std::string doubt = loaded.report.invalid_trim_reason();
  const auto certify = [&] {
    require_certified(loaded.report, global);
    if (!doubt.empty()) throw CommandFailed("the thickness is not certified: " + doubt);
  };
  if (!a.output.empty()) try {
      if (nurbs::io::mesh_format_of(a.output) != nurbs::io::MeshFormat::Ply)
        throw BadInput(fmt::format("-o {}: the coloured thickness mesh is written as .ply", a.output));
    } catch (const std::invalid_argument& e) {
      throw BadInput(fmt::format("-o: {}", e.what()));
    }
  check_output(a.output, "-o");
  check_output(a.csv, "--csv");
  RayEngine engine(model, a.engine, global);
  const nurbs::ray::Scene& scene = engine.scene();
  engine.rays_start_on_surfaces();
  nurbs::ray::ThicknessOptions o;
  // A spacing finer than that of the most samples --samples allows is refused before the work.
  if (const double finest = nurbs::ray::spacing_for_samples(scene, kMaxSamples);
      a.spacing_given && !(a.spacing >= finest))
    throw BadInput(fmt::format("--spacing {:g}: below {:.4g}, the spacing of {} samples (the most --samples allows)",
                               a.spacing, finest, kMaxSamples));
  o.spacing = a.spacing_given ? a.spacing : nurbs::ray::spacing_for_samples(scene, a.samples);
  const nurbs::ray::CastFn cast = [&](const std::vector<nurbs::ray::Ray>& rays, double t_min) {
    return engine.cast(rays, t_min, "thickness: orientation");
  };
  const nurbs::ray::ThicknessSamples samples = nurbs::ray::thickness_samples(scene, o, cast);
  const nurbs::ray::ThicknessRays rays = nurbs::ray::thickness_rays(samples);
  const double orient_seconds = engine.cast_seconds();
  const std::vector<nurbs::ray::Hit> hits = engine.cast(rays.rays, o.start_offset * scene.size, "thickness");
  const double cast_seconds = engine.cast_seconds() - orient_seconds;

  Thickness th(samples.faces.size());
  for (size_t f = 0; f < samples.faces.size(); ++f) th[f].assign(samples.faces[f].uv.size(), -1.0);
  long long hit_count = 0, below = 0;
  double lo = 0, hi = 0;
  size_t thinnest = 0;
  std::vector<double> values;
  for (size_t r = 0; r < hits.size(); ++r) {
    if (hits[r].face < 0) continue;
    const auto [f, k] = rays.source[r];
    th[size_t(f)][size_t(k)] = hits[r].t;
    if (hit_count == 0 || hits[r].t < lo) lo = hits[r].t, thinnest = r;
    hi = hit_count == 0 ? hits[r].t : std::max(hi, hits[r].t);
    ++hit_count;
    below += a.min_wall_given && hits[r].t < a.min_wall ? 1 : 0;
    values.push_back(hits[r].t);
  }
  const nurbs::ray::ThicknessSummary summary = nurbs::ray::summarize_thickness(std::move(values));
  std::optional<BallResult> ball;
  Thickness ball_th;
  if (a.ball.enabled) {
    ball = ball_thickness(model, rays, hits, size, a.ball, global, engine.gpu());
    ball_th = Thickness(samples.faces.size());
    for (size_t f = 0; f < samples.faces.size(); ++f) ball_th[f].assign(samples.faces[f].uv.size(), -1.0);
    for (size_t r = 0; r < rays.rays.size(); ++r)
      ball_th[size_t(rays.source[r].first)][size_t(rays.source[r].second)] = ball->samples[r].thickness;
  }
  const bool by_ball = a.colour == "ball";
  if (!a.output.empty())
    nurbs::io::write_mesh_file(a.output, nurbs::ray::thickness_mesh(samples, by_ball ? ball_th : th, lo, hi));
  if (!a.csv.empty()) write_csv(a.csv, samples, th, hits, rays, ball ? &*ball : nullptr);
  if (!a.exr.empty()) {
    write_exr_maps(a.exr, samples, th, "thickness");
    if (ball) write_exr_maps(a.exr, samples, ball_th, "ball");
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double residual = scene.options.exact_residual * scene.size;
  const long long n = static_cast<long long>(rays.rays.size());
  const nlohmann::json f = engine.figures();

  if (a.json) {
    nlohmann::json j = {
        {"model", a.model},
        {"model_size", size},
        {"spacing", o.spacing},
        {"rays", n},
        {"hits", hit_count},
        {"misses", n - hit_count},
        {"hit_residual", residual},
        {"thickness", summary_json(summary)},
        {"orientation",
         {{"faces_flipped_from_file", samples.orientation_flips}, {"faces_unsure", samples.orientation_unsure}}},
        {"seconds", {{"orientation", orient_seconds}, {"cast", cast_seconds}, {"total", total}}},
        {"thickness_rays_per_second", cast_seconds > 0 ? double(n) / cast_seconds : 0.0}};
    if (a.min_wall_given) j["min_wall"] = a.min_wall, j["below_min_wall"] = below;
    if (ball) j["ball"] = ball_json(*ball, hits, a.min_wall_given ? a.min_wall : 0.0);
    if (hit_count) {
      const auto [tf, tk] = rays.source[thinnest];
      const auto& g = samples.faces[size_t(tf)];
      j["thinnest"] = {{"face", g.face},
                       {"uv", {g.uv[size_t(tk)].x, g.uv[size_t(tk)].y}},
                       {"point", {g.point[size_t(tk)].x, g.point[size_t(tk)].y, g.point[size_t(tk)].z}},
                       {"thickness", lo},
                       {"hit_face", hits[thinnest].face}};
    }
    j.update(f);
    j["preset"] = a.preset.json();
    j["hit_residual"] = j["hit_residual"].get<double>() + gap;
    if (!doubt.empty()) j["uncertified"] = doubt;
    add_model_json(j, loaded.report, global);
    print_json(j);
    certify();
    return;
  }
  a.preset.print_text();
  fmt::print("model      {} ({} faces, {} bicubic patches, size {:.6g})\n", a.model, scene.faces.size(),
             scene.patches.size(), size);
  fmt::print("samples    {} rays at spacing {:.4g}; {} hits, {} misses\n", n, o.spacing, hit_count, n - hit_count);
  if (hit_count) {
    const auto [tf, tk] = rays.source[thinnest];
    const auto& g = samples.faces[size_t(tf)];
    fmt::print("thickness  min {:.6g} (face {} at ({:.4g}, {:.4g}, {:.4g})), median {:.6g}, mean {:.6g}, max {:.6g}\n",
               lo, g.face, g.point[size_t(tk)].x, g.point[size_t(tk)].y, g.point[size_t(tk)].z, summary.median,
               summary.mean, summary.max);
  }
  if (a.min_wall_given) fmt::print("below      {} samples thinner than {:.6g}\n", below, a.min_wall);
  if (ball) {
    const nlohmann::json b = ball_json(*ball, hits, a.min_wall_given ? a.min_wall : 0.0);
    fmt::print(
        "ball       min {:.6g}, median {:.6g}, mean {:.6g}, max {:.6g} (+- {:.2g}); thinner than the ray at {} "
        "samples; {} rounds, {} point queries ({} walks cut, searched on the CPU), {} unconverged; descent on the {}; "
        "{:.3f} s (+ {:.3f} s preparing the point query)\n",
        b["thickness"]["min"].get<double>(), b["thickness"]["median"].get<double>(),
        b["thickness"]["mean"].get<double>(), b["thickness"]["max"].get<double>(), b["bound"].get<double>(),
        b["thinner_than_ray"].get<long long>(), b["rounds"].get<int>(), b["queries"].get<long long>(),
        b["walks_cut"].get<long long>(), b["unconverged"].get<long long>(),
        ball->engine == "cpu" ? "CPU in double" : "GPU", ball->seconds, ball->prepare_seconds);
    if (a.min_wall_given)
      fmt::print("ball below {} samples thinner than {:.6g}\n", b["below_min_wall"].get<long long>(), a.min_wall);
  }
  fmt::print("orientation {} faces flipped from the file's flags by ray parity, {} unsure\n", samples.orientation_flips,
             samples.orientation_unsure);
  fmt::print("time       {:.3f} s (build {:.3f}, orientation {:.3f}, rays {:.3f} = {:.0f} rays/s, {}, {})\n", total,
             f["seconds_build"].get<double>(), orient_seconds, cast_seconds,
             cast_seconds > 0 ? double(n) / cast_seconds : 0.0, a.engine.method, a.engine.device);
  fmt::print("tests      {:.1f} boxes and {:.1f} patches per ray\n", f["tests_per_ray"]["box"].get<double>(),
             f["tests_per_ray"]["patch"].get<double>());
  certify();
}

}  // namespace cmd_thickness_impl

void add_thickness(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_thickness_impl;
  auto a = std::make_shared<ThicknessArgs>();
  CLI::App* cmd = app.add_subcommand(
      "thickness",
      "Wall thickness by ray casting (Lemasson et al.): from samples on every face, the distance to the nearest "
      "hit along the inward normal (faces oriented by ray parity)");
  cmd->add_option("MODEL", a->model, "Model file (.igs/.iges/.bpt)")->required();
  cmd->add_option_function<long long>(
         "--samples", [a](long long v) { a->samples = v, a->samples_given = true; },
         "About this many samples over the model's area (default 20000)")
      ->check(CLI::Range(1LL, kMaxSamples));
  cmd->add_option_function<double>(
         "--spacing", [a](double v) { a->spacing = v, a->spacing_given = true; },
         "Sample spacing on the faces, in model units (instead of --samples)")
      ->check(positive_number("a positive distance"));
  cmd->add_option_function<double>(
         "--min-wall", [a](double v) { a->min_wall = v, a->min_wall_given = true; },
         "Count the samples thinner than T (model units)")
      ->check(positive_number("a positive distance"));
  add_ray_engine_options(cmd, a->engine, a->preset);
  cmd->add_flag("--ball", a->ball.enabled,
                "Also the rolling-ball thickness: the largest empty ball tangent at each sample (shrinking ball over "
                "the GPU batched point query; never above the ray's)");
  cmd->add_option("--ball-tolerance", a->ball.tolerance,
                  "--ball: the point query's grid bound K_e, relative to the model size")
      ->check(finite_range(1e-7, 1e-2))
      ->capture_default_str();
  auto* ball_engine = cmd->add_option("--ball-engine", a->ball.engine,
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
    if (ball_engine->count() > 0 && !a->ball.enabled) throw BadInput("--ball-engine needs --ball");
    run(global, *a);
  });
}

}  // namespace cli
