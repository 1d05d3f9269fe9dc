#include "queries/distance/point_query.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <stdexcept>

#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/request_error.h"
#include "nurbs/tessellation/model_mesh.h"
#include "nurbs/stopwatch.h"
#include "nurbs/system_memory.h"
#include "queries/distance/batch_cache.h"

namespace queries {

namespace {

/// The faithful grids of a batched preparation fit this many bytes (and the memory free), else
/// coarse grids are taken.
constexpr long long kFaithfulBytes = 1LL << 30;

}  // namespace

BatchEngine choose_engine(EngineChoice choice, const gpgpu::Gpu& gpu) {
  if (choice == EngineChoice::Gpu) return BatchEngine::Gpu;
  if (choice == EngineChoice::Cpu) return BatchEngine::Cpu;
  return gpu.info().software_renderer() ? BatchEngine::Cpu : BatchEngine::Gpu;
}

const char* engine_name(BatchEngine engine) { return engine == BatchEngine::Cpu ? "cpu" : "gpu"; }

const char* engine_name(EngineChoice choice) {
  return choice == EngineChoice::Auto ? "auto" : choice == EngineChoice::Cpu ? "cpu" : "gpu";
}

EngineChoice engine_choice(const std::string& name) {
  if (name == "auto") return EngineChoice::Auto;
  if (name == "gpu") return EngineChoice::Gpu;
  if (name == "cpu") return EngineChoice::Cpu;
  throw std::invalid_argument("engine '" + name + "': auto, gpu or cpu");
}

const char* path_name(PointPath path) {
  return path == PointPath::Auto ? "auto" : path == PointPath::Mesh ? "mesh" : "batched";
}

PointPath point_path(const std::string& name) {
  if (name == "auto") return PointPath::Auto;
  if (name == "mesh") return PointPath::Mesh;
  if (name == "batched") return PointPath::Batched;
  throw std::invalid_argument("path '" + name + "': auto, mesh or batched");
}

PointQueryOptions PointQueryOptions::paper() const {
  PointQueryOptions o = *this;
  o.per_point = true;
  o.search = Search::Faithful;
  o.host_cells = 0;
  return o;
}

std::vector<nurbs::PaperSwitch> PointQueryOptions::paper_switches() {
  return {{"per-point", "§3.1"}, {"search", "§3.1, §4"}, {"host-cells", "§3.1"}};
}

std::string PointQueryResult::failure(bool strict) const {
  if (!model_reason.empty()) return model_reason;
  std::vector<std::string> parts;
  if (uncertified > 0)
    parts.push_back(fmt::format(
        "{} not certified ({})", uncertified,
        *std::find_if(reasons.begin(), reasons.end(), [](const std::string& w) { return !w.empty(); })));
  if (not_found > 0) parts.push_back(fmt::format("{} not found", not_found));
  if (const size_t over = over_tolerance - limited_by_file; over > 0) {
    size_t k = 0;
    while (k < answers.size() && !(answers[k].found && reasons[k].empty() && !file_limits[k].limited &&
                                   !over_reasons[k].empty()))
      ++k;
    parts.push_back(fmt::format("{} with a bound over the tolerance {:.3g} ({})", over, tolerance,
                                k < answers.size() ? over_reasons[k] : ""));
  }
  if (strict && limited_by_file > 0)
    parts.push_back(fmt::format("{} over the tolerance only by the file's precision (strict)", limited_by_file));
  if (parts.empty()) return {};
  const size_t short_of = uncertified + not_found + over_tolerance - (strict ? 0 : limited_by_file);
  return fmt::format("{} of {} answers fall short: {}", short_of, answers.size(), fmt::join(parts, "; "));
}

std::string PointQueryResult::file_precision() const {
  if (limited_by_file == 0) return {};
  // Every face that limits an answer, with its gap and how many answers it limits.
  std::map<int, std::pair<const FileLimit*, size_t>> faces;
  for (const FileLimit& l : file_limits)
    if (l.limited) {
      auto& [first, n] = faces[l.face];
      if (!first) first = &l;
      ++n;
    }
  std::vector<std::string> named;
  for (const auto& [face, v] : faces)
    named.push_back(fmt::format("face {} (id {}) gap {:.3g}: {}", face, v.first->face_id, v.first->gap, v.second));
  return fmt::format(
      "{} of {} answers are over the tolerance {:.3g} only because the file's edges lie off their faces near them: "
      "certified to the file's precision (limited_by_file); by face: {}",
      limited_by_file, answers.size(), tolerance, fmt::join(named, ", "));
}

PointQuery::PointQuery(gpgpu::Gpu& gpu, const nurbs::LoadedModel& model, PointQueryOptions options)
    : options_(std::move(options)),
      model_reason_(model.report.uncertified_reason(options_.accept_partial)),
      size_(model.checked_size()),
      faces_(nurbs::world_faces(model.model)),
      doubts_(faces_),
      engine_(choose_engine(options_.engine, gpu)) {
  nurbs::require_relative_tolerance(options_.tolerance, "tolerance");
  if (options_.signed_distance) {
    require_closed_solids(model);
    std::vector<int> solid_of_face;  // a body is a solid; world_faces keeps body order
    for (size_t b = 0; b < model.model.bodies.size(); ++b)
      solid_of_face.insert(solid_of_face.end(), model.model.bodies[b].faces.size(), int(b));
    sides_ = std::make_unique<SideTest>(faces_, std::move(solid_of_face));
  }
  // The reader's edge gaps widen the bounds near them (nurbs/model_report.h): the query aims that
  // much below the tolerance, up to half of it, so that an answer beside a gap still meets it.
  const double tolerance = options_.tolerance * size_;
  query_tolerance_ = tolerance - std::min(0.5 * tolerance, model.report.largest_gap());
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (options_.per_point) {
      single_.emplace(gpu, faces_, query_tolerance_, options_.max_samples, options_.search);
      single_->set_host_cells(options_.host_cells);
    } else {
      const bool mesh = options_.path == PointPath::Mesh ||
                        (options_.path == PointPath::Auto && options_.engine == EngineChoice::Auto);
      if (!mesh || !prepare_mesh(query_tolerance_)) prepare_batched(gpu, model.path, query_tolerance_);
    }
  } catch (const GridLimitError& e) {
    throw nurbs::RequestError(
        fmt::format("--tol {:g} --max-samples {}: {}", options_.tolerance, options_.max_samples, e.what()));
  }
  gpu.finish();
  prepare_seconds_ = nurbs::seconds_since(t0);
}

