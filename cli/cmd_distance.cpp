// `nurbsgl distance MODEL --point X,Y,Z | --points FILE`: minimum distance from points to a trimmed
// NURBS model with the bounds of Krishnamurthy et al. §4 (queries/point_distance.h). JSON for
// --point: found, meets_tolerance, query, distance, bound, point, face, uv, seconds (and point_bound,
// on_trim_edge, candidates); for --points: {"points", "seconds", "not_found", "over_tolerance",
// "results": [...]} in input order. --points runs the batched projection (queries/point_batch.h: all
// points in one pass, on faithful grids within 1 GB or on coarse ones, every answer whose bound is
// over the tolerance refined in double);
// --per-point keeps one query per point. The rule: an answer meets the tolerance when it is found
// and its bound is within --tol x model size; exit 1 naming the counts when one does not.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/io/query_text.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "queries/batch_cache.h"
#include "queries/point_batch.h"
#include "queries/point_distance.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_distance_impl {

struct Options {
  std::string path, point, points;
  double rel_tolerance = 1e-5;
  queries::Search search = queries::Search::CoarseToFine;
  bool json = false;
  bool per_point = false;
  std::string boxes = "oriented";  ///< the batched projection's pyramid (point_batch.h)
  long long host_cells = -1;       ///< PointDistanceQuery::set_host_cells
  long long max_samples = 1LL << 22;  ///< per face grid
  bool no_cache = false;              ///< the batched preparation neither read from nor written to disk
  std::string engine = "auto";        ///< where the batched descent runs (queries::BatchEngine)
  PaperPreset preset;                 ///< --paper
};

/// The rule every answer is held to: found, and its bound within the requested tolerance T.
bool meets(const queries::PointDistance& d, double tolerance) {
  return d.found && d.meets_tolerance && d.bound <= tolerance * (1.0 + 1e-12);
}

nlohmann::json result_json(const queries::PointDistance& d, const glm::dvec3& query, double tolerance,
                           const std::vector<nurbs::TrimmedSurface>& faces, const std::string& uncertified) {
  if (!d.found)
    return {{"found", false}, {"meets_tolerance", false}, {"query", {query.x, query.y, query.z}}, {"distance", nullptr}};
  nlohmann::json j = {{"found", true},
          {"meets_tolerance", meets(d, tolerance)},
          {"query", {query.x, query.y, query.z}},
          {"distance", d.distance},
          {"bound", d.bound},
          {"point_bound", d.point_bound},
          {"point", {d.point.x, d.point.y, d.point.z}},
          {"face", d.face},
          {"face_id", d.face >= 0 ? faces[size_t(d.face)].face_id : -1},
          {"uv", {d.uv.x, d.uv.y}},
          {"on_trim_edge", d.on_trim_edge},
          {"candidates", d.candidates}};
  if (!uncertified.empty()) j["uncertified"] = uncertified;
  return j;
}

