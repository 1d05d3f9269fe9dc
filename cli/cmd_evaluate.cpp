// `nurbsgl evaluate MODEL`: evaluates every face (or the chosen ones) on the GPU into point and
// normal textures on the knot-aligned grid whose Euclidean Filip bound K_e meets the tolerance on
// every cell (nurbs/certified_grid.h), in tiles when the grid exceeds the GPU's limits, renders the
// trim masks on the same samples, and reports per face the grid, K, K_e, the bound's ratio to the
// sampled second derivatives and whether the tolerance is met. Exit 1 when a face does not meet it.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "cli/commands.h"
#include "nurbs/grid_report.h"
#include "nurbs/io/obj_writer.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/surface_grid.h"
#include "queries/trim_texture.h"

namespace cli {
namespace {

struct Options {
  std::string path;
  std::vector<int> faces;  ///< indices into the model's face list; empty = all
  int grid = 0;            ///< samples per direction of a uniform grid; 0 = certified grid from the tolerance
  double rel_tolerance = 1e-4;
  long long max_samples = 1LL << 26;
  int tile_mb = 256;
  std::string obj;
  bool json = false;
  queries::EvalMethod method = queries::EvalMethod::Tabulated;
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The grid of one face: certified for the tolerance, or the uniform --grid with its bounds.
nurbs::FaceGridReport face_grid(const nurbs::Surface& s, const Options& o, double tolerance) {
  if (o.grid == 0) return nurbs::grid_report(s, tolerance, {o.max_samples}, false);
  nurbs::FaceGridReport r;
  const nurbs::FilipBound b = nurbs::filip_bound(s);
  r.grid.grid = nurbs::uniform_param_grid(b.domain_u, b.domain_v, o.grid - 1, o.grid - 1);
  r.grid.k = nurbs::grid_k(b, r.grid.grid, nurbs::KNorm::Component);
  r.grid.k_e = nurbs::grid_k(b, r.grid.grid, nurbs::KNorm::Euclidean);
  r.grid.tolerance = tolerance;
  r.grid.meets_tolerance = r.grid.k_e <= tolerance;
  if (!r.grid.meets_tolerance)
    r.grid.reason = std::isfinite(r.grid.k_e) ? fmt::format("the {}^2 grid has K_e {:.3g}", o.grid, r.grid.k_e)
                                              : fmt::format("the {}^2 grid crosses a C0 knot line", o.grid);
  const double sampled = nurbs::grid_k(nurbs::sampled_bound(s, b), r.grid.grid, nurbs::KNorm::Euclidean);
  r.bound_ratio = sampled > 0 ? r.grid.k_e / sampled : 1.0;
  return r;
}

nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

void run(const GlobalOptions& global, const Options& o) {
  const nurbs::Model model = nurbs::io::read_model(o.path);
  const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
  const double size = nurbs::model_size(model);
  if (const auto problems = nurbs::validate_model_size(size); !problems.empty())
    throw BadInput(fmt::format("{}: {}", o.path, problems.front()));
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
  auto gpu = start_gpu(global);
  const queries::TileLimits limits{0, static_cast<long long>(o.tile_mb) << 20};
  const int side = queries::tile_side(gpu->info(), limits);
  nlohmann::json rows = nlohmann::json::array();
  std::vector<nurbs::io::SampledGrid> grids;
  std::vector<std::string> failures;
  std::set<int> compiled;  // MAX_DEGREE values whose programs are built (not timed)
  long long total_samples = 0, largest = 0;
  double total_ms = 0;
  const bool progress = chosen.size() > 8 && isatty(STDERR_FILENO);
  if (!o.json)
    fmt::print(
        "{} faces, model size {:.6g}, tolerance {:.3g} ({:g} x size), backend {} ({}), tiles of {}^2\n"
        "{:>5} {:>7} {:>11} {:>11} {:>9} {:>10} {:>10} {:>9} {:>6} {:>9} {:>9}\n",
        faces.size(), size, tolerance, o.rel_tolerance, gpu->info().backend, gpu->info().renderer, side, "face",
        "degree", "ctrl", "grid", "segments", "K", "K_e", "K_e/size", "ratio", "eval ms", "trim ms");
  for (size_t c = 0; c < chosen.size(); ++c) {
    const int index = chosen[c];
    const nurbs::TrimmedSurface& f = faces[size_t(index)];
    const nurbs::FaceGridReport report = face_grid(f.surface, o, tolerance);
    const nurbs::ParamGrid& params = report.grid.grid;
    const queries::GpuSurface g = queries::upload_surface(f.surface, gpu->info().max_texture_size);
    if (compiled.insert(std::max(f.surface.degree_u, f.surface.degree_v)).second) {
      (void)queries::evaluate_surface(*gpu, g, 1, 1, o.method);  // builds the programs for this degree
      gpu->finish();
    }
    nurbs::io::SampledGrid sg{{}, int(params.u.size()), int(params.v.size()), fmt::format("face{}", index)};
    if (!o.obj.empty()) sg.points.resize(size_t(params.samples()));
    int tiles = 0;
    auto t0 = std::chrono::steady_clock::now();
    queries::evaluate_surface_tiles(*gpu, g, params, o.method, limits, [&](queries::GridTile&& t) {
      ++tiles;
      if (o.obj.empty()) return;
      const auto pts = t.points.read();
      for (int y = 0; y < t.points.height(); ++y)
        for (int x = 0; x < t.points.width(); ++x) {
          const size_t k = size_t(y * t.points.width() + x) * 4;
          sg.points[size_t(t.j0 + y) * params.u.size() + size_t(t.i0 + x)] = {pts[k], pts[k + 1], pts[k + 2]};
        }
    });
    gpu->finish();
    const double eval_ms = ms_since(t0);
    double trim_ms = 0;
    if (!f.loops.empty()) {
      t0 = std::chrono::steady_clock::now();
      double step = 1e300;  // a tenth of the smallest step flattens the loops finely enough
      for (size_t i = 0; i + 1 < params.u.size(); ++i) step = std::min(step, params.u[i + 1] - params.u[i]);
      for (size_t j = 0; j + 1 < params.v.size(); ++j) step = std::min(step, params.v[j + 1] - params.v[j]);
      (void)queries::trim_masks(*gpu, f, params, side, 0.1 * step);
      gpu->finish();
      trim_ms = ms_since(t0);
    }
    const nurbs::CertifiedGrid& cg = report.grid;
    if (!cg.meets_tolerance) failures.push_back(fmt::format("face {}: {}", index, cg.reason));
    total_samples += params.samples();
    largest = std::max(largest, params.samples());
    total_ms += eval_ms + trim_ms;
    nlohmann::json row{{"face", index},
                       {"face_id", f.face_id},
                       {"degree", {f.surface.degree_u, f.surface.degree_v}},
                       {"control_points", {f.surface.count_u, f.surface.count_v}},
                       {"grid", {params.u.size(), params.v.size()}},
                       {"segments", {cg.cells_u.size(), cg.cells_v.size()}},
                       {"tiles", tiles},
                       {"K", finite_or_null(cg.k)},
                       {"K_e", finite_or_null(cg.k_e)},
                       {"K_e_over_size", finite_or_null(cg.k_e / size)},
                       {"tolerance", tolerance},
                       {"meets_tolerance", cg.meets_tolerance},
                       {"bound_ratio", finite_or_null(report.bound_ratio)},
                       {"eval_ms", eval_ms},
                       {"trim_ms", trim_ms},
                       {"trimmed", !f.loops.empty()}};
    if (!cg.meets_tolerance) row["reason"] = cg.reason;
    rows.push_back(std::move(row));
    if (progress)
      fmt::print(stderr, "\r[{}/{}] faces evaluated", c + 1, chosen.size());
    else if (!o.json)
      fmt::print(
          "{:>5} {:>3}x{:<3} {:>5}x{:<5} {:>5}x{:<5} {:>4}x{:<4} {:>10.4g} {:>10.4g} {:>9.3g} {:>6.2f} {:>9.2f} "
          "{:>9.2f}{}\n",
          index, f.surface.degree_u, f.surface.degree_v, f.surface.count_u, f.surface.count_v, params.u.size(),
          params.v.size(), cg.cells_u.size(), cg.cells_v.size(), cg.k, cg.k_e, cg.k_e / size, report.bound_ratio,
          eval_ms, trim_ms, cg.meets_tolerance ? "" : "  NOT MET");
    if (!o.obj.empty()) grids.push_back(std::move(sg));
  }
  if (progress) fmt::print(stderr, "\n");
  if (!o.obj.empty()) nurbs::io::write_obj_file(o.obj, grids);
  if (o.json) {
    fmt::print("{}\n", nlohmann::json{{"model", o.path},
                                      {"model_size", size},
                                      {"tolerance", tolerance},
                                      {"backend", gpu->info().backend},
                                      {"renderer", gpu->info().renderer},
                                      {"tile_side", side},
                                      {"faces_meeting_tolerance", chosen.size() - failures.size()},
                                      {"samples", total_samples},
                                      {"faces", rows}}
                           .dump(2));
  } else {
    fmt::print("{}/{} faces meet the tolerance; {} samples in all, largest grid {}, {:.1f} ms on the GPU\n",
               chosen.size() - failures.size(), chosen.size(), total_samples, largest, total_ms);
  }
  report_profile(*gpu, global);
  if (!failures.empty()) {
    std::string list;
    for (const auto& f : failures) list += "\n  " + f;
    throw CommandFailed(
        fmt::format("{} of {} faces do not meet the tolerance:{}", failures.size(), chosen.size(), list));
  }
}

}  // namespace

void add_evaluate(CLI::App& app, const GlobalOptions& global) {
  auto* cmd =
      app.add_subcommand("evaluate",
                         "Evaluate faces on the GPU on knot-aligned grids whose Filip bound K_e meets the "
                         "tolerance on every cell; trim masks; EXR/OBJ output. Exit 1 if a face cannot meet it");
  auto o = std::make_shared<Options>();
  cmd->add_option("MODEL", o->path, "Model file (.igs/.iges/.bpt)")->required();
  cmd->add_option("--face", o->faces, "Face index (repeatable); default: all faces");
  cmd->add_option("--grid", o->grid, "Uniform grid of N x N samples instead of the certified one (reports its K_e)")
      ->check(CLI::Range(2, 1 << 20));
  cmd->add_option("--tolerance", o->rel_tolerance,
                  "Bound on the Euclidean deviation K_e of surface from grid triangles, relative to the model size "
                  "(1e-9 to 1: below, float samples could not carry it)")
      ->check(CLI::Range(1e-9, 1.0))
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
  cmd->callback([&global, o, method] {
    o->method = methods.at(*method);
    run(global, *o);
  });
}

}  // namespace cli