void PointQuery::require_closed_solids(const nurbs::LoadedModel& model) {
  const auto refuse = [&](size_t b, const std::string& why) {
    const std::string& name = model.model.bodies[b].name;
    throw nurbs::RequestError(fmt::format("{}: signed distances need closed solids, and body {}{} {}",
                                          model.path.string(), b, name.empty() ? "" : " (" + name + ")", why));
  };
  for (size_t b = 0; b < model.model.bodies.size(); ++b)
    if (const nurbs::Body& body = model.model.bodies[b]; !body.closed)
      refuse(b, body.not_closed.empty()
                    ? "is not stated closed (an open shell or loose faces: its inside is not defined)"
                    : "is stated closed, but " + body.not_closed + ": its inside is not defined");
  // A file may state a solid whose faces do not close (a face missing, edges that do not meet):
  // the rays of the side test would then pass through the gaps. A watertight mesh shows it (at the
  // tessellation's default eps: coarser meshes may leave cracks of their own).
  nurbs::tess::ModelMeshOptions o;
  o.eps = 1e-3, o.relative = true, o.accept_partial = true;
  o.tess.watertight = true;  // guaranteed: the approximate mode may leave cracks at coarse eps
  const nurbs::tess::ModelMesh mesh = nurbs::tess::mesh_model(model, o);
  if (mesh.solid_open == 0 && mesh.result.failures.empty()) return;
  // The body of the first face that leaves open edges (or was not meshed): faces in body order.
  int face = mesh.result.failures.empty() ? -1 : mesh.result.failures.front().face;
  for (const auto& [f, n] : mesh.edges.open_by_face)
    if (face < 0 && f >= 0) face = f;
  size_t b = 0;
  for (int first = 0; b + 1 < model.model.bodies.size(); ++b) {
    first += int(model.model.bodies[b].faces.size());
    if (face < first) break;
  }
  refuse(b, mesh.result.failures.empty()
                ? fmt::format("is stated closed, but its faces leave {} open edges ({})", mesh.solid_open,
                              fmt::join(mesh.solid_cracks, "; "))
                : fmt::format("is stated closed, but face {} could not be meshed to check it: {}", face,
                              mesh.result.failures.front().reason));
}

