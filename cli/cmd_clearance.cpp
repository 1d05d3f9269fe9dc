// `nurbsgl clearance A B [--move-b DX,DY,DZ] [--rotate-b AX,AY,AZ,DEG]`: minimum distance between two
// models with the bound K_a + K_b through the library's front door queries::ClearancePair
// (queries/distance/clearance_pair.h), within --tol x the larger model size (found and
// meets_tolerance in JSON; exit 1 when the bound is over it). B is first rotated by DEG degrees about
// the axis (AX, AY, AZ) through the origin, then moved. JSON: distance, bound, point_bound, point_a,
// point_b, face_a, face_b, uv_a, uv_b, seconds; with --timings the passes of the query. `--motion FILE` runs
// one query per line of FILE (DX DY DZ AX AY AZ DEG: B rotated, then moved), B's hierarchy refitted
// each time (the paper's Fig. 16): JSON {"frames", "prepare_seconds", "tolerance", "results": [...]}.
// `engine` (JSON: requested, used, cpu_queries, gpu_queries): small models run on the CPU alone
// (queries::clearance_cpu, no GL context), others on the GPU (--engine).
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/clearance_json.h"
#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/model_ops.h"
#include "nurbs/paper_switch.h"
#include "nurbs/rigid_motion.h"
#include "queries/distance/clearance_pair.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_clearance_impl {

struct Options {
  std::string a, b, move, rotate, motion;
  queries::ClearanceOptions query;
  std::string first_stage = "hierarchy";
  std::string upper = "auto";
  std::string face_cull = "boxes";
  std::string engine = "auto";
  bool json = false, timings = false;
  PaperPreset preset;  ///< --paper
};

/// `count` finite numbers separated by commas or spaces; `what` names the option in errors.
std::vector<double> numbers(const std::string& text, size_t count, const std::string& what) {
  std::vector<double> v(count);
  if (!nurbs::parse_numbers(text, int(count), v.data()))
    throw BadInput(fmt::format("{}: '{}' is not {} finite numbers", what, text, count));
  return v;
}

/// nurbs::rigid_motion with a move of at most `limit` in every coordinate; `what` names the source
/// in errors.
glm::dmat4 rigid_motion(const glm::dvec3& t, const glm::dvec3& axis, double deg, double limit,
                        const std::string& what) {
  if (!nurbs::within_coordinate_limit(t, limit))
    throw BadInput(fmt::format("{}: the move ({}, {}, {}) is beyond {:.3g}, the coordinates double arithmetic "
                               "carries for these models",
                               what, t.x, t.y, t.z, limit));
  try {
    return nurbs::rigid_motion(t, axis, deg);
  } catch (const std::invalid_argument& e) {
    throw BadInput(fmt::format("{}: {}", what, e.what()));
  }
}

/// The motions of B: one from --rotate-b / --move-b, or one per line of --motion FILE; moves of at
/// most `limit` in every coordinate.
std::vector<glm::dmat4> motions(const Options& o, double limit) {
  if (o.motion.empty()) {
    glm::dvec3 t(0.0), axis(0.0, 0.0, 1.0);
    double deg = 0.0;
    if (!o.rotate.empty()) {
      const auto r = numbers(o.rotate, 4, "--rotate-b");
      axis = {r[0], r[1], r[2]};
      deg = r[3];
      if (axis == glm::dvec3(0.0)) throw BadInput("--rotate-b: the axis is zero");
    }
    if (!o.move.empty()) {
      const auto v = numbers(o.move, 3, "--move-b");
      t = {v[0], v[1], v[2]};
      (void)rigid_motion(t, axis, 0.0, limit, "--move-b");
    }
    return {rigid_motion(t, axis, deg, limit, o.rotate.empty() ? "--move-b" : "--rotate-b")};
  }
  if (!o.move.empty() || !o.rotate.empty()) throw BadInput("--motion cannot be combined with --move-b or --rotate-b");
  std::istringstream in(read_input_text(o.motion, "--motion"));
  std::vector<glm::dmat4> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t\r")] == '#') continue;
    const std::string where = fmt::format("{}: line {}", o.motion, n);
    const auto v = numbers(line, 7, where + " (DX DY DZ AX AY AZ DEG)");
    out.push_back(rigid_motion({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6], limit, where));
  }
  if (out.empty()) throw BadInput(fmt::format("--motion {}: no frames", o.motion));
  return out;
}

