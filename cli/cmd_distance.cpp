// `nurbsgl distance MODEL --point X,Y,Z | --points FILE`: minimum distance from points to a trimmed
// NURBS model with the bounds of Krishnamurthy et al. §4, through the library's front door
// queries::PointQuery (queries/distance/point_query.h: preparation, refusals, cache, engine, answers). JSON for
// --point: found, meets_tolerance, query, distance, bound, point, normal, face, uv, seconds (and point_bound,
// on_trim_edge, candidates); for --points: {"points", "seconds", "not_found", "over_tolerance",
// "results": [...]} in input order. --points runs the batched projection (queries/distance/point_batch.h: all
// points in one pass, on faithful grids within 1 GB or on coarse ones, every answer whose bound is
// over the tolerance refined in double);
// --per-point keeps one query per point. The rule (queries::meets_tolerance): an answer meets the
// tolerance when it is found and its bound is within --tol x model size; exit 1 naming the counts
// when one does not.
#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <span>

#include "cli/commands.h"
#include "cli/deviation_outputs.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/query_text.h"
#include "nurbs/model_ops.h"
#include "nurbs/paper_switch.h"
#include "queries/distance/point_query.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_distance_impl {

struct Options {
  std::string path, point, points;
  queries::PointQueryOptions query;
  bool json = false;
  std::string boxes = "oriented";  ///< the batched projection's pyramid (point_batch.h)
  std::string engine = "auto";     ///< where the batched descent runs (queries::EngineChoice)
  std::string point_path = "auto";  ///< many points: certified mesh or grids (queries::PointPath)
  bool no_cache = false;
  PaperPreset preset;  ///< --paper
  // The scan's deviation report (deviation_outputs.h).
  std::vector<double> within;  ///< --within, model units
  std::string ply, histogram;
  std::string csv;  ///< --csv: one row per point, instead of the JSON's results
  [[nodiscard]] bool report() const { return query.signed_distance || !within.empty() || !ply.empty() || !histogram.empty(); }
};

nlohmann::json result_json(const queries::PointQueryResult& r, size_t k, const glm::dvec3& query,
                           const std::vector<nurbs::TrimmedSurface>& faces) {
  const queries::PointDistance& d = r.answers[k];
  if (!d.found)
    return {{"found", false},
            {"meets_tolerance", false},
            {"query", {query.x, query.y, query.z}},
            {"distance", nullptr},
            {"limited_by_file", false},
            {"reason", r.reason(k)}};
  nlohmann::json j = {{"found", true},
                      {"meets_tolerance", queries::meets_tolerance(d, r.tolerance)},
                      {"query", {query.x, query.y, query.z}},
                      {"distance", d.distance},
                      {"bound", d.bound},
                      {"point_bound", d.point_bound},
                      {"point", {d.point.x, d.point.y, d.point.z}},
                      {"normal", {r.normals[k].x, r.normals[k].y, r.normals[k].z}},
                      {"face", d.face},
                      {"face_id", d.face >= 0 ? faces[size_t(d.face)].face_id : -1},
                      {"uv", {d.uv.x, d.uv.y}},
                      {"on_trim_edge", d.on_trim_edge},
                      {"candidates", d.candidates}};
  if (!r.signed_distance.empty()) j["signed_distance"] = r.signed_distance[k];
  if (!r.reasons[k].empty()) j["uncertified"] = r.reasons[k];
  const queries::FileLimit& l = r.file_limits[k];
  j["limited_by_file"] = l.limited;
  if (l.widen > 0.0) j["file_widen"] = l.widen, j["file_gap"] = l.gap, j["gap_face"] = l.face, j["gap_face_id"] = l.face_id;
  if (!r.reason(k).empty()) j["reason"] = r.reason(k);
  return j;
}