void PointQuery::sign_answers(std::span<const glm::dvec3> points, PointQueryResult& out) {
  const std::vector<SideAnswer> side = sides_->sides(points, out.answers, out.normals);
  out.sides = sides_->figures();
  out.signed_distance.assign(out.answers.size(), std::nan(""));
  for (size_t k = 0; k < out.answers.size(); ++k) {
    PointDistance& r = out.answers[k];
    if (!r.found) continue;
    if (side[k].hidden_by >= 0 && out.reasons[k].empty()) {
      // The part is the union of its solids: from inside it, a face point inside or on another
      // solid is not on its boundary, which may lie farther.
      r.meets_tolerance = false;
      out.reasons[k] = fmt::format(
          "{}: its closest face point (face {}) lies inside or on body {} too (the part's solids overlap or "
          "touch there), so the part's boundary may lie farther",
          side[k].side == Side::Inside ? "inside the part" : "inside or outside unsure", r.face, side[k].hidden_by);
    }
    if (side[k].side != Side::Unsure) {
      out.signed_distance[k] = side[k].side == Side::Inside ? -r.distance : r.distance;
    } else {
      // Either side: the true signed distance lies within d + d* <= 2 d + bound of +d. Certified
      // only where that still meets the tolerance (a point on the surface, or within its bound).
      out.signed_distance[k] = r.distance;
      r.bound += 2.0 * r.distance;
      if (!within_tolerance(r.bound, out.tolerance) && out.reasons[k].empty()) {
        r.meets_tolerance = false;
        out.reasons[k] = "inside or outside unsure: the rays from the point disagree (the solids overlap, or a face "
                         "is missing or misoriented)";
      }
    }
  }
}

PointQuery::~PointQuery() {
  if (cache_write_.valid()) cache_write_.wait();
}

void PointQuery::prepare_batched(gpgpu::Gpu& gpu, const std::filesystem::path& path, double tolerance) {
  // Faithful grids within 1 GB (and the memory free), else coarse ones; answers whose bound is
  // over T refined in double (point_batch.h), so no tolerance is beyond the float pass. Refused
  // before the work: a preparation larger than the memory this machine has free.
  const int side = atlas_side(gpu.info());
  const long long free = nurbs::available_memory();
  PreparedModel geometry =
      prepare_batch_geometry(faces_, tolerance, options_.max_samples, side, options_.boxes,
                             free > 0 ? std::min(free, kFaithfulBytes) : kFaithfulBytes);
  const long long need = estimate_batch_bytes(geometry, side, options_.boxes);
  if (free > 0 && need > free)
    throw nurbs::RequestError(fmt::format(
        "--tol {:g}: the grids of {} faces need about {:.1f} GB, and this machine has {:.1f} GB free; a larger --tol",
        options_.tolerance, faces_.size(), double(need) / 1e9, double(free) / 1e9));
  // The atlases and the pyramid from the disk cache when an earlier run made them, else built and
  // stored there.
  const std::filesystem::path dir = batch_cache_directory();
  cache_.used = options_.cache && options_.boxes == PointBoxes::Oriented && !gpu.dump_dir() && !dir.empty() &&
                !path.empty();
  std::string key;
  std::optional<PointBatchState> state;
  if (cache_.used) {
    const auto c0 = std::chrono::steady_clock::now();
    key = batch_cache_key(path, geometry.grid_tolerance, options_.max_samples, side, gpu.info().renderer);
    cache_.file = batch_cache_file(dir, key);
    BatchCacheRead read = load_batch_state(cache_.file, key);
    if (read.state && !state_matches(geometry, *read.state))
      read = {std::nullopt, "its atlases do not match the model's grids"};
    if (!read.problem.empty() && options_.log)  // rebuilt below and written over it
      options_.log(fmt::format("warning: the cache file {} is not used: {}; the preparation is rebuilt",
                               cache_.file.string(), read.problem));
    cache_.problem = read.problem;
    state = std::move(read.state);
    cache_.hit = state.has_value();
    cache_.read_seconds = nurbs::seconds_since(c0);
  }
  if (state) {
    restore_atlases(geometry, *state);
    prepared_.emplace(std::move(geometry));
    batch_.emplace(gpu, *prepared_, std::move(*state));
  } else {
    prepare_atlases(gpu, geometry, side);
    prepared_.emplace(std::move(geometry));
    batch_.emplace(gpu, *prepared_, options_.boxes);
    if (cache_.used)  // exported and written on another thread while the points are answered (the
                      // query reads the batch's atlases and pyramid, never changes them)
      cache_write_ = std::async(std::launch::async, [&b = *batch_, file = cache_.file, key] {
        const auto c0 = std::chrono::steady_clock::now();
        std::string why = save_batch_state(file, key, b.state_view());
        return std::pair{why, nurbs::seconds_since(c0)};
      });
  }
  batch_->set_engine(engine_);
  batch_->set_refine_tolerance(tolerance);
}

