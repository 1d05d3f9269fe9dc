// `nurbsgl evaluate MODEL`: evaluates every face (or the chosen ones) on the GPU into point and
// normal textures on the knot-aligned grid whose Euclidean Filip bound K_e meets the tolerance on
// every cell (nurbs/distance/certified_grid.h): faces packed into atlases, one evaluation pass and one trim
// fill per atlas (queries/distance/face_atlas.h); a face too large for an atlas alone, in tiles. It reports
// per face the grid, K, K_e, the bound's ratio to the sampled second derivatives and whether the
// tolerance is met. Exit 1 when a face does not meet it.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "cli/commands.h"
#include "cli/validators.h"
#include "nurbs/distance/grid_report.h"
#include "nurbs/io/obj_writer.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/face_atlas.h"
#include "queries/distance/surface_grid.h"
#include "queries/distance/trim_texture.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_evaluate_impl {

struct Options {
  std::string path;
  std::vector<int> faces;  ///< indices into the model's face list; empty = all
  int grid = 0;            ///< samples per direction of a uniform grid; 0 = certified grid from the tolerance
  double rel_tolerance = 1e-4;
  bool tolerance_given = false;  ///< with --grid, the tolerance is checked only when asked for
  long long max_samples = 1LL << 26;
  int tile_mb = 256;
  std::string obj;
  bool json = false;
  bool spans = false;  ///< per-segment K_e in the JSON
  bool batch = true;   ///< faces in atlases (one pass per batch); false = one face at a time
  queries::EvalMethod method = queries::EvalMethod::Tabulated;
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The grid of one face: certified for the tolerance, or the uniform --grid with its bounds.
nurbs::FaceGridReport face_grid(const nurbs::Surface& s, const Options& o, double tolerance) {
  if (o.grid == 0) return nurbs::grid_report(s, tolerance, {o.max_samples}, false);
  nurbs::FaceGridReport r;
  r.bound = nurbs::filip_bound(s);
  const nurbs::FilipBound& b = r.bound;
  r.grid.grid = nurbs::uniform_param_grid(b.domain_u, b.domain_v, o.grid - 1, o.grid - 1);
  r.grid.k = nurbs::grid_k(b, r.grid.grid, nurbs::KNorm::Component);
  r.grid.k_e = nurbs::grid_k(b, r.grid.grid, nurbs::KNorm::Euclidean);
  r.grid.tolerance = tolerance;
  r.grid.lines_u = {b.domain_u.min, b.domain_u.max};
  r.grid.lines_v = {b.domain_v.min, b.domain_v.max};
  r.grid.cells_u = {o.grid - 1};
  r.grid.cells_v = {o.grid - 1};
  r.grid.meets_tolerance = !o.tolerance_given || r.grid.k_e <= tolerance;
  if (!r.grid.meets_tolerance)
    r.grid.reason = std::isfinite(r.grid.k_e) ? fmt::format("the {}^2 grid has K_e {:.3g}", o.grid, r.grid.k_e)
                                              : fmt::format("the {}^2 grid crosses a C0 knot line", o.grid);
  const double sampled = nurbs::grid_k(nurbs::sampled_bound(s, b), r.grid.grid, nurbs::KNorm::Euclidean);
  r.bound_ratio = sampled > 0 ? r.grid.k_e / sampled : 1.0;
  return r;
}

nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

/// GPU work of one face or batch: times and, for --obj, the points.
struct GpuWork {
  double eval_ms = 0, trim_ms = 0;
  int tiles = 0;
  int batch = -1;  ///< index of the atlas the face was evaluated in; -1 = alone (tiled)
};

/// Evaluates one face alone, tile by tile (grids larger than a tile, or --no-batch).
GpuWork evaluate_alone(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& f, const nurbs::ParamGrid& params,
                       const Options& o, const queries::TileLimits& limits, int side, std::set<int>& compiled,
                       nurbs::io::SampledGrid* sg) {
  GpuWork w;
  const queries::GpuSurface g = queries::upload_surface(f.surface, gpu.info().max_texture_size);
  if (compiled.insert(std::max(f.surface.degree_u, f.surface.degree_v)).second) {
    (void)queries::evaluate_surface(gpu, g, 1, 1, o.method);  // builds the programs for this degree: not timed
    gpu.finish();
  }
  auto t0 = std::chrono::steady_clock::now();
  queries::evaluate_surface_tiles(gpu, g, params, o.method, limits, [&](queries::GridTile&& t) {
    ++w.tiles;
    if (!sg) return;
    const auto pts = t.points.read();
    for (int y = 0; y < t.points.height(); ++y)
      for (int x = 0; x < t.points.width(); ++x) {
        const size_t k = size_t(y * t.points.width() + x) * 4;
        sg->points[size_t(t.j0 + y) * params.u.size() + size_t(t.i0 + x)] = {pts[k], pts[k + 1], pts[k + 2]};
      }
  });
  gpu.finish();
  w.eval_ms = ms_since(t0);
  if (!f.loops.empty()) {
    t0 = std::chrono::steady_clock::now();
    (void)queries::trim_masks(gpu, f, params, side, queries::trim_flatten_tolerance(params));
    gpu.finish();
    w.trim_ms = ms_since(t0);
  }
  return w;
}

/// What the GPU evaluated: per face its work (a batch or tiles alone) and, with --obj, its points.
struct Evaluated {
  std::vector<GpuWork> gpu_work;
  std::vector<nurbs::io::SampledGrid> grids;
  std::vector<nurbs::ParamGrid> params;
  nlohmann::json batches;
  std::vector<int> alone;  ///< faces evaluated alone, in tiles
  int side = 0;
};

/// Step 2: the faces `work` (chosen[k] in the model) on their grids `reports`, in atlases of
/// batches where the method allows, the others alone.
Evaluated evaluate_on_gpu(gpgpu::Gpu& gpu, const std::vector<nurbs::TrimmedSurface>& work,
                          const std::vector<nurbs::FaceGridReport>& reports, const std::vector<int>& chosen,
                          const Options& o, bool progress) {
  const queries::TileLimits limits{0, static_cast<long long>(o.tile_mb) << 20};
  const int side = queries::tile_side(gpu.info(), limits);
  std::vector<GpuWork> gpu_work(work.size());
  std::vector<nurbs::io::SampledGrid> grids(work.size());
  std::vector<nurbs::ParamGrid> params;
  std::vector<std::pair<int, int>> sizes;
  for (size_t k = 0; k < work.size(); ++k) {
    params.push_back(reports[k].grid.grid);
    sizes.emplace_back(int(params.back().u.size()), int(params.back().v.size()));
    grids[k] = {{}, sizes.back().first, sizes.back().second, fmt::format("face{}", chosen[k])};
    if (!o.obj.empty()) grids[k].points.resize(size_t(params.back().samples()));
  }
  std::vector<int> alone;
  std::vector<queries::AtlasPlan> plans;
  if (o.batch && o.method == queries::EvalMethod::Tabulated) {
    plans = queries::plan_atlases(sizes, side, (static_cast<long long>(o.tile_mb) << 20) / 33, alone);
  } else {
    for (int k = 0; k < int(work.size()); ++k) alone.push_back(k);
  }
  nlohmann::json batches = nlohmann::json::array();
  std::vector<double> flatten;
  for (const auto& p : params) flatten.push_back(queries::trim_flatten_tolerance(p));
  if (!plans.empty()) {  // build the atlas program outside the timing
    (void)queries::evaluate_atlas(gpu, {1, 1, {}}, work, params, flatten);
    gpu.finish();
  }
  for (size_t b = 0; b < plans.size(); ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    const queries::FaceAtlas atlas = queries::evaluate_atlas(gpu, plans[b], work, params, flatten);
    gpu.finish();
    const double ms = ms_since(t0);
    long long samples = 0;
    for (const auto& sl : plans[b].slots) {
      gpu_work[size_t(sl.face)].batch = int(b);
      samples += static_cast<long long>(sl.width) * sl.height;
    }
    batches.push_back({{"faces", plans[b].slots.size()},
                       {"atlas", {plans[b].width, plans[b].height}},
                       {"samples", samples},
                       {"ms", ms}});
    if (!o.obj.empty()) {
      const auto pts = atlas.points.read();
      for (const auto& sl : plans[b].slots)
        for (int j = 0; j < sl.height; ++j)
          for (int i = 0; i < sl.width; ++i) {
            const size_t t = (size_t(sl.y + j) * size_t(plans[b].width) + size_t(sl.x + i)) * 4;
            grids[size_t(sl.face)].points[size_t(j) * size_t(sl.width) + size_t(i)] = {pts[t], pts[t + 1], pts[t + 2]};
          }
    }
  }
  std::set<int> compiled;
  for (size_t a = 0; a < alone.size(); ++a) {
    const auto k = size_t(alone[a]);
    gpu_work[k] =
        evaluate_alone(gpu, work[k], params[k], o, limits, side, compiled, o.obj.empty() ? nullptr : &grids[k]);
    if (progress) fmt::print(stderr, "\r[{}/{}] faces evaluated alone", a + 1, alone.size());
  }
  if (progress && !alone.empty()) fmt::print(stderr, "\n");

  return {std::move(gpu_work), std::move(grids), std::move(params), std::move(batches), std::move(alone), side};
}

/// Step 3: the JSON row of face `index` (the model's) on its grid.
nlohmann::json face_row(int index, const nurbs::TrimmedSurface& f, const nurbs::FaceGridReport& report,
                        const nurbs::ParamGrid& grid, const GpuWork& w, double size, double tolerance, const Options& o) {
  const nurbs::CertifiedGrid& cg = report.grid;
  nlohmann::json row{
      {"face", index},
      {"face_id", f.face_id},
      {"degree", {f.surface.degree_u, f.surface.degree_v}},
      {"control_points", {f.surface.count_u, f.surface.count_v}},
      {"grid", {grid.u.size(), grid.v.size()}},
      {"segments", {cg.cells_u.size(), cg.cells_v.size()}},
      {"K", finite_or_null(cg.k)},
      {"K_e", finite_or_null(cg.k_e)},
      {"K_e_over_size", finite_or_null(cg.k_e / size)},
      {"tolerance", o.grid > 0 && !o.tolerance_given ? nlohmann::json(nullptr) : nlohmann::json(tolerance)},
      {"meets_tolerance", cg.meets_tolerance},
      {"bound_ratio", finite_or_null(report.bound_ratio)},
      {"trimmed", !f.loops.empty()}};
  if (w.batch >= 0) {
    row["batch"] = w.batch;
  } else {
    row["tiles"] = w.tiles;
    row["eval_ms"] = w.eval_ms;
    row["trim_ms"] = w.trim_ms;
  }
  if (!cg.meets_tolerance) row["reason"] = cg.reason;
  if (o.spans) {
    nlohmann::json ke = nlohmann::json::array();
    for (double k : nurbs::segment_k(report.bound, cg)) ke.push_back(finite_or_null(k));
    row["spans"] = {{"lines_u", cg.lines_u},
                    {"lines_v", cg.lines_v},
                    {"cells_u", cg.cells_u},
                    {"cells_v", cg.cells_v},
                    {"K_e", ke}};
  }
  return row;
}

void run(const GlobalOptions& global, const Options& o) {
  // --obj is checked before the work, in a --dump folder once that exists.
  if (global.dump_dir.empty()) check_output(o.obj, "--obj");
  const LoadedModel loaded = load_model(o.path, "evaluate");
  const nurbs::Model& model = loaded.model;
  const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
  const double size = nurbs::checked_model_size(model, o.path);
  std::vector<int> chosen = o.faces;
  for (int index : chosen)
    if (index < 0 || index >= int(faces.size()))
      throw BadInput(fmt::format("--face {}: the model has faces 0..{}", index, int(faces.size()) - 1));
  if (chosen.empty())
    for (int i = 0; i < int(faces.size()); ++i) chosen.push_back(i);
  if (o.grid > 0 && static_cast<long long>(o.grid) * o.grid > o.max_samples)
    throw BadInput(fmt::format("--grid {}: {} samples per face exceed --max-samples {}", o.grid,
                               static_cast<long long>(o.grid) * o.grid, o.max_samples));
  const double tolerance = o.rel_tolerance * size;
  const bool progress = chosen.size() > 8 && isatty(STDERR_FILENO);

  // 1. Grids, on the CPU.
  std::vector<nurbs::TrimmedSurface> work;
  std::vector<nurbs::FaceGridReport> reports;
  for (size_t c = 0; c < chosen.size(); ++c) {
    work.push_back(faces[size_t(chosen[c])]);
    reports.push_back(face_grid(work.back().surface, o, tolerance));
    if (progress) fmt::print(stderr, "\r[{}/{}] grids chosen", c + 1, chosen.size());
  }
  if (progress) fmt::print(stderr, "\n");

  // 2. The GPU: batches of faces in atlases (one evaluation pass and one trim fill each), the
  // faces too large for an atlas alone in tiles.
  auto gpu = start_gpu(global);
  if (!global.dump_dir.empty()) check_output(o.obj, "--obj");
  const Evaluated e = evaluate_on_gpu(*gpu, work, reports, chosen, o, progress);
  const auto& [gpu_work, grids, params, batches, alone, side] = e;

  // 3. Report.
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::string> failures;
  long long total_samples = 0, largest = 0;
  double total_ms = 0;
  for (const auto& b : batches) total_ms += b["ms"].get<double>();
  if (!o.json)
    fmt::print(
        "{} faces, model size {:.6g}, tolerance {:.3g} ({:g} x size), backend {} ({}), tiles of {}^2\n"
        "{:>5} {:>7} {:>11} {:>11} {:>9} {:>10} {:>10} {:>9} {:>6} {:>9}\n",
        faces.size(), size, tolerance, o.rel_tolerance, gpu->info().backend, gpu->info().renderer, side, "face",
        "degree", "ctrl", "grid", "segments", "K", "K_e", "K_e/size", "ratio", "GPU ms");
  for (size_t k = 0; k < work.size(); ++k) {
    const int index = chosen[k];
    const nurbs::TrimmedSurface& f = work[k];
    const nurbs::CertifiedGrid& cg = reports[k].grid;
    const GpuWork& w = gpu_work[k];
    if (!cg.meets_tolerance) failures.push_back(fmt::format("face {}: {}", index, cg.reason));
    total_samples += params[k].samples();
    largest = std::max(largest, params[k].samples());
    total_ms += w.eval_ms + w.trim_ms;
    nlohmann::json row = face_row(index, f, reports[k], params[k], w, size, tolerance, o);
    if (!o.json && !progress)
      fmt::print(
          "{:>5} {:>3}x{:<3} {:>5}x{:<5} {:>5}x{:<5} {:>4}x{:<4} {:>10.4g} {:>10.4g} {:>9.3g} {:>6.2f} {:>9}{}\n",
          index, f.surface.degree_u, f.surface.degree_v, f.surface.count_u, f.surface.count_v, params[k].u.size(),
          params[k].v.size(), cg.cells_u.size(), cg.cells_v.size(), cg.k, cg.k_e, cg.k_e / size, reports[k].bound_ratio,
          w.batch >= 0 ? fmt::format("batch {}", w.batch) : fmt::format("{:.2f}", w.eval_ms + w.trim_ms),
          cg.meets_tolerance ? "" : "  NOT MET");
    rows.push_back(std::move(row));
  }
  if (!o.obj.empty()) nurbs::io::write_obj_file(o.obj, grids);
  if (o.json) {
    nlohmann::json j{{"model", o.path},
                                      {"model_size", size},
                                      {"tolerance", tolerance},
                                      {"backend", gpu->info().backend},
                                      {"renderer", gpu->info().renderer},
                                      {"tile_side", side},
                                      {"faces_meeting_tolerance", chosen.size() - failures.size()},
                                      {"samples", total_samples},
                                      {"gpu_ms", total_ms},
                                      {"batches", batches},
                                      {"faces_alone", alone.size()},
                                      {"faces", rows}};
    add_model_json(j, loaded.report, global);
    print_json(j);
  } else {
    fmt::print(
        "{}/{} faces meet the tolerance; {} samples in all, largest grid {}; GPU {:.1f} ms ({} batches, {} "
        "faces alone)\n",
        chosen.size() - failures.size(), chosen.size(), total_samples, largest, total_ms, batches.size(), alone.size());
  }
  report_profile(*gpu, global);
  if (!failures.empty()) {
    std::string list;
    for (const auto& f : failures) list += "\n  " + f;
    throw CommandFailed(
        fmt::format("{} of {} faces do not meet the tolerance:{}", failures.size(), chosen.size(), list));
  }
}

}  // namespace cmd_evaluate_impl

