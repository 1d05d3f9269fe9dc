// `nurbsgl clearance A B [--move-b DX,DY,DZ] [--rotate-b AX,AY,AZ,DEG]`: minimum distance between two
// models with the bound K_a + K_b (queries/clearance.h), within --tol x the larger model size (found and
// meets_tolerance in JSON; exit 1 when the bound is over it). B is first rotated by DEG degrees about
// the axis (AX, AY, AZ) through the origin, then moved. JSON: distance, bound, point_bound, point_a,
// point_b, face_a, face_b, uv_a, uv_b, seconds; with --timings the passes of the query. `--motion FILE` runs
// one query per line of FILE (DX DY DZ AX AY AZ DEG: B rotated, then moved), B's hierarchy refitted
// each time (the paper's Fig. 16): JSON {"frames", "prepare_seconds", "tolerance", "results": [...]}.
// `engine` (JSON: requested, used, cpu_queries, gpu_queries): small models run on the CPU alone
// (queries::clearance_cpu, no GL context), others on the GPU (--engine).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <future>
#include <glm/gtc/matrix_transform.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/rigid_motion.h"
#include "queries/clearance.h"
#include "queries/face_cull.h"
#include "queries/refine.h"
#include "queries/voxel_stage.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_clearance_impl {

struct Options {
  std::string a, b, move, rotate, motion;
  std::string body_a, body_b;  ///< one body of the model (index or name); empty = every body
  double rel_tolerance = 1e-5;
  queries::Search search = queries::Search::CoarseToFine;
  std::string first_stage = "hierarchy";
  int voxels = 40;
  int reduce_block = queries::ClearanceLimits{}.reduce_block;
  int compact_fanout = queries::ClearanceLimits{}.compact_fanout;
  long long host_pairs = queries::ClearanceLimits{}.host_pairs;
  long long start_pairs = queries::ClearanceLimits{}.start_pairs;
  std::string upper = "auto";
  long long max_samples = 1LL << 22;  ///< per face grid
  bool json = false, timings = false;
  std::string face_cull = "boxes";
  std::string engine = "auto";
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

/// The rule every answer is held to (as `distance`): found, and its bound within the tolerance T.
bool meets(const queries::Clearance& c, double tolerance) {
  return c.found && c.meets_tolerance && c.bound <= tolerance * (1.0 + 1e-12);
}

nlohmann::json result_json(const queries::Clearance& c, double seconds, double tolerance) {
  nlohmann::json j = {{"found", c.found},
          {"distance", c.distance},
          {"bound", c.bound},
          {"point_bound", c.point_bound()},
          {"point_a", {c.point_a.x, c.point_a.y, c.point_a.z}},
          {"point_b", {c.point_b.x, c.point_b.y, c.point_b.z}},
          {"face_a", c.face_a},
          {"face_b", c.face_b},
          {"uv_a", {c.uv_a.x, c.uv_a.y}},
          {"uv_b", {c.uv_b.x, c.uv_b.y}},
          {"seconds", seconds},
          {"pairs_per_level", c.pairs_per_level},
          {"leaf_pairs", c.leaf_pairs},
          {"on_trim_edge", c.on_trim_edge},
          {"intersecting", c.intersecting},
          {"meets_tolerance", meets(c, tolerance)},
          {"refine",
           {{"rounds", c.rounds},
            {"cells", c.refined_cells},
            {"most_pairs", c.most_pairs},
            {"start_pairs", c.start_pairs},
            {"seconds", c.refine_seconds}}}};
  if (c.intersecting)  // a point of both models: the surfaces meet (or touch) there
    j["intersection"] = {{"point", {c.intersection.x, c.intersection.y, c.intersection.z}},
                         {"residual", c.intersection_residual}};
  return j;
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

/// The model of `file` with only the body `spec` names (its index as `nurbsgl info` lists it, or its
/// name); `model` itself when `spec` is empty.
nurbs::Model select_body(nurbs::Model model, const std::string& spec, const std::string& option, const std::string& file) {
  if (spec.empty()) return model;
  int index = -1;
  for (size_t k = 0; k < model.bodies.size() && index < 0; ++k)
    if (model.bodies[k].name == spec) index = int(k);
  if (index < 0 && !spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos && spec.size() < 9)
    index = std::stoi(spec) < int(model.bodies.size()) ? std::stoi(spec) : -1;
  if (index < 0)
    throw BadInput(fmt::format("{}: {} has no body '{}' ({} bodies; `nurbsgl info {}` lists them)", option, file, spec,
                               model.bodies.size(), file));
  nurbs::Body body = std::move(model.bodies[static_cast<size_t>(index)]);
  model.bodies.clear();
  model.bodies.push_back(std::move(body));
  return model;
}

void run(const GlobalOptions& global, const Options& o) {
  // B read (and sized) again only when it is another file or another body of it.
  LoadedModel la = load_model(o.a, "clearance");
  const nurbs::ModelReport report_a = la.report;
  const nurbs::Model ma = select_body(std::move(la.model), o.body_a, "--body-a", o.a);
  const bool same_file = o.b == o.a;
  std::optional<LoadedModel> lb;
  if (!same_file) lb.emplace(load_model(o.b, "clearance"));
  const nurbs::ModelReport& report_b = lb ? lb->report : report_a;
  const std::optional<nurbs::Model> other_b =
      same_file && o.body_b == o.body_a
          ? std::nullopt
          : std::optional<nurbs::Model>(select_body(lb ? std::move(lb->model) : nurbs::io::read_model(o.b), o.body_b,
                                                    "--body-b", o.b));
  const nurbs::Model& mb = other_b ? *other_b : ma;
  const double size_a = checked_model_size(ma, o.a);
  const double size =  // in A's unit
      other_b ? std::max(size_a, checked_model_size(mb, o.b) * mb.unit_scale_to_mm / ma.unit_scale_to_mm) : size_a;
  // B's moves: within reach of both models (B's box scaled into A's unit).
  const double scale_b = mb.unit_scale_to_mm / ma.unit_scale_to_mm;
  const std::vector<glm::dmat4> frames =
      motions(o, nurbs::coordinate_limit(nurbs::model_box(ma)) + scale_b * nurbs::coordinate_limit(nurbs::model_box(mb)));
  const double tolerance = o.rel_tolerance * size;
  const std::string unit = unit_name(ma);  // of every distance printed (B is scaled into it below)
  // The reader's edge gaps widen the bounds near them (nurbs/model_report.h): the query aims that
  // much below the tolerance, up to half of it, so that an answer beside a gap still meets it.
  const double reserve = std::min(0.5 * tolerance, std::max(report_a.largest_gap(), report_b.largest_gap()));
  const double grid_tolerance = queries::clearance_model_tolerance(tolerance - reserve);
  std::unique_ptr<gpgpu::Gpu> gpu;  // started only for the GPU search
  const auto t0 = std::chrono::steady_clock::now();
  queries::ClearanceLimits limits;
  limits.reduce_block = o.reduce_block;
  limits.compact_fanout = o.compact_fanout;
  limits.host_pairs = o.host_pairs;
  limits.start_pairs = o.start_pairs;
  using Upper = queries::ClearanceLimits::Upper;
  limits.upper = o.upper == "boxes" ? Upper::Boxes : o.upper == "samples" ? Upper::Samples : Upper::Auto;
  // The query's programs compile on this thread while the geometry threads work.
  std::vector<nurbs::TrimmedSurface> fa = nurbs::world_faces(ma), fb = nurbs::world_faces(mb);
  // B in A's unit (a file in inches against one in millimetres): the answer and --move-b are in A's.
  if (const double k = mb.unit_scale_to_mm / ma.unit_scale_to_mm; k != 1.0)
    for (nurbs::TrimmedSurface& f : fb)
      for (glm::dvec3& p : f.surface.points) p *= k;
  // The reader's doubts of either side (nurbs/model_report.h), judged per answer against the other
  // side's box in the answer's frame.
  const nurbs::FaceDoubts doubts_a(fa), doubts_b(fb);
  const auto moved = [](const nurbs::Box& b, const glm::dmat4& m) {  // the box of b's corners mapped by m
    nurbs::Box out{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 q(m * glm::dvec4((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                                        (k & 4) ? b.max.z : b.min.z, 1.0));
      out.min = glm::min(out.min, q), out.max = glm::max(out.max, q);
    }
    return out;
  };
  const auto faces_box = [](const std::vector<nurbs::TrimmedSurface>& faces) {
    nurbs::Box box{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    for (const nurbs::TrimmedSurface& f : faces) {
      const nurbs::Box c = nurbs::control_box(f.surface);
      box.min = glm::min(box.min, c.min), box.max = glm::max(box.max, c.max);
    }
    return box;
  };
  const nurbs::Box box_a = faces_box(fa), box_b = faces_box(fb);
  std::string model_reason = report_a.uncertified_reason(global.accept_partial);
  if (model_reason.empty() && lb) model_reason = report_b.uncertified_reason(global.accept_partial);
  double last_widen = 0.0;  // of the last answer's bound: the reader's edge gaps within its reach
  // Widens c's bound by the gaps within reach and returns why it is not certified (empty: it may be).
  const auto judge = [&](queries::Clearance& c, const glm::dmat4& motion) -> std::string {
    if (doubts_a.empty() && doubts_b.empty()) return model_reason;
    const double reach = c.distance + c.bound;
    const nurbs::FaceDoubts::Verdict va = doubts_a.near(moved(box_b, motion), reach);
    const nurbs::FaceDoubts::Verdict vb = doubts_b.near(moved(box_a, glm::inverse(motion)), reach);
    last_widen = std::max(va.widen, vb.widen);
    c.bound += last_widen;
    if (!model_reason.empty()) return model_reason;
    return !va.reason.empty() ? "A: " + va.reason : !vb.reason.empty() ? "B: " + vb.reason : "";
  };
  // Before any grid: the faces that can hold the closest pair (for every frame); the answers
  // name faces by their index in the model.
  const size_t faces_a = fa.size(), faces_b = fb.size();
  std::vector<int> index_a(fa.size()), index_b(fb.size());
  for (size_t f = 0; f < fa.size(); ++f) index_a[f] = int(f);
  for (size_t f = 0; f < fb.size(); ++f) index_b[f] = int(f);
  nlohmann::json cull_json = {{"method", o.face_cull}};
  // The kept faces' coarse grids as the whole models' (a part's smaller box would make them finer).
  const double coarse_a = queries::coarse_tolerance(fa, grid_tolerance);
  const double coarse_b = queries::coarse_tolerance(fb, grid_tolerance);
  if (o.face_cull == "boxes") {
    const auto c0 = std::chrono::steady_clock::now();
    // The margin: far above the spatial error of a sample classified by trim polygons flattened
    // within 1e-6 of the domain.
    const queries::FaceCull cull = queries::cull_faces(fa, fb, frames, 1e-4 * size);
    const auto keep = [](std::vector<nurbs::TrimmedSurface>& faces, std::vector<int>& index,
                         const std::vector<char>& flags) {
      std::vector<nurbs::TrimmedSurface> kept;
      std::vector<int> kept_index;
      for (size_t f = 0; f < faces.size(); ++f)
        if (flags[f]) kept.push_back(std::move(faces[f])), kept_index.push_back(index[f]);
      faces = std::move(kept), index = std::move(kept_index);
    };
    keep(fa, index_a, cull.keep_a), keep(fb, index_b, cull.keep_b);
    cull_json["faces_a"] = fa.size(), cull_json["faces_b"] = fb.size(), cull_json["face_pairs"] = cull.pairs;
    cull_json["upper"] = cull.upper;
    cull_json["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
  }
  auto any_trimmed = [](const std::vector<nurbs::TrimmedSurface>& faces) {
    return std::any_of(faces.begin(), faces.end(), [](const auto& f) { return !f.loops.empty(); });
  };
  const bool trimmed = any_trimmed(fa) || any_trimmed(fb);
  // The search on the CPU alone (coarse grids, the cell pairs within an upper bound refined in
  // double) where the models are small enough that the GPU's set-up would cost more: tried per
  // query once the coarse grids exist, before any GL context; over its budget the GPU takes over.
  const bool voxel = o.first_stage == "voxels";
  const bool cpu_possible = o.search == queries::Search::CoarseToFine && !voxel;
  if (o.engine == "cpu" && !cpu_possible)
    throw BadInput("--engine cpu needs --search coarse-to-fine and --first-stage hierarchy");
  const auto grid_limit = [&](const queries::GridLimitError& e) {
    return BadInput(fmt::format("--tol {:g} --max-samples {}: {}", o.rel_tolerance, o.max_samples, e.what()));
  };
  queries::PreparedPair pair;
  bool try_cpu = false;
  try {
    if (o.engine != "gpu" && cpu_possible) {
      auto geometry = [&](std::vector<nurbs::TrimmedSurface>& faces, double coarse) {
        return std::async(std::launch::async, [&faces, &grid_tolerance, &o, coarse] {
          return queries::prepare_geometry(std::move(faces), grid_tolerance, o.max_samples, o.search, coarse);
        });
      };
      auto ga = geometry(fa, coarse_a), gb = geometry(fb, coarse_b);
      pair.a = ga.get(), pair.b = gb.get();
      // One query of models whose kept faces' coarse grids hold few cell pairs (a motion sequence
      // reuses A's hierarchy on the GPU from one motion to the next).
      try_cpu = o.engine == "cpu" || (frames.size() == 1 && queries::grid_cell_count(pair.a) *
                                                                queries::grid_cell_count(pair.b) <=
                                                            queries::kCpuClearanceStartPairs);
    } else {
      gpu = start_gpu(global);
      pair = queries::prepare_pair(*gpu, std::move(fa), std::move(fb), grid_tolerance, o.search, o.max_samples,
                                   [&](const std::function<bool()>& geometry_done) {
                                     queries::compile_clearance_programs(*gpu, limits, o.search, trimmed,
                                                                         geometry_done);
                                   },
                                   coarse_a, coarse_b);
    }
  } catch (const queries::GridLimitError& e) {
    throw grid_limit(e);
  }
  // The GPU's set-up, once, when a query needs it.
  bool gpu_ready = false;
  const auto ensure_gpu = [&] {
    if (gpu_ready) return;
    gpu_ready = true;
    if (!gpu) {
      gpu = start_gpu(global);
      queries::compile_clearance_programs(*gpu, limits, o.search, trimmed);
      try {
        queries::prepare_atlases(*gpu, pair.a);
        queries::prepare_atlases(*gpu, pair.b);
      } catch (const queries::GridLimitError& e) {
        throw grid_limit(e);
      }
    }
    gpu->finish();
    if (o.timings) {  // the passes of the queries alone, each synchronised (Table 2 of the paper)
      gpu->profiler().reset();
      gpu->profiler().set_enabled(true);
      gpu->profiler().set_sync(true);
    }
  };
  if (!try_cpu) ensure_gpu();
  const queries::PreparedModel &a = pair.a, &b = pair.b;
  long long cpu_frames = 0, gpu_frames = 0;
  const auto engine_json = [&] {
    return nlohmann::json{{"requested", o.engine},
                          {"used", cpu_frames > 0 && gpu_frames > 0 ? "cpu and gpu" : cpu_frames > 0 ? "cpu" : "gpu"},
                          {"cpu_queries", cpu_frames},
                          {"gpu_queries", gpu_frames}};
  };
  // §5.4: the voxel grids once per model; per query the voxel pairs keep the faces that take part.
  const queries::VoxelGrid va = voxel ? queries::voxelize(a, {o.voxels}) : queries::VoxelGrid{};
  const queries::VoxelGrid vb = voxel ? queries::voxelize(b, {o.voxels}) : queries::VoxelGrid{};
  nlohmann::json stage;
  queries::ClearanceCache cache;  // A's hierarchy, built once for every motion (destroyed before gpu)
  auto query_kept = [&](const glm::dmat4& motion) {
    // On the CPU the cell pairs start from those within the face cull's upper bound for this motion.
    if (try_cpu) {
      const double upper = queries::cull_faces(a.faces, b.faces, {&motion, 1}, 1e-4 * size).upper;
      const long long budget = o.engine == "cpu" ? -1 : queries::kCpuClearanceStartPairs;
      if (auto c = queries::clearance_cpu(a, b, motion, upper, budget)) {
        ++cpu_frames;
        return *c;
      }
      ensure_gpu();
    }
    ++gpu_frames;
    if (!voxel) return queries::clearance(*gpu, a, b, motion, nullptr, nullptr, limits, &cache);
    const auto v0 = std::chrono::steady_clock::now();
    const queries::VoxelStage vs = queries::voxel_stage(*gpu, va, vb, motion);
    stage = {{"method", "voxels"},
             {"voxels", o.voxels},
             {"occupied_a", vs.voxels_a},
             {"occupied_b", vs.voxels_b},
             {"voxel_pairs", vs.voxel_pairs},
             {"surviving_pairs", vs.surviving_pairs},
             {"face_pairs", vs.face_pairs.size()},
             {"faces_a", std::count(vs.faces_a.begin(), vs.faces_a.end(), 1)},
             {"faces_b", std::count(vs.faces_b.begin(), vs.faces_b.end(), 1)},
             {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - v0).count()}};
    return queries::clearance(*gpu, a, b, motion, &vs.faces_a, &vs.faces_b, limits);
  };
  // The switches of --paper as used; null where this run does not use them (the GPU descent's on
  // the CPU engine, --voxels without the voxel stage).
  const auto preset_json = [&] {
    const bool descent = gpu_frames > 0;
    const auto on_gpu = [&](const nlohmann::json& v) { return descent ? v : nlohmann::json(); };
    const bool c2f = o.search == queries::Search::CoarseToFine;
    return o.preset.json({{"engine", engine_json()["used"]},
                          {"voxels", voxel ? nlohmann::json(o.voxels) : nlohmann::json()},
                          {"reduce-block", on_gpu(o.reduce_block)},
                          {"compact-fanout", on_gpu(o.compact_fanout)},
                          {"host-pairs", on_gpu(queries::host_pairs_used(limits, c2f))},
                          {"start-pairs", on_gpu(o.start_pairs)},
                          {"gpu-upper", on_gpu(queries::upper_from_samples(limits, c2f) ? "samples" : "boxes")}});
  };
  std::string last_reason;  // why the last answer is not certified (the reader's doubts), empty if it may be
  size_t uncertified = 0;
  auto query = [&](const glm::dmat4& motion) {
    queries::Clearance c = query_kept(motion);
    last_reason = judge(c, motion);
    if (!last_reason.empty()) c.meets_tolerance = false;
    if (c.face_a >= 0) c.face_a = index_a[size_t(c.face_a)];
    if (c.face_b >= 0) c.face_b = index_b[size_t(c.face_b)];
    return c;
  };
  if (gpu) gpu->finish();
  const auto t1 = std::chrono::steady_clock::now();
  const double prepare_s = std::chrono::duration<double>(t1 - t0).count();
  if (!o.motion.empty()) {
    if (!o.json) o.preset.print_text();
    nlohmann::json results = nlohmann::json::array();
    size_t over = 0;
    const bool progress = frames.size() > 1 && isatty(STDERR_FILENO);
    for (size_t k = 0; k < frames.size(); ++k) {
      const auto f0 = std::chrono::steady_clock::now();
      const queries::Clearance c = query(frames[k]);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count();
      if (!c.found) throw CommandFailed(fmt::format("frame {}: no pair of surface points found", k + 1));
      results.push_back(result_json(c, s, tolerance));
      if (!last_reason.empty()) results.back()["uncertified"] = last_reason, ++uncertified;
      over += last_reason.empty() && !meets(c, tolerance);
      if (voxel) results.back()["first_stage"] = stage;
      if (progress) fmt::print(stderr, "\r[{}/{}] frames", k + 1, frames.size());
      if (!o.json)
        fmt::print("frame {}: clearance {:.9g} +- {:.3g} (faces {}, {}){} in {:.1f} ms\n", k + 1, c.distance, c.bound,
                   c.face_a, c.face_b, c.intersecting ? ", intersecting" : "", 1e3 * s);
    }
    if (progress) fmt::print(stderr, "\n");
    if (o.json)
      print_json(nlohmann::json{{"frames", frames.size()},
                                {"prepare_seconds", prepare_s},
                                {"prepare", prepare_json(a, b)},
                                {"face_cull", cull_json},
                                {"engine", engine_json()},
                                {"preset", preset_json()},
                                {"tolerance", tolerance},
                                {"unit", unit},
                                {"uncertified", uncertified},
                                {"model_a", model_json(report_a, global)},
                                {"model_b", model_json(report_b, global)},
                                {"results", results}});
    if (gpu) report_profile(*gpu, global);
    require_certified(report_a, global);
    require_certified(report_b, global);
    if (uncertified > 0)
      throw CommandFailed(fmt::format("{} of {} frames not certified: {}", uncertified, frames.size(), last_reason));
    if (over > 0)
      throw CommandFailed(fmt::format("{} of {} frames with a bound over the tolerance {:.3g}", over, frames.size(),
                                      tolerance));
    return;
  }
  const queries::Clearance c = query(frames.front());
  const auto t2 = std::chrono::steady_clock::now();
  const double query_s = std::chrono::duration<double>(t2 - t1).count();
  if (!c.found) throw CommandFailed("no pair of surface points found (every cell trimmed away?)");
  if (o.json) {
    nlohmann::json j = result_json(c, query_s, tolerance);
    if (voxel) j["first_stage"] = stage;
    j["prepare_seconds"] = prepare_s;
    j["prepare"] = prepare_json(a, b);
    j["face_cull"] = cull_json;
    j["engine"] = engine_json();
    j["preset"] = preset_json();
    j["tolerance"] = tolerance;
    j["unit"] = unit;
    if (!last_reason.empty()) j["uncertified"] = last_reason;
    j["model_a"] = model_json(report_a, global);
    j["model_b"] = model_json(report_b, global);
    print_json(j);
  } else {
    o.preset.print_text();
    fmt::print(
        "clearance {:.9g} +- {:.3g} {} between face {} of A at ({:.6g}, {:.6g}, {:.6g}) and face {} of B at "
        "({:.6g}, {:.6g}, {:.6g}); each point within {:.3g} of its surface's nearest point to the other\n",
        c.distance, c.bound, unit, c.face_a, c.point_a.x, c.point_a.y, c.point_a.z, c.face_b, c.point_b.x, c.point_b.y,
        c.point_b.z, c.point_bound());
    if (cpu_frames > 0)
      fmt::print("prepared {} of {} faces of A, {} of {} of B in {:.3f} s (coarse grids); query {:.3f} s on the CPU, "
                 "{} cells refined in {} rounds\n",
                 a.faces.size(), faces_a, b.faces.size(), faces_b, prepare_s, query_s, c.refined_cells, c.rounds);
    else
      fmt::print("prepared {} of {} faces of A, {} of {} of B in {:.3f} s (grids with K_e <= {:.3g}); query {:.3f} s, "
                 "{} levels, {} leaf cell pairs\n",
                 a.faces.size(), faces_a, b.faces.size(), faces_b, prepare_s, grid_tolerance, query_s,
                 c.pairs_per_level.size(), c.leaf_pairs);
    if (c.intersecting)
      fmt::print("the models intersect: faces {} and {} meet at ({:.9g}, {:.9g}, {:.9g})\n", c.face_a, c.face_b,
                 c.intersection.x, c.intersection.y, c.intersection.z);
    if (!last_reason.empty())
      fmt::print("not certified: {}\n", last_reason);
    else if (!meets(c, tolerance))
      fmt::print("the bound {:.3g} is over the tolerance {:.3g}\n", c.bound, tolerance);
  }
  if (o.timings) {
    std::string levels;
    for (long long n : c.pairs_per_level) levels += fmt::format(" {}", n);
    std::fflush(stdout);
    // The CPU refinement in double (coarse-to-fine), which the GPU table does not hold, and the whole.
    fmt::print(stderr,
               "pairs per level:{}\n{}cpu refinement: {} rounds, {} cells, {:.3f} ms\nquery: {:.3f} ms in all (GPU "
               "passes, CPU refinement, read-backs)\n",
               levels, gpu ? gpu->profiler().table() : std::string("no GPU passes (the search ran on the CPU)\n"),
               c.rounds, c.refined_cells, 1e3 * c.refine_seconds, 1e3 * query_s);
  } else if (gpu) {
    report_profile(*gpu, global);
  }
  require_certified(report_a, global);
  require_certified(report_b, global);
  if (!last_reason.empty()) throw CommandFailed("the answer is not certified: " + last_reason);
  if (!meets(c, tolerance))
    throw CommandFailed(
        last_widen > 0.0 && c.bound - last_widen <= tolerance * (1.0 + 1e-12)
            ? fmt::format("the bound {:.3g} is over the tolerance {:.3g}: {:.3g} of it is the file's edges lying off "
                          "their faces near the answer (a larger --tol)",
                          c.bound, tolerance, last_widen)
            : fmt::format("the bound {:.3g} is over the tolerance {:.3g} (the refinement's budget ran out)", c.bound,
                          tolerance));
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
  cmd->add_option("--body-a", o->body_a,
                  "Only this body of A: its index or name as `nurbsgl info A` lists them (a part of an assembly)");
  cmd->add_option("--body-b", o->body_b, "Only this body of B (index or name)");
  cmd->add_option("--move-b", o->move, "Translate B by DX,DY,DZ (after the rotation)");
  cmd->add_option("--rotate-b", o->rotate, "Rotate B by DEG degrees about the axis AX,AY,AZ through the origin");
  cmd->add_option("--tol", o->rel_tolerance,
                  "The bound every answer must meet, relative to the larger model size (each model prepared at half "
                  "of it, as the bound is K_a + K_b)")
      ->check(relative_tolerance())
      ->capture_default_str();
  cmd->add_option("--motion", o->motion,
                  "One query per line of FILE: DX DY DZ AX AY AZ DEG (B rotated, then moved; - reads stdin)");
  auto* search = add_search_option(cmd, o->search);
  auto* first_stage =
      cmd->add_option("--first-stage", o->first_stage,
                      "hierarchy: one box hierarchy over all faces of each model; voxels: the paper's voxel grid "
                      "first (5.4), then the hierarchy over the faces it keeps")
          ->check(CLI::IsMember({"hierarchy", "voxels"}))
          ->capture_default_str();
  auto* voxels = cmd->add_option("--voxels", o->voxels, "Voxels per axis of the voxel first stage")
                     ->check(CLI::Range(1, 512))
                     ->capture_default_str();
  auto* reduce_block_opt = cmd->add_option("--reduce-block", o->reduce_block,
                  "Texels per pass along each axis of the least-upper-bound reductions: 2 (the paper's log2 passes), "
                  "4 or 8")
      ->check(CLI::IsMember({2, 4, 8}))
      ->capture_default_str();
  auto* fanout_opt = cmd->add_option("--compact-fanout", o->compact_fanout,
                  "Texels each level of the stream reduction's count pyramid sums: 4 (one pass per factor 4) or 16")
      ->check(CLI::IsMember({4, 16}))
      ->capture_default_str();
  auto* host_pairs_opt = cmd->add_option("--host-pairs", o->host_pairs,
                  "A descent level of at most this many child box pairs is pruned on the CPU from one read-back "
                  "instead of the reduction and stream-reduction passes (the same pairs survive); 0: every level "
                  "on the GPU, as the paper; -1: 65536 with coarse-to-fine, 0 with faithful")
      ->check(CLI::Range(-1LL, 1LL << 40))
      ->capture_default_str();
  auto* start_opt = cmd->add_option("--start-pairs", o->start_pairs,
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
  cmd->add_option("--max-samples", o->max_samples,
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
  // --paper: faithful grids (5.1), every face prepared and the voxel first stage of 5.4 at the
  // 40^3 grid of the paper's tests (6), the descent on the GPU (5.1) with its log2 reductions of 2 x 2
  // texels and the stream reduction's 4-texel count pyramid (1.1), every level on the GPU (5.1), U
  // from the boxes' farthest points (5.2, Eqs. 13-16), the descent from the roots (5.1).
  auto& preset = o->preset;
  preset.add_flag(cmd, "Krishnamurthy et al.");
  govern_search(preset, search, o->search, "§5.1");
  preset.govern(face_cull, o->face_cull, std::string("off"), "§5.4");
  preset.govern(first_stage, o->first_stage, std::string("voxels"), "§5.4");
  preset.govern(voxels, o->voxels, 40, "§6");
  preset.govern(engine, o->engine, std::string("gpu"), "§5.1");
  preset.govern(reduce_block_opt, o->reduce_block, 2, "§1.1, §3.1");
  preset.govern(fanout_opt, o->compact_fanout, 4, "§1.1");
  preset.govern(host_pairs_opt, o->host_pairs, 0LL, "§5.1");
  preset.govern(upper_opt, o->upper, std::string("boxes"), "§5.2");
  preset.govern(start_opt, o->start_pairs, 1LL, "§5.1");
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