/// One row per point (the fields of result_json; numbers in their shortest exact form), written to a
/// temporary file and renamed.
void write_csv(const std::string& path, const queries::PointQueryResult& r, std::span<const glm::dvec3> points) {
  const std::string header =
      std::string("point,x,y,z,found,meets_tolerance,distance,bound,point_bound,closest_x,closest_y,closest_z,"
                  "normal_x,normal_y,normal_z,face,u,v") +
      (r.signed_distance.empty() ? "" : ",signed_distance") + ",limited_by_file,file_gap,gap_face,reason\n";
  write_rows(path, header, points.size(), [&](fmt::memory_buffer& buf, size_t k) {
    const auto out = std::back_inserter(buf);
    const queries::PointDistance& d = r.answers[k];
    fmt::format_to(out, "{},{},{},{},{},{}", k, points[k].x, points[k].y, points[k].z, d.found ? "true" : "false",
                   r.meets(k) ? "true" : "false");
    if (d.found)
      fmt::format_to(out, ",{},{},{},{},{},{},{},{},{},{},{},{}", d.distance, d.bound, d.point_bound, d.point.x,
                     d.point.y, d.point.z, r.normals[k].x, r.normals[k].y, r.normals[k].z, d.face, d.uv.x, d.uv.y);
    else
      fmt::format_to(out, ",,,,,,,,,,-1,,");
    if (!r.signed_distance.empty()) fmt::format_to(out, ",{}", r.signed_distance[k]);
    const queries::FileLimit& l = r.file_limits[k];
    if (l.widen > 0.0)
      fmt::format_to(out, ",{},{},{}", l.limited ? "true" : "false", l.gap, l.face);
    else
      fmt::format_to(out, ",false,,");
    buf.push_back(',');
    append_csv_quoted(buf, r.reason(k));
    buf.push_back('\n');
  });
}

/// The deviation report of a scan: its JSON (into j, when not null), the PLY and the histogram.
void write_report(const queries::PointQueryResult& r, std::span<const glm::dvec3> points, const Options& o,
                  const std::string& unit, nlohmann::json* j) {
  const queries::DeviationReport report = queries::deviation_report(r, o.within);
  if (!o.ply.empty()) {
    const double green = o.within.empty() ? r.tolerance : *std::min_element(o.within.begin(), o.within.end());
    nurbs::io::write_mesh_file(o.ply, queries::deviation_cloud(points, report, green));
  }
  if (!o.histogram.empty()) write_histogram(o.histogram, report, o.within, unit);
  if (!j) return print_deviation(report, unit);
  (*j)["deviation"] = deviation_json(report);
  if (!r.signed_distance.empty())
    (*j)["deviation"]["sides"] = {
        {"by_normal", r.sides.by_normal}, {"by_rays", r.sides.by_rays}, {"unsure", r.sides.unsure}, {"hidden", r.sides.hidden}};
}

/// The mesh path's figures in the JSON object.
void add_mesh_json(nlohmann::json& j, const queries::MeshDistance& m) {
  j["mesh"] = {{"triangles", m.triangles()},
               {"eps", m.eps()},
               {"tessellate_seconds", m.tessellate_seconds()},
               {"build_seconds", m.build_seconds()}};
}

/// The batched path's figures in the JSON object.
void add_batch_json(nlohmann::json& j, const queries::PointQuery& q, const Options& o) {
  const queries::PointBatchStats& st = q.stats();
  j["fallbacks"] = st.fallbacks, j["boxes"] = o.boxes;
  j["grids"] = q.grids() == queries::Search::Faithful ? "faithful" : "coarse";
  j["refined_cells"] = st.refined_cells;
  j["engine"] = {{"requested", o.engine}, {"used", queries::engine_name(q.engine())}};
  // The points whose answer the CPU searched for, by reason (the rest: the GPU pass's cell,
  // finished in double), and those resolved inside a cell a trim edge crosses.
  j["cpu"] = {{"points", st.fallbacks + st.cut},
              {"walk_cut_short", st.cut},
              {"no_material_in_winning_cell", st.fallbacks},
              {"share", st.points > 0 ? double(st.fallbacks + st.cut) / double(st.points) : 0.0}};
  j["trimmed_winners"] = st.trimmed;
  const queries::PointQueryCache& c = q.cache();
  j["cache"] = {{"used", c.used}, {"hit", c.hit}};
  if (c.used) j["cache"]["file"] = c.file.string(), j["cache"]["read_seconds"] = c.read_seconds;
  if (!c.problem.empty()) j["cache"]["problem"] = c.problem;
  if (c.write_seconds >= 0) j["cache"]["write_seconds"] = c.write_seconds;
  j["samples"] = q.samples();
}