void add_evaluate(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_evaluate_impl;
  auto* cmd =
      app.add_subcommand("evaluate",
                         "Evaluate faces on the GPU on knot-aligned grids whose Filip bound K_e meets the "
                         "tolerance on every cell; trim masks; EXR/OBJ output. Exit 1 if a face cannot meet it");
  auto o = std::make_shared<Options>();
  cmd->add_option("MODEL", o->path, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option("--face", o->faces, "Face index (repeatable); default: all faces");
  cmd->add_option("--grid", o->grid,
                  "Uniform grid of N x N samples instead of the certified one (reports its K_e; checked against "
                  "--tolerance only when that is given too)")
      ->check(CLI::Range(2, 1 << 20));
  cmd->add_option("--tolerance", o->rel_tolerance,
                  "Bound on the Euclidean deviation K_e of surface from grid triangles, relative to the model size "
                  "(1e-9 to 1: below, float samples could not carry it)")
      ->check(relative_tolerance())
      ->capture_default_str();
  cmd->add_option("--max-samples", o->max_samples, "Most samples one face's grid may have")
      ->check(CLI::Range(4LL, 1LL << 32))
      ->capture_default_str();
  cmd->add_option("--tile-mb", o->tile_mb, "GPU memory for one tile of points and normals, MiB (grids are tiled)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  static const std::map<std::string, queries::EvalMethod> methods{{"tabulated", queries::EvalMethod::Tabulated},
                                                                  {"per-fragment", queries::EvalMethod::PerFragment}};
  auto method = std::make_shared<std::string>("tabulated");
  cmd->add_option("--method", *method,
                  "GPU evaluation: tabulated (basis tables per row/column, then combine) or per-fragment (one pass)")
      ->check(CLI::IsMember({"tabulated", "per-fragment"}))
      ->capture_default_str();
  cmd->add_option("--obj", o->obj, "Write the evaluated grids to this OBJ file");
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->add_flag("--spans", o->spans,
                "With --json: per face the segments (kept knot lines, cells per segment) and the K_e of every "
                "segment pair, row-major with u fastest");
  cmd->add_flag("!--no-batch", o->batch,
                "Evaluate one face at a time instead of packing faces into atlases (one pass per batch)");
  cmd->callback([&global, o, method, cmd] {
    o->method = methods.at(*method);
    o->tolerance_given = cmd->count("--tolerance") > 0;
    if (o->spans && !o->json) throw BadInput("--spans: needs --json");
    run(global, *o);
  });
}

}  // namespace cli