bool PointQuery::prepare_mesh(double tolerance) {
  try {
    auto mesh = std::make_unique<MeshDistance>(faces_, tolerance);
    const auto& failures = mesh->tessellation().failures;
    if (failures.empty()) {
      mesh_ = std::move(mesh);
      return true;
    }
    mesh_refused_ = fmt::format("{} of {} faces could not be meshed within the tolerance (face {}: {})",
                                failures.size(), faces_.size(), failures.front().face, failures.front().reason);
  } catch (const nurbs::tess::WorkLimitError& e) {
    mesh_refused_ = fmt::format("the mesh would be too large: {}", e.what());
  }
  if (options_.log) options_.log(fmt::format("the certified mesh is not used: {}; the grids' pyramid answers", mesh_refused_));
  return false;
}

void PointQuery::finish_cache_write() {
  if (!cache_write_.valid()) return;
  const auto [why, seconds] = cache_write_.get();
  cache_.write_problem = why;
  cache_.write_seconds = seconds;
  if (!why.empty() && options_.log) options_.log(fmt::format("the preparation is not cached: {}", why));
}

Search PointQuery::grids() const {
  return prepared_ ? prepared_->search : single_ ? single_->model().search : Search::Faithful;
}

long long PointQuery::samples() const {
  long long n = 0;
  if (mesh_) return 0;
  for (const auto& g : prepared_ ? prepared_->grids : single_->grids()) n += g.grid.samples();
  return n;
}

const PointBatchStats& PointQuery::stats() const {
  static const PointBatchStats none;
  return batch_ ? batch_->stats() : none;
}