void print_text(const queries::PointQuery& q, const queries::PointQueryResult& r, std::span<const glm::dvec3> points,
                const std::string& unit, const Options& o) {
  o.preset.print_text();
  if (const queries::MeshDistance* m = q.mesh())
    fmt::print("{} faces, model size {:.6g} {}, certified mesh of {} triangles within {:.3g}: prepared in {:.3f} s\n",
               q.faces().size(), q.model_size(), unit, m->triangles(), m->eps(), q.prepare_seconds());
  else
    fmt::print("{} faces, model size {:.6g} {}, grids with K_e <= {:.3g}: prepared in {:.3f} s{}\n", q.faces().size(),
               q.model_size(), unit, r.tolerance, q.prepare_seconds(),
               q.cache().hit ? " (atlases and pyramid from the cache)" : "");
  for (size_t k = 0; k < (o.csv.empty() ? points.size() : 0); ++k) {
    const auto& a = r.answers[k];
    if (!a.found) {
      fmt::print("point ({:.6g}, {:.6g}, {:.6g}): no surface point found (every cell trimmed away?)\n", points[k].x,
                 points[k].y, points[k].z);
      continue;
    }
    fmt::print("point ({:.6g}, {:.6g}, {:.6g}): distance {:.9g} +- {:.3g}, closest ({:.9g}, {:.9g}, {:.9g}) within "
               "{:.3g}, face {} (u, v) = ({:.6g}, {:.6g}){}, {} {}\n",
               points[k].x, points[k].y, points[k].z, a.distance, a.bound, a.point.x, a.point.y, a.point.z,
               a.point_bound, a.face, a.uv.x, a.uv.y, a.on_trim_edge ? " on a trim edge" : "", a.candidates,
               q.meshed() ? "triangles tested" : q.batched() ? "cells tested" : "candidate cells");
    if (!r.reasons[k].empty())
      fmt::print("  not certified: {}\n", r.reasons[k]);
    else if (r.file_limits[k].limited)
      fmt::print("  certified to the file's precision: {}\n", r.over_reasons[k]);
    else if (!r.over_reasons[k].empty())
      fmt::print("  {}\n", r.over_reasons[k]);
  }
  std::vector<double> d;
  for (const auto& a : r.answers)
    if (a.found) d.push_back(a.distance);
  std::sort(d.begin(), d.end());
  if (d.size() > 1)
    fmt::print("distances ({}): min {:.9g}, median {:.9g}, max {:.9g}\n", unit, d.front(), d[d.size() / 2], d.back());
  fmt::print("{} queries in {:.3f} s ({:.2f} ms each{})\n", points.size(), r.seconds,
             1e3 * r.seconds / double(points.size()),
             q.meshed()    ? std::string(", certified mesh")
             : q.batched() ? fmt::format(", batched, descent on the {}; {} searched again on the CPU, {} walks cut "
                                         "short and finished there",
                                         q.engine() == queries::BatchEngine::Cpu ? "CPU in double" : "GPU",
                                         q.stats().fallbacks, q.stats().cut)
                           : std::string());
}