void run(const GlobalOptions& global, const Options& o) {
  if (o.point.empty() == o.points.empty()) throw BadInput("give exactly one of --point X,Y,Z and --points FILE");
  const LoadedModel loaded = load_model(o.path, "distance");
  const nurbs::Model& model = loaded.model;
  const double size = checked_model_size(model, o.path);
  const double limit = nurbs::coordinate_limit(nurbs::model_box(model));
  const std::vector<glm::dvec3> points =
      o.point.empty() ? nurbs::io::parse_points(read_input_text(o.points, "--points"), o.points, limit)
                      : std::vector{nurbs::io::parse_point(o.point, "--point", limit)};
  const std::string unit = unit_name(model);  // of every distance printed
  const auto faces = nurbs::world_faces(model);
  // The reader's edge gaps widen the bounds near them (nurbs/model_report.h): the query aims that
  // much below the tolerance, up to half of it, so that an answer beside a gap still meets it.
  const double query_tolerance =
      o.rel_tolerance * size - std::min(0.5 * o.rel_tolerance * size, loaded.report.largest_gap());
  auto gpu = start_gpu(global);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<queries::PointDistance> results;
  std::optional<queries::PointDistanceQuery> query;
  std::optional<queries::PreparedModel> prepared;
  std::optional<queries::PointBatch> batch;
  nlohmann::json cache_json;  // the batched preparation's disk cache
  std::future<std::pair<std::string, double>> cache_write;
  const bool batched = !o.points.empty() && !o.per_point;
  // auto: the descent in double on the CPU where the GL rasterizes on the CPU (the float pass there
  // runs on the same cores, slower than the twin); on the GPU otherwise.
  const std::string engine_used =
      o.engine != "auto" ? o.engine : (gpu->info().software_renderer() ? "cpu" : "gpu");
  try {
    if (batched) {  // grids and refinement: queries::prepare_batch_geometry, PointBatch::set_refine_tolerance
      const double tolerance = query_tolerance;
      // Faithful grids within 1 GB (and the memory free), else coarse ones; answers whose bound is
      // over T refined in double (point_batch.h), so no tolerance is beyond the float pass. Refused
      // before the work: a preparation larger than the memory this machine has free.
      const auto boxes = o.boxes == "aabb" ? queries::PointBoxes::Aabb : queries::PointBoxes::Oriented;
      const int side = std::min(gpu->info().max_texture_size, 4096);  // prepare_atlases' atlas side
      const long long free = available_memory(), faithful_bytes = 1LL << 30;
      queries::PreparedModel geometry = queries::prepare_batch_geometry(
          faces, tolerance, o.max_samples, side, boxes, free > 0 ? std::min(free, faithful_bytes) : faithful_bytes);
      const long long need = queries::estimate_batch_bytes(geometry, side, boxes);
      if (free > 0 && need > free)
        throw BadInput(fmt::format("--tol {:g}: the grids of {} faces need about {:.1f} GB, and this machine has "
                                   "{:.1f} GB free; a larger --tol",
                                   o.rel_tolerance, faces.size(), double(need) / 1e9, double(free) / 1e9));
      // The atlases and the pyramid from the disk cache when an earlier run made them (oriented
      // boxes; not with --dump, which wants the passes' textures), else built and stored there.
      const std::filesystem::path dir = queries::batch_cache_directory();
      const bool use_cache = !o.no_cache && boxes == queries::PointBoxes::Oriented && global.dump_dir.empty() &&
                             !dir.empty();
      cache_json = {{"used", use_cache}, {"hit", false}};
      std::string key;
      std::filesystem::path file;
      std::optional<queries::PointBatchState> state;
      if (use_cache) {
        const auto c0 = std::chrono::steady_clock::now();
        key = queries::batch_cache_key(o.path, geometry.grid_tolerance, o.max_samples, side, gpu->info().renderer);
        file = queries::batch_cache_file(dir, key);
        queries::BatchCacheRead read = queries::load_batch_state(file, key);
        if (read.state && !queries::state_matches(geometry, *read.state))
          read = {std::nullopt, "its atlases do not match the model's grids"};
        if (!read.problem.empty()) {  // rebuilt below and written over it
          fmt::print(stderr, "distance: warning: the cache file {} is not used: {}; the preparation is rebuilt\n",
                     file.string(), read.problem);
          cache_json["problem"] = read.problem;
        }
        state = std::move(read.state);
        cache_json["file"] = file.string();
        cache_json["hit"] = state.has_value();
        cache_json["read_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
      }
      if (state) {
        queries::restore_atlases(geometry, *state);
        prepared.emplace(std::move(geometry));
        batch.emplace(*gpu, *prepared, std::move(*state));
      } else {
        queries::prepare_atlases(*gpu, geometry, side);
        prepared.emplace(std::move(geometry));
        batch.emplace(*gpu, *prepared, boxes);
        if (use_cache)  // exported and written on another thread while the points are answered (the
                        // query reads the batch's atlases and pyramid, never changes them)
          cache_write = std::async(std::launch::async, [&b = *batch, file, key] {
            const auto c0 = std::chrono::steady_clock::now();
            std::string why = queries::save_batch_state(file, key, b.state_view());
            return std::pair{why, std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count()};
          });
      }
    } else {
      query.emplace(*gpu, faces, query_tolerance, o.max_samples, o.search);
      query->set_host_cells(o.host_cells);
    }
  } catch (const queries::GridLimitError& e) {
    throw BadInput(fmt::format("--tol {:g} --max-samples {}: {}", o.rel_tolerance, o.max_samples, e.what()));
  }
  gpu->finish();
  const auto t1 = std::chrono::steady_clock::now();
  if (batched) {
    // Long work shows on stderr: the preparation once it took a second, then a batch of many points
    // pass by pass (passes of at least 65536 points: llvmpipe spreads a pass's 64 x 64 tiles over
    // its threads, and a pass of 4096 points is one tile, one thread: 2x slower in all).
    const double prepared_s = std::chrono::duration<double>(t1 - t0).count();
    if (prepared_s >= 1.0)
      fmt::print(stderr, "distance: {} faces prepared in {:.1f} s; {} points\n", faces.size(), prepared_s,
                 points.size());
    Progress progress("distance", "points");
    batch->set_points_per_pass(std::max<size_t>(65536, (points.size() + 7) / 8));
    batch->set_progress([&](size_t done, size_t total) { progress.update((long long)done, (long long)total); });
    batch->set_engine(engine_used == "cpu" ? queries::BatchEngine::Cpu : queries::BatchEngine::Gpu);
    batch->set_refine_tolerance(query_tolerance);
    results = batch->query(points);
  } else {
    const bool progress = points.size() > 100 && isatty(STDERR_FILENO);
    for (size_t k = 0; k < points.size(); ++k) {
      results.push_back(query->query(points[k]));
      if (progress && k % 100 == 0) fmt::print(stderr, "\r[{}/{}] points", k, points.size());
    }
    if (progress) fmt::print(stderr, "\n");
  }
  const auto t2 = std::chrono::steady_clock::now();
  if (cache_write.valid()) {
    const auto [why, seconds] = cache_write.get();
    if (!why.empty()) fmt::print(stderr, "distance: the preparation is not cached: {}\n", why);
    cache_json["write_seconds"] = seconds;
  }
  const double prepare_s = std::chrono::duration<double>(t1 - t0).count();
  const double query_s = std::chrono::duration<double>(t2 - t1).count();
  const double tolerance = o.rel_tolerance * size;
  // An answer is a distance only with a face and finite figures: anything else is reported as not
  // found (exit 1), never printed as a distance.
  for (auto& r : results)
    if (r.found && (r.face < 0 || !std::isfinite(r.distance) || !std::isfinite(r.bound))) r.found = false;
  // The reader's doubts (nurbs/model_report.h): a face within reach whose edges lie off its surface
  // widens the bound by the gap; one whose trim could not be made valid, or a model that lost faces,
  // leaves the answer uncertified.
  const nurbs::FaceDoubts doubts(faces);
  const std::string model_reason = loaded.report.uncertified_reason(global.accept_partial);
  std::vector<std::string> reasons(results.size());
  size_t widened = 0;  // answers over the tolerance only by the reader's edge gaps
  for (size_t k = 0; k < results.size(); ++k) {
    auto& r = results[k];
    if (!r.found) continue;
    const nurbs::FaceDoubts::Verdict v = doubts.at(points[k], r.distance, r.bound);
    r.bound += v.widen;
    widened += v.widen > 0.0 && r.bound - v.widen <= tolerance * (1.0 + 1e-12) && r.bound > tolerance * (1.0 + 1e-12);
    reasons[k] = !model_reason.empty() ? model_reason : v.reason;
    if (!reasons[k].empty()) r.meets_tolerance = false;
  }
  size_t uncertified = 0;
  for (const std::string& why : reasons) uncertified += !why.empty();
  size_t not_found = 0, over = 0;
  for (size_t k = 0; k < results.size(); ++k)
    not_found += !results[k].found, over += results[k].found && reasons[k].empty() && !meets(results[k], tolerance);
  if (o.json) {
    nlohmann::json j;
    if (!o.point.empty()) {
      j = result_json(results.front(), points.front(), tolerance, faces, reasons.front());
      j["seconds"] = query_s;
    } else {
      j = {{"points", points.size()}, {"seconds", query_s}};
      j["not_found"] = not_found, j["over_tolerance"] = over;
    }
    j["uncertified"] = uncertified;
    add_model_json(j, loaded.report, global);
    j["prepare_seconds"] = prepare_s;
    // The switches of --paper as used; null where the batched projection does not use them.
    const auto one_at_a_time = [&](const nlohmann::json& v) { return batched ? nlohmann::json() : v; };
    j["preset"] = o.preset.json({{"per-point", !batched},
                                 {"search", one_at_a_time(search_name(o.search))},
                                 {"host-cells", one_at_a_time(batched ? 0 : query->host_cells_used())}});
    j["tolerance"] = tolerance;
    j["unit"] = unit;
    if (!o.points.empty()) j["path"] = batched ? "batched" : "per-point";
    if (batched) {
      const queries::PointBatchStats& st = batch->stats();
      j["fallbacks"] = st.fallbacks, j["boxes"] = o.boxes;
      j["grids"] = prepared->search == queries::Search::Faithful ? "faithful" : "coarse";
      j["refined_cells"] = st.refined_cells;
      j["engine"] = {{"requested", o.engine}, {"used", engine_used}, {"renderer", gpu->info().renderer}};
      // The points whose answer the CPU searched for, by reason (the rest: the GPU pass's cell,
      // finished in double), and those resolved inside a cell a trim edge crosses.
      j["cpu"] = {{"points", st.fallbacks + st.cut},
                  {"walk_cut_short", st.cut},
                  {"no_material_in_winning_cell", st.fallbacks},
                  {"share", st.points > 0 ? double(st.fallbacks + st.cut) / double(st.points) : 0.0}};
      j["trimmed_winners"] = st.trimmed;
      j["cache"] = cache_json;
      long long samples = 0;
      for (const auto& g : prepared->grids) samples += g.grid.samples();
      j["samples"] = samples;
    }
    if (o.point.empty())
      print_json_streamed(std::move(j), "results", results.size(),
                          [&](size_t k) { return result_json(results[k], points[k], tolerance, faces, reasons[k]); });
    else
      print_json(j);
  } else {
    o.preset.print_text();
    fmt::print("{} faces, model size {:.6g} {}, grids with K_e <= {:.3g}: prepared in {:.3f} s{}\n", faces.size(),
               size, unit, o.rel_tolerance * size, prepare_s,
               cache_json.is_object() && cache_json.value("hit", false) ? " (atlases and pyramid from the cache)" : "");
    for (size_t k = 0; k < points.size(); ++k) {
      const auto& r = results[k];
      if (!r.found) {
        fmt::print("point ({:.6g}, {:.6g}, {:.6g}): no surface point found (every cell trimmed away?)\n", points[k].x,
                   points[k].y, points[k].z);
        continue;
      }
      fmt::print(
          "point ({:.6g}, {:.6g}, {:.6g}): distance {:.9g} +- {:.3g}, closest ({:.9g}, {:.9g}, {:.9g}) within "
          "{:.3g}, face {} (u, v) = ({:.6g}, {:.6g}){}, {} {}\n",
          points[k].x, points[k].y, points[k].z, r.distance, r.bound, r.point.x, r.point.y, r.point.z, r.point_bound,
          r.face, r.uv.x, r.uv.y, r.on_trim_edge ? " on a trim edge" : "", r.candidates,
          batched ? "cells tested" : "candidate cells");
      if (!reasons[k].empty())
        fmt::print("  not certified: {}\n", reasons[k]);
      else if (!meets(r, tolerance))
        fmt::print("  its bound {:.3g} is over the tolerance {:.3g}\n", r.bound, tolerance);
    }
    std::vector<double> d;
    for (const auto& r : results)
      if (r.found) d.push_back(r.distance);
    std::sort(d.begin(), d.end());
    if (d.size() > 1)
      fmt::print("distances ({}): min {:.9g}, median {:.9g}, max {:.9g}\n", unit, d.front(), d[d.size() / 2], d.back());
    fmt::print("{} queries in {:.3f} s ({:.2f} ms each{})\n", points.size(), query_s,
               1e3 * query_s / double(points.size()),
               batched ? fmt::format(", batched, descent on the {}; {} searched again on the CPU, {} walks cut short and "
                                     "finished there",
                                     engine_used == "cpu" ? "CPU in double" : "GPU", batch->stats().fallbacks,
                                     batch->stats().cut)
                       : "");
  }
  report_profile(*gpu, global);
  require_certified(loaded.report, global);
  if (uncertified > 0)
    throw CommandFailed(fmt::format("{} of {} answers not certified: {}", uncertified, results.size(),
                                    *std::find_if(reasons.begin(), reasons.end(),
                                                  [](const std::string& w) { return !w.empty(); })));
  if (not_found == 0 && over > 0 && widened == over)
    throw CommandFailed(fmt::format("{} of {} answers with a bound over the tolerance {:.3g} only by the file's edges "
                                    "lying off their faces near them (the edge_gaps; a larger --tol)",
                                    over, results.size(), tolerance));
  if (not_found > 0 || over > 0)
    throw CommandFailed(fmt::format(
        "{} of {} answers not found, {} with a bound over the tolerance {:.3g} (a point far from the model: the "
        "float slack grows with its distance; a finer --tol or --per-point)",
        not_found, results.size(), over, tolerance));
}

}  // namespace cmd_distance_impl