long long samples(const queries::PreparedModel& m) {
  long long n = 0;
  for (const auto& g : m.grids) n += g.grid.samples();
  return n;
}

/// The preparation of both models: time per stage, grid tolerance and samples evaluated.
nlohmann::json prepare_json(const queries::PreparedModel& a, const queries::PreparedModel& b) {
  return {{"bounds_seconds", a.bounds_seconds + b.bounds_seconds},
          {"grids_seconds", a.grids_seconds + b.grids_seconds},
          {"atlas_seconds", a.atlas_seconds + b.atlas_seconds},
          {"grid_tolerance", std::max(a.grid_tolerance, b.grid_tolerance)},
          {"samples", samples(a) + samples(b)}};
}

/// The JSON fields both forms share: preparation, face cull, engine, preset, models.
void add_pair_json(nlohmann::json& j, const queries::ClearancePair& pair, const Options& o, const LoadedModel& la,
                   const nurbs::ModelReport& report_b, const GlobalOptions& global) {
  const queries::ClearanceOptions& q = pair.options();
  j["prepare_seconds"] = pair.prepare_seconds();
  j["prepare"] = prepare_json(pair.prepared_a(), pair.prepared_b());
  const queries::FaceCullFigures& f = pair.face_cull();
  j["face_cull"] = {{"method", o.face_cull}};
  if (f.on)
    j["face_cull"].update({{"faces_a", f.faces_a},
                           {"faces_b", f.faces_b},
                           {"face_pairs", f.face_pairs},
                           {"upper", f.upper},
                           {"seconds", f.seconds}});
  j["engine"] = {{"requested", o.engine},
                 {"used", pair.engine_used()},
                 {"cpu_queries", pair.cpu_queries()},
                 {"gpu_queries", pair.gpu_queries()}};
  // The switches of --paper as used; null where this run does not use them (the GPU descent's on
  // the CPU engine, --voxels without the voxel stage).
  const auto on_gpu = [&](const nlohmann::json& v) { return pair.gpu_queries() > 0 ? v : nlohmann::json(); };
  const bool c2f = q.search == queries::Search::CoarseToFine;
  j["preset"] = o.preset.json(
      {{"engine", pair.engine_used()},
       {"voxels", q.voxel_stage ? nlohmann::json(q.voxels) : nlohmann::json()},
       {"reduce-block", on_gpu(q.limits.reduce_block)},
       {"compact-fanout", on_gpu(q.limits.compact_fanout)},
       {"host-pairs", on_gpu(queries::host_pairs_used(q.limits, c2f))},
       {"start-pairs", on_gpu(q.limits.start_pairs)},
       {"gpu-upper", on_gpu(queries::upper_from_samples(q.limits, c2f) ? "samples" : "boxes")}});
  j["tolerance"] = pair.tolerance();
  j["unit"] = unit_name(pair.model_a());
  j["model_a"] = model_json(la.report, global);
  j["model_b"] = model_json(report_b, global);
}

void print_text(const queries::ClearancePair& pair, const queries::ClearanceAnswer& answer) {
  const queries::Clearance& c = answer.clearance;
  fmt::print(
      "clearance {:.9g} +- {:.3g} {} between face {} of A at ({:.6g}, {:.6g}, {:.6g}) and face {} of B at "
      "({:.6g}, {:.6g}, {:.6g}); each point within {:.3g} of its surface's nearest point to the other\n",
      c.distance, c.bound, unit_name(pair.model_a()), c.face_a, c.point_a.x, c.point_a.y, c.point_a.z, c.face_b,
      c.point_b.x, c.point_b.y, c.point_b.z, c.point_bound());
  const queries::PreparedModel &a = pair.prepared_a(), &b = pair.prepared_b();
  if (pair.cpu_queries() > 0)
    fmt::print("prepared {} of {} faces of A, {} of {} of B in {:.3f} s (coarse grids); query {:.3f} s on the CPU, "
               "{} cells refined in {} rounds\n",
               a.faces.size(), pair.faces_a(), b.faces.size(), pair.faces_b(), pair.prepare_seconds(), answer.seconds,
               c.refined_cells, c.rounds);
  else
    fmt::print("prepared {} of {} faces of A, {} of {} of B in {:.3f} s (grids with K_e <= {:.3g}); query {:.3f} s, "
               "{} levels, {} leaf cell pairs\n",
               a.faces.size(), pair.faces_a(), b.faces.size(), pair.faces_b(), pair.prepare_seconds(),
               pair.grid_tolerance(), answer.seconds, c.pairs_per_level.size(), c.leaf_pairs);
  if (c.intersecting)
    fmt::print("the models intersect: faces {} and {} meet at ({:.9g}, {:.9g}, {:.9g})\n", c.face_a, c.face_b,
               c.intersection.x, c.intersection.y, c.intersection.z);
  if (!answer.reason.empty())
    fmt::print("not certified: {}\n", answer.reason);
  else if (!answer.meets())
    fmt::print("the bound {:.3g} is over the tolerance {:.3g}\n", c.bound, answer.tolerance);
}