void run(const GlobalOptions& global, const Options& o) {
  if (o.point.empty() == o.points.empty()) throw BadInput("give exactly one of --point X,Y,Z and --points FILE");
  const LoadedModel loaded = load_model(o.path, "distance");
  const double limit = nurbs::coordinate_limit(nurbs::model_box(loaded.model));
  const std::vector<glm::dvec3> points =
      o.point.empty() ? read_points_file(o.points, "--points", limit).points
                      : std::vector{nurbs::io::parse_point(o.point, "--point", limit)};
  const std::string unit = unit_name(loaded.model);  // of every distance printed
  if (!o.histogram.empty()) check_histogram_python();
  if (!o.csv.empty()) check_output(o.csv, "--csv");
  auto gpu = start_gpu(global);
  queries::PointQueryOptions q = o.query;
  q.per_point = q.per_point || o.points.empty();
  q.boxes = o.boxes == "aabb" ? queries::PointBoxes::Aabb : queries::PointBoxes::Oriented;
  q.engine = queries::engine_choice(o.engine);
  q.path = queries::point_path(o.point_path);
  q.cache = !o.no_cache;
  q.accept_partial = global.accept_partial;
  const CommandProgress watch = command_progress("distance", "points");
  q.progress = watch.progress, q.log = watch.log;
  queries::PointQuery query(*gpu, loaded, q);
  const queries::PointQueryResult r = query.query(points);
  if (!o.csv.empty()) write_csv(o.csv, r, points);
  if (o.json) {
    nlohmann::json j;
    if (!o.point.empty()) {
      j = result_json(r, 0, points.front(), query.faces());
      j["seconds"] = r.seconds;
    } else {
      j = {{"points", points.size()}, {"seconds", r.seconds}, {"not_found", r.not_found},
           {"over_tolerance", r.over_tolerance}};
    }
    j["uncertified"] = r.uncertified;
    if (o.point.empty()) j["limited_by_file"] = r.limited_by_file;
    j["strict"] = global.strict;
    add_model_json(j, loaded.report, global);
    j["prepare_seconds"] = query.prepare_seconds();
    // The switches of --paper as used; null where the batched projection does not use them.
    const bool batched = query.batched() || query.meshed();
    const auto one_at_a_time = [&](const nlohmann::json& v) { return batched ? nlohmann::json() : v; };
    j["preset"] = o.preset.json({{"per-point", !batched},
                                 {"search", one_at_a_time(search_name(q.search))},
                                 {"host-cells", one_at_a_time(query.host_cells_used())}});
    j["tolerance"] = r.tolerance, j["unit"] = unit;
    if (!o.points.empty()) j["path"] = query.meshed() ? "mesh" : batched ? "batched" : "per-point";
    if (!query.mesh_refused().empty()) j["mesh_refused"] = query.mesh_refused();
    if (query.meshed()) add_mesh_json(j, *query.mesh());
    if (query.batched()) add_batch_json(j, query, o), j["engine"]["renderer"] = gpu->info().renderer;
    if (o.report()) write_report(r, points, o, unit, &j);
    if (!o.csv.empty())
      j["results_file"] = o.csv, print_json(j);
    else if (o.point.empty())
      print_json_streamed(std::move(j), "results", points.size(),
                          [&](size_t k) { return result_json(r, k, points[k], query.faces()); });
    else
      print_json(j);
  } else {
    print_text(query, r, points, unit, o);
    if (o.report()) write_report(r, points, o, unit, nullptr);
  }
  report_profile(*gpu, global);
  // Once, for people: the file's precision where it sets bounds over the tolerance.
  if (const std::string note = r.file_precision(); !note.empty()) watch.log(note);
  if (const std::string why = r.failure(global.strict); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_distance_impl

void add_distance(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_distance_impl;
  auto* cmd = app.add_subcommand(
      "distance", "Minimum distance from points to a model with certified bounds (Krishnamurthy et al. 3.1-4)");
  auto o = std::make_shared<Options>();
  cmd->add_option("MODEL", o->path, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option("--point", o->point, "The query point X,Y,Z");
  cmd->add_option("--points", o->points,
                  "A file of points: x y z per line (spaces, tabs, commas or semicolons; a header line may name the "
                  "columns), a PLY (ascii or binary) or a NumPy .npy N x 3 array, told apart by content; "
                  "- reads stdin");
  cmd->add_option("--tol", o->query.tolerance, "K_e of the faces' grids, relative to the model size")
      ->check(relative_tolerance())
      ->capture_default_str();
  auto* search = add_search_option(cmd, o->query.search);
  auto* per_point =
      cmd->add_flag("--per-point", o->query.per_point,
                    "With --points: one query per point (the per-point path; --search applies) instead of the batched "
                    "projection (all points in one pass, on faithful grids)");
  auto* boxes = cmd->add_option("--boxes", o->boxes,
                  "Batched projection: the box pyramid the points descend, 'oriented' (each box in its cells' "
                  "tangent frame: far fewer cells tested) or 'aabb' (axis-aligned, as Krishnamurthy et al. 5.1)")
      ->check(CLI::IsMember({"oriented", "aabb"}))
      ->capture_default_str();
  auto* host_cells = cmd->add_option("--host-cells", o->query.host_cells,
                  "One query at a time: an atlas of at most this many cells is pruned on the CPU from one read-back "
                  "instead of the reduction, threshold and stream-reduction passes (the same cells); 0: on the GPU, "
                  "as the paper; -1: 65536 with coarse-to-fine, 0 with faithful")
      ->check(CLI::Range(-1LL, 1LL << 40))
      ->capture_default_str();
  cmd->add_option("--max-samples", o->query.max_samples,
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
  auto* path = cmd->add_option("--path", o->point_path,
                  "With --points: mesh = the faces tessellated within the tolerance in guaranteed mode and every "
                  "point's closest triangle found in Embree's BVH (beyond the paper; each bound the mesh's proven "
                  "distance to the faces); batched = the grids' box pyramid (--boxes, --engine, --no-cache); auto: "
                  "mesh, unless one of those three is given or the mesh cannot be made")
      ->check(CLI::IsMember({"auto", "mesh", "batched"}))
      ->capture_default_str();
  // --paper: queries::PointQueryOptions::paper.
  const queries::PointQueryOptions paper = o->query.paper();
  const auto section = [](const char* option) {
    return nurbs::paper_section(queries::PointQueryOptions::paper_switches(), option);
  };
  o->preset.add_flag(cmd, "Krishnamurthy et al.");
  o->preset.govern(per_point, o->query.per_point, paper.per_point, section("per-point"));
  govern_search(o->preset, search, o->query.search, section("search"));
  o->preset.govern(host_cells, o->query.host_cells, paper.host_cells, section("host-cells"));
  cmd->add_flag("--signed", o->query.signed_distance,
                "Also the signed distance, negative inside the model's solids, the part being their union (by the outward "
                "normal at the closest point, by rays at each solid where that cannot tell); refused for a model whose "
                "bodies are not stated closed");
  cmd->add_option("--within", o->within,
                  "Tolerances (model units, comma-separated) whose share of points the deviation report gives, each "
                  "also counted with the answers' bounds (certainly / possibly within)")
      ->delimiter(',')
      ->check(positive_number("a positive distance"));
  cmd->add_option("--ply", o->ply,
                  "Write the points coloured by deviation (green within the first --within, else the tolerance; "
                  "yellow to red outside, cyan to blue inside) as PLY, with the per-point value 'deviation'")
      ->check(extension_is(".ply"));
  cmd->add_option("--histogram", o->histogram,
                  "Write the deviation histogram with the --within bands and their shares as PNG (python3 with "
                  "matplotlib: $NURBSGL_PYTHON, else the interpreter found at build time)")
      ->check(extension_is(".png"));
  cmd->add_option("--csv", o->csv,
                  "Write one row per point (the fields of the JSON's results) as CSV; the JSON then names the file "
                  "(results_file) instead of listing the results, and the text lists no points")
      ->check(extension_is(".csv"));
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([&global, o, search, boxes, host_cells, no_cache, engine, path] {
    o->preset.apply();
    // Options of the other path are refused, not ignored: --search and --host-cells steer one query
    // at a time, --boxes the batched projection.
    const bool batched = !o->points.empty() && !o->query.per_point;
    if (batched && search->count() > 0) throw BadInput("--search applies to one query at a time: add --per-point");
    if (batched && host_cells->count() > 0)
      throw BadInput("--host-cells applies to one query at a time: add --per-point");
    const std::string why = o->preset.paper() ? " (--paper sets --per-point)" : "";
    for (const CLI::Option* b : {boxes, no_cache, engine, path})
      if (!batched && b->count() > 0)
        throw BadInput(fmt::format("{} applies to the batched --points projection{}", b->get_name(), why));
    for (const CLI::Option* b : {boxes, no_cache, engine}) {
      if (b->count() > 0 && o->point_path == "mesh")
        throw BadInput(fmt::format("{} applies to the grids' pyramid, not to --path mesh", b->get_name()));
      if (b->count() > 0) o->point_path = "batched";
    }
    run(global, *o);
  });
}

}  // namespace cli