PointQueryResult PointQuery::query(std::span<const glm::dvec3> points) {
  PointQueryResult out;
  out.tolerance = options_.tolerance * size_;
  out.model_reason = model_reason_;
  const auto t0 = std::chrono::steady_clock::now();
  if (mesh_) {
    if (prepare_seconds_ >= 1.0 && options_.log && !told_prepared_)
      told_prepared_ = true,
      options_.log(fmt::format("{} faces meshed ({} triangles) in {:.1f} s; {} points", faces_.size(),
                               mesh_->triangles(), prepare_seconds_, points.size()));
    out.answers = mesh_->query(points, options_.progress);
  } else if (batch_) {
    // Long work shows: the preparation once it took a second, then the points pass by pass
    // (passes of at least 65536 points: llvmpipe spreads a pass's 64 x 64 tiles over its threads,
    // and a pass of 4096 points is one tile, one thread: 2x slower in all).
    if (prepare_seconds_ >= 1.0 && options_.log && !told_prepared_)
      told_prepared_ = true, options_.log(fmt::format("{} faces prepared in {:.1f} s; {} points", faces_.size(), prepare_seconds_,
                               points.size()));
    batch_->set_points_per_pass(std::max<size_t>(65536, (points.size() + 7) / 8));
    batch_->set_progress(options_.progress);
    out.answers = batch_->query(points);
  } else {
    out.answers.reserve(points.size());
    for (size_t k = 0; k < points.size(); ++k) {
      out.answers.push_back(single_->query(points[k]));
      if (options_.progress && k % 100 == 0) options_.progress(k, points.size());
    }
    if (options_.progress) options_.progress(points.size(), points.size());
  }
  out.seconds = nurbs::seconds_since(t0);
  finish_cache_write();
  // An answer is a distance only with a face and finite figures: anything else is not found,
  // never a distance.
  for (auto& r : out.answers)
    if (r.found && (r.face < 0 || !std::isfinite(r.distance) || !std::isfinite(r.bound))) r.found = false;
  // The reader's doubts (nurbs/model_report.h): what the edge gaps within reach can change widens
  // the bound; a face whose trim could not be made valid, or a model that lost faces, leaves the
  // answer uncertified.
  out.reasons.resize(out.answers.size());
  out.over_reasons.resize(out.answers.size());
  out.file_limits.resize(out.answers.size());
  out.normals.assign(out.answers.size(), glm::dvec3(0.0));
  const double T = out.tolerance;
  // Per answer on its own: on every core, in contiguous shares (the gapped faces' boundaries are
  // searched per answer).
  nurbs::parallel_for(out.answers.size(), 0, [&](size_t k, int) {
    auto& r = out.answers[k];
    if (!r.found) return;
    out.normals[k] = nurbs::outward_normal(faces_[size_t(r.face)], r.uv);
    // The upper end's witness: on the mesh, the face point nearest the answer's point (within eps of
    // it, so at most d + eps from p); else the true closest point, within point_bound of it.
    const bool on_mesh = mesh_ && glm::length(points[k] - r.point) <= r.distance * (1.0 + 1e-12);
    const nurbs::FaceDoubts::Verdict v = doubts_.at(
        points[k], r.distance, r.bound,
        nurbs::FaceDoubts::Witness{r.point, on_mesh ? std::min(r.bound, r.point_bound) : r.point_bound});
    r.bound += v.widen;
    out.file_limits[k] = {v.widen, v.gap_face, v.gap_face_id, v.gap, false};
    out.reasons[k] = !model_reason_.empty() ? model_reason_ : v.reason;
    if (!out.reasons[k].empty()) r.meets_tolerance = false;
  }, 1024);
  if (sides_) sign_answers(points, out);
  for (size_t k = 0; k < out.answers.size(); ++k) {
    const auto& r = out.answers[k];
    FileLimit& limit = out.file_limits[k];
    out.uncertified += !out.reasons[k].empty();
    out.not_found += !r.found;
    if (!r.found) {
      out.over_reasons[k] = "no surface point found (every cell trimmed away)";
      continue;
    }
    if (!out.reasons[k].empty() || meets_tolerance(r, T)) continue;
    ++out.over_tolerance;
    if (r.meets_tolerance && limit.widen > 0.0 && within_tolerance(r.bound - limit.widen, T)) {
      limit.limited = true;
      ++out.limited_by_file;
      out.over_reasons[k] = fmt::format(
          "its bound {:.3g} is over the tolerance {:.3g} only by the file's precision: face {} (id {}) has edges up "
          "to {:.3g} off its surface near the answer, which widen the bound by {:.3g}",
          r.bound, T, limit.face, limit.face_id, limit.gap, limit.widen);
    } else if (!r.meets_tolerance) {
      out.over_reasons[k] = fmt::format(
          "its bound {:.3g} is over the tolerance {:.3g}: the search stopped at its budget (a larger tolerance)",
          r.bound, T);
    } else {
      out.over_reasons[k] = fmt::format(
          "its bound {:.3g} is over the tolerance {:.3g}: a point far from the model (the float slack grows with its "
          "distance; a finer tolerance or one point at a time)",
          r.bound, T);
    }
  }
  return out;
}

}  // namespace queries