/// --timings: the pairs per level, the GPU passes, the CPU refinement and the whole query on stderr.
void print_timings(const queries::ClearancePair& pair, const queries::ClearanceAnswer& answer) {
  const queries::Clearance& c = answer.clearance;
  std::string levels;
  for (long long n : c.pairs_per_level) levels += fmt::format(" {}", n);
  std::fflush(stdout);
  fmt::print(stderr,
             "pairs per level:{}\n{}cpu refinement: {} rounds, {} cells, {:.3f} ms\nquery: {:.3f} ms in all (GPU "
             "passes, CPU refinement, read-backs)\n",
             levels, pair.gpu() ? pair.gpu()->profiler().table() : "no GPU passes (the search ran on the CPU)\n",
             c.rounds, c.refined_cells, 1e3 * c.refine_seconds, 1e3 * answer.seconds);
}

void run(const GlobalOptions& global, const Options& o) {
  // B read again only when it is another file.
  const LoadedModel la = load_model(o.a, "clearance");
  std::optional<LoadedModel> lb;
  if (o.b != o.a) lb.emplace(load_model(o.b, "clearance"));
  const nurbs::ModelReport& report_b = lb ? lb->report : la.report;
  queries::ClearanceOptions q = o.query;
  q.engine = queries::engine_choice(o.engine);
  q.voxel_stage = o.first_stage == "voxels";
  q.face_cull = o.face_cull == "boxes";
  using Upper = queries::ClearanceLimits::Upper;
  q.limits.upper = o.upper == "boxes" ? Upper::Boxes : o.upper == "samples" ? Upper::Samples : Upper::Auto;
  q.accept_partial = global.accept_partial;
  q.profile_queries = o.timings;
  queries::ClearancePair pair(la, lb ? &*lb : nullptr, q, nullptr, [&global] { return start_gpu(global); });
  const std::vector<glm::dmat4> frames = motions(o, pair.move_limit());
  pair.prepare(frames);
  if (!o.json) o.preset.print_text();
  if (!o.motion.empty()) {
    nlohmann::json results = nlohmann::json::array();
    size_t over = 0, uncertified = 0, limited = 0;
    std::string last_reason, last_limit;
    Progress progress("clearance", "frames");
    for (size_t k = 0; k < frames.size(); ++k) {
      const queries::ClearanceAnswer answer = pair.query(frames[k]);
      const queries::Clearance& c = answer.clearance;
      if (!c.found) throw CommandFailed(fmt::format("frame {}: no pair of surface points found", k + 1));
      results.push_back(clearance_answer_json(answer, q.voxels));
      if (!answer.reason.empty()) last_reason = answer.reason, ++uncertified;
      over += answer.reason.empty() && !answer.meets() && !answer.limited_by_file();
      if (answer.limited_by_file()) ++limited, last_limit = answer.file_precision();
      progress.update((long long)k + 1, (long long)frames.size());
      if (!o.json)
        fmt::print("frame {}: clearance {:.9g} +- {:.3g} (faces {}, {}){} in {:.1f} ms\n", k + 1, c.distance, c.bound,
                   c.face_a, c.face_b, c.intersecting ? ", intersecting" : "", 1e3 * answer.seconds);
    }
    if (o.json) {
      nlohmann::json j = {{"frames", frames.size()}, {"uncertified", uncertified}, {"results", results}};
      add_pair_json(j, pair, o, la, report_b, global);
      print_json(j);
    }
    if (pair.gpu()) report_profile(*pair.gpu(), global);
    require_certified(la.report, global);
    require_certified(report_b, global);
    if (limited > 0)
      fmt::print(stderr, "clearance: {} of {} frames certified to the file's precision (limited_by_file); the last: {}\n",
                 limited, frames.size(), last_limit);
    if (uncertified > 0)
      throw CommandFailed(fmt::format("{} of {} frames not certified: {}", uncertified, frames.size(), last_reason));
    if (global.strict && limited > 0)
      throw CommandFailed(fmt::format("{} of {} frames over the tolerance only by the file's precision (strict)",
                                      limited, frames.size()));
    if (over > 0)
      throw CommandFailed(fmt::format("{} of {} frames with a bound over the tolerance {:.3g}", over, frames.size(),
                                      pair.tolerance()));
    return;
  }
  const queries::ClearanceAnswer answer = pair.query(frames.front());
  if (!answer.clearance.found) throw CommandFailed(answer.failure());
  if (o.json) {
    nlohmann::json j = clearance_answer_json(answer, q.voxels);
    add_pair_json(j, pair, o, la, report_b, global);
    print_json(j);
  } else {
    print_text(pair, answer);
  }
  if (o.timings)
    print_timings(pair, answer);
  else if (pair.gpu())
    report_profile(*pair.gpu(), global);
  require_certified(la.report, global);
  require_certified(report_b, global);
  if (answer.limited_by_file()) fmt::print(stderr, "clearance: {}\n", answer.file_precision());
  if (const std::string why = answer.failure(global.strict); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_clearance_impl

void add_clearance(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_clearance_impl;
  auto* cmd = app.add_subcommand("clearance",
                                 "Minimum distance between two models with a certified bound "
                                 "(Krishnamurthy et al. 5.1-5.3)");
  auto o = std::make_shared<Options>();
  cmd->add_option("A", o->a, "First model file")->required();
  cmd->add_option("B", o->b, "Second model file (may be the same file)")->required();
  cmd->add_option("--body-a", o->query.body_a,
                  "Only this body of A: its index or name as `nurbsgl info A` lists them (a part of an assembly)");
  cmd->add_option("--body-b", o->query.body_b, "Only this body of B (index or name)");
  cmd->add_option("--move-b", o->move, "Translate B by DX,DY,DZ (after the rotation)");
  cmd->add_option("--rotate-b", o->rotate, "Rotate B by DEG degrees about the axis AX,AY,AZ through the origin");
  cmd->add_option("--tol", o->query.tolerance,
                  "The bound every answer must meet, relative to the larger model size (each model prepared at half "
                  "of it, as the bound is K_a + K_b)")
      ->check(relative_tolerance())
      ->capture_default_str();
  cmd->add_option("--motion", o->motion,
                  "One query per line of FILE: DX DY DZ AX AY AZ DEG (B rotated, then moved; - reads stdin)");
  auto* search = add_search_option(cmd, o->query.search);
  auto* first_stage =
      cmd->add_option("--first-stage", o->first_stage,
                      "hierarchy: one box hierarchy over all faces of each model; voxels: the paper's voxel grid "
                      "first (5.4), then the hierarchy over the faces it keeps")
          ->check(CLI::IsMember({"hierarchy", "voxels"}))
          ->capture_default_str();
  auto* voxels = cmd->add_option("--voxels", o->query.voxels, "Voxels per axis of the voxel first stage")
                     ->check(CLI::Range(1, 512))
                     ->capture_default_str();
  auto* reduce_block_opt = cmd->add_option("--reduce-block", o->query.limits.reduce_block,
                  "Texels per pass along each axis of the least-upper-bound reductions: 2 (the paper's log2 passes), "
                  "4 or 8")
      ->check(CLI::IsMember({2, 4, 8}))
      ->capture_default_str();
  auto* fanout_opt = cmd->add_option("--compact-fanout", o->query.limits.compact_fanout,
                  "Texels each level of the stream reduction's count pyramid sums: 4 (one pass per factor 4) or 16")
      ->check(CLI::IsMember({4, 16}))
      ->capture_default_str();
  auto* host_pairs_opt = cmd->add_option("--host-pairs", o->query.limits.host_pairs,
                  "A descent level of at most this many child box pairs is pruned on the CPU from one read-back "
                  "instead of the reduction and stream-reduction passes (the same pairs survive); 0: every level "
                  "on the GPU, as the paper; -1: 65536 with coarse-to-fine, 0 with faithful")
      ->check(CLI::Range(-1LL, 1LL << 40))
      ->capture_default_str();
  auto* start_opt = cmd->add_option("--start-pairs", o->query.limits.start_pairs,
                  "The descent starts at the finest levels whose box pairs number at most this (all of them kept); "
                  "1: at the roots, as the paper (the pairs per level from the root, Fig. 12)")
      ->check(CLI::Range(1LL, 1LL << 40))
      ->capture_default_str();
  auto* upper_opt = cmd->add_option("--gpu-upper", o->upper,
                  "Least upper bound of each level of the descent: boxes (the paper's farthest box points), "
                  "samples (also a face sample per node: far fewer pairs survive; the same answer) or auto "
                  "(samples with coarse-to-fine, boxes with faithful)")
      ->check(CLI::IsMember({"auto", "boxes", "samples"}))
      ->capture_default_str();
  cmd->add_flag("--timings", o->timings,
                "Print the pairs per level, the time per GPU pass, the CPU refinement and the whole query on stderr");
  cmd->add_option("--max-samples", o->query.max_samples,
                  "The most grid samples of one face; a face that needs more for --tol is refused (exit 2)")
      ->check(CLI::Range(4LL, 1LL << 30))
      ->capture_default_str();
  auto* face_cull =
      cmd->add_option("--face-cull", o->face_cull,
                      "boxes: before any grid, leave out the faces whose control boxes lie farther from every face of "
                      "the other model than an upper bound from material samples (they cannot hold the closest pair); "
                      "off: prepare every face (the paper)")
          ->check(CLI::IsMember({"boxes", "off"}))
          ->capture_default_str();
  auto* engine =
      cmd->add_option("--engine", o->engine,
                      "auto: one query whose kept faces' coarse grids hold at most 2^22 cell pairs runs on the CPU "
                      "alone, in double (the GPU's set-up would cost more), others on the GPU, as does any option of "
                      "the GPU descent; gpu: always the GPU descent; cpu: always the CPU (coarse-to-fine, hierarchy "
                      "first stage)")
          ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
          ->capture_default_str();
  // --paper: queries::ClearanceOptions::paper.
  const queries::ClearanceOptions paper = o->query.paper();
  const auto section = [](const char* option) {
    return nurbs::paper_section(queries::ClearanceOptions::paper_switches(), option);
  };
  auto& preset = o->preset;
  auto& q = o->query;
  preset.add_flag(cmd, "Krishnamurthy et al.");
  govern_search(preset, search, q.search, section("search"));
  preset.govern(face_cull, o->face_cull, std::string(paper.face_cull ? "boxes" : "off"), section("face-cull"));
  preset.govern(first_stage, o->first_stage, std::string(paper.voxel_stage ? "voxels" : "hierarchy"),
                section("first-stage"));
  preset.govern(voxels, q.voxels, paper.voxels, section("voxels"));
  preset.govern(engine, o->engine, std::string(queries::engine_name(paper.engine)), section("engine"));
  preset.govern(reduce_block_opt, q.limits.reduce_block, paper.limits.reduce_block, section("reduce-block"));
  preset.govern(fanout_opt, q.limits.compact_fanout, paper.limits.compact_fanout, section("compact-fanout"));
  preset.govern(host_pairs_opt, q.limits.host_pairs, paper.limits.host_pairs, section("host-pairs"));
  preset.govern(upper_opt, o->upper,
                std::string(paper.limits.upper == queries::ClearanceLimits::Upper::Boxes ? "boxes" : "samples"),
                section("gpu-upper"));
  preset.govern(start_opt, q.limits.start_pairs, paper.limits.start_pairs, section("start-pairs"));
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([&global, o, voxels, reduce_block_opt, fanout_opt, host_pairs_opt, upper_opt, start_opt] {
    o->preset.apply();
    if (voxels->count() > 0 && o->first_stage != "voxels") throw BadInput("--voxels needs --first-stage voxels");
    // The options of the GPU descent ask for it: auto runs on the GPU, cpu is refused.
    for (const CLI::Option* g : {reduce_block_opt, fanout_opt, host_pairs_opt, upper_opt, start_opt})
      if (g->count() > 0) {
        if (o->engine == "cpu")
          throw BadInput(fmt::format("{} sets the GPU descent; not with --engine cpu", g->get_name()));
        if (o->engine == "auto") o->engine = "gpu";
      }
    run(global, *o);
  });
}

}  // namespace cli