void add_distance(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_distance_impl;
  auto* cmd = app.add_subcommand(
      "distance", "Minimum distance from points to a model with certified bounds (Krishnamurthy et al. 3.1-4)");
  auto o = std::make_shared<Options>();
  cmd->add_option("MODEL", o->path, "Model file (.igs/.iges/.bpt)")->required();
  cmd->add_option("--point", o->point, "The query point X,Y,Z");
  cmd->add_option("--points", o->points, "A file of points, x y z per line (spaces or commas; - reads stdin)");
  cmd->add_option("--tol", o->rel_tolerance, "K_e of the faces' grids, relative to the model size")
      ->check(relative_tolerance())
      ->capture_default_str();
  auto* search = add_search_option(cmd, o->search);
  auto* per_point =
      cmd->add_flag("--per-point", o->per_point,
                    "With --points: one query per point (the per-point path; --search applies) instead of the batched "
                    "projection (all points in one pass, on faithful grids)");
  auto* boxes = cmd->add_option("--boxes", o->boxes,
                  "Batched projection: the box pyramid the points descend, 'oriented' (each box in its cells' "
                  "tangent frame: far fewer cells tested) or 'aabb' (axis-aligned, as Krishnamurthy et al. 5.1)")
      ->check(CLI::IsMember({"oriented", "aabb"}))
      ->capture_default_str();
  auto* host_cells = cmd->add_option("--host-cells", o->host_cells,
                  "One query at a time: an atlas of at most this many cells is pruned on the CPU from one read-back "
                  "instead of the reduction, threshold and stream-reduction passes (the same cells); 0: on the GPU, "
                  "as the paper; -1: 65536 with coarse-to-fine, 0 with faithful")
      ->check(CLI::Range(-1LL, 1LL << 40))
      ->capture_default_str();
  cmd->add_option("--max-samples", o->max_samples,
                  "The most grid samples of one face; a face that needs more for --tol is refused (exit 2)")
      ->check(CLI::Range(4LL, 1LL << 30))
      ->capture_default_str();
  auto* no_cache = cmd->add_flag("--no-cache", o->no_cache,
                                 "Batched projection: neither read the atlases and pyramid from the preparation "
                                 "cache ($XDG_CACHE_HOME/nurbsgl, else ~/.cache/nurbsgl) nor store them there");
  auto* engine = cmd->add_option("--engine", o->engine,
                  "Batched projection: where the points descend the pyramid. gpu: the float pass; cpu: its twin in "
                  "double on every core (the same cells, bound and answers within it); auto: cpu when the GL "
                  "renderer rasterizes on the CPU (llvmpipe), gpu otherwise")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->capture_default_str();
  // --paper: the paper's point query, one point at a time (3.1: the batched projection is beyond
  // it), every face on its grid at the tolerance (3.1, 4), every atlas pruned by the GPU's
  // reduction and stream reduction (3.1).
  o->preset.add_flag(cmd, "Krishnamurthy et al.");
  o->preset.govern(per_point, o->per_point, true, "§3.1");
  govern_search(o->preset, search, o->search, "§3.1, §4");
  o->preset.govern(host_cells, o->host_cells, 0LL, "§3.1");
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([&global, o, search, boxes, host_cells, no_cache, engine] {
    o->preset.apply();
    // Options of the other path are refused, not ignored: --search and --host-cells steer one query
    // at a time, --boxes the batched projection.
    const bool batched = !o->points.empty() && !o->per_point;
    if (batched && search->count() > 0) throw BadInput("--search applies to one query at a time: add --per-point");
    if (batched && host_cells->count() > 0)
      throw BadInput("--host-cells applies to one query at a time: add --per-point");
    const std::string why = o->preset.paper() ? " (--paper sets --per-point)" : "";
    for (const CLI::Option* b : {boxes, no_cache, engine})
      if (!batched && b->count() > 0)
        throw BadInput(fmt::format("{} applies to the batched --points projection{}", b->get_name(), why));
    run(global, *o);
  });
}

}  // namespace cli
