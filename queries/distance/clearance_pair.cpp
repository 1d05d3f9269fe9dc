#include "queries/distance/clearance_pair.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <limits>
#include <stdexcept>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/stopwatch.h"
#include "queries/distance/face_cull.h"
#include "queries/distance/refine.h"

namespace queries {

namespace {

/// `model` with only the body `spec` names (its index as the model lists them, or its name);
/// `model` itself when `spec` is empty. `option` and `file` name the request in the error.
nurbs::Model select_body(nurbs::Model model, const std::string& spec, const std::string& option,
                         const std::string& file) {
  if (spec.empty()) return model;
  int index = -1;
  for (size_t k = 0; k < model.bodies.size() && index < 0; ++k)
    if (model.bodies[k].name == spec) index = int(k);
  if (index < 0 && spec.find_first_not_of("0123456789") == std::string::npos && spec.size() < 9)
    index = std::stoi(spec) < int(model.bodies.size()) ? std::stoi(spec) : -1;
  if (index < 0)
    throw nurbs::RequestError(fmt::format("{}: {} has no body '{}' ({} bodies; `nurbsgl info {}` lists them)", option,
                                          file, spec, model.bodies.size(), file));
  nurbs::Body body = std::move(model.bodies[static_cast<size_t>(index)]);
  model.bodies.clear();
  model.bodies.push_back(std::move(body));
  return model;
}

/// The box of b's corners mapped by m.
nurbs::Box moved(const nurbs::Box& b, const glm::dmat4& m) {
  nurbs::Box out{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 q(m * glm::dvec4((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                                      (k & 4) ? b.max.z : b.min.z, 1.0));
    out.min = glm::min(out.min, q), out.max = glm::max(out.max, q);
  }
  return out;
}

nurbs::Box faces_box(const std::vector<nurbs::TrimmedSurface>& faces) {
  nurbs::Box box{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
  for (const nurbs::TrimmedSurface& f : faces) {
    const nurbs::Box c = nurbs::control_box(f.surface);
    box.min = glm::min(box.min, c.min), box.max = glm::max(box.max, c.max);
  }
  return box;
}

bool any_trimmed(const std::vector<nurbs::TrimmedSurface>& faces) {
  return std::any_of(faces.begin(), faces.end(), [](const auto& f) { return !f.loops.empty(); });
}

}  // namespace

ClearanceOptions ClearanceOptions::paper() const {
  ClearanceOptions o = *this;
  o.search = Search::Faithful;
  o.face_cull = false;
  o.voxel_stage = true;
  o.voxels = 40;
  o.engine = EngineChoice::Gpu;
  o.limits.reduce_block = 2;
  o.limits.compact_fanout = 4;
  o.limits.host_pairs = 0;
  o.limits.upper = ClearanceLimits::Upper::Boxes;
  o.limits.start_pairs = 1;
  return o;
}

std::vector<nurbs::PaperSwitch> ClearanceOptions::paper_switches() {
  return {{"search", "§5.1"},         {"face-cull", "§5.4"},          {"first-stage", "§5.4"}, {"voxels", "§6"},
          {"engine", "§5.1"},         {"reduce-block", "§1.1, §3.1"}, {"compact-fanout", "§1.1"},
          {"host-pairs", "§5.1"},     {"gpu-upper", "§5.2"},          {"start-pairs", "§5.1"}};
}

bool ClearanceAnswer::meets() const {
  const Clearance& c = clearance;
  return reason.empty() && c.found && c.meets_tolerance && within_tolerance(c.bound, tolerance);
}

bool ClearanceAnswer::limited_by_file() const {
  const Clearance& c = clearance;
  return reason.empty() && c.found && c.meets_tolerance && widen > 0.0 && !within_tolerance(c.bound, tolerance) &&
         within_tolerance(c.bound - widen, tolerance);
}

std::string ClearanceAnswer::file_precision() const {
  if (!limited_by_file()) return {};
  return fmt::format(
      "its bound {:.3g} is over the tolerance {:.3g} only by the file's precision: face {} (id {}) of {} has edges up "
      "to {:.3g} off its surface near the answer, which widen the bound by {:.3g} (certified to the file's precision)",
      clearance.bound, tolerance, gap_face, gap_face_id, gap_model, gap, widen);
}

std::string ClearanceAnswer::shortfall() const {
  if (meets()) return {};
  return limited_by_file() ? file_precision() : failure(true);
}

std::string ClearanceAnswer::failure(bool strict) const {
  const Clearance& c = clearance;
  if (!c.found) return "no pair of surface points found (every cell trimmed away?)";
  if (!reason.empty()) return "the answer is not certified: " + reason;
  if (meets()) return {};
  if (limited_by_file()) return strict ? file_precision() + " (strict)" : std::string();
  return fmt::format("the bound {:.3g} is over the tolerance {:.3g} (the refinement's budget ran out)", c.bound,
                     tolerance);
}

ClearancePair::ClearancePair(const nurbs::LoadedModel& a, const nurbs::LoadedModel* b, ClearanceOptions options,
                             gpgpu::Gpu* gpu, GpuStart start)
    : options_(std::move(options)), gpu_(gpu), start_(std::move(start)) {
  nurbs::require_relative_tolerance(options_.tolerance, "tolerance");
  const std::string file_a = a.path.string(), file_b = b ? b->path.string() : file_a;
  a_ = select_body(a.model, options_.body_a, "--body-a", file_a);
  // B is a model of its own unless it is A's file with the same body.
  if (b || options_.body_b != options_.body_a)
    b_ = select_body(b ? b->model : a.model, options_.body_b, "--body-b", file_b);
  const nurbs::Model& mb = model_b();
  const double scale_b = mb.unit_scale_to_mm / a_.unit_scale_to_mm;  // B in A's unit
  const double size_a = nurbs::checked_model_size(a_, file_a);
  size_ = b_ ? std::max(size_a, nurbs::checked_model_size(mb, file_b) * scale_b) : size_a;
  move_limit_ = nurbs::coordinate_limit(nurbs::model_box(a_)) + scale_b * nurbs::coordinate_limit(nurbs::model_box(mb));
  tolerance_ = options_.tolerance * size_;
  const nurbs::ModelReport& report_b = b ? b->report : a.report;
  // The reader's edge gaps widen the bounds near them (nurbs/model_report.h): the query aims that
  // much below the tolerance, up to half of it, so that an answer beside a gap still meets it.
  const double reserve = std::min(0.5 * tolerance_, std::max(a.report.largest_gap(), report_b.largest_gap()));
  grid_tolerance_ = clearance_model_tolerance(tolerance_ - reserve);
  model_reason_ = a.report.uncertified_reason(options_.accept_partial);
  if (model_reason_.empty() && b) model_reason_ = report_b.uncertified_reason(options_.accept_partial);
  fa_ = nurbs::world_faces(a_), fb_ = nurbs::world_faces(mb);
  if (scale_b != 1.0)
    for (nurbs::TrimmedSurface& f : fb_)
      for (glm::dvec3& p : f.surface.points) p *= scale_b;
  // The reader's doubts of either side, judged per answer against the other side's box in the
  // answer's frame.
  doubts_a_.emplace(fa_), doubts_b_.emplace(fb_);
  box_a_ = faces_box(fa_), box_b_ = faces_box(fb_);
  for (const nurbs::TrimmedSurface& f : fa_) boxes_a_.push_back(nurbs::control_box(f.surface));
  for (const nurbs::TrimmedSurface& f : fb_) boxes_b_.push_back(nurbs::control_box(f.surface));
  faces_a_ = fa_.size(), faces_b_ = fb_.size();
}

ClearancePair::~ClearancePair() = default;

std::string ClearancePair::engine_used() const {
  return cpu_queries_ > 0 && gpu_queries_ > 0 ? "cpu and gpu" : cpu_queries_ > 0 ? "cpu" : "gpu";
}

void ClearancePair::prepare(std::span<const glm::dmat4> frames) {
  if (prepared_) throw std::logic_error("ClearancePair::prepare: prepared already");
  prepared_ = true;
  const auto t0 = std::chrono::steady_clock::now();
  index_a_.resize(fa_.size()), index_b_.resize(fb_.size());
  for (size_t f = 0; f < fa_.size(); ++f) index_a_[f] = int(f);
  for (size_t f = 0; f < fb_.size(); ++f) index_b_[f] = int(f);
  // The kept faces' coarse grids as the whole models' (a part's smaller box would make them finer).
  const double coarse_a = coarse_tolerance(fa_, grid_tolerance_);
  const double coarse_b = coarse_tolerance(fb_, grid_tolerance_);
  // Before any grid: the faces that can hold the closest pair at every frame.
  if (options_.face_cull && !frames.empty()) {
    frames_.assign(frames.begin(), frames.end());
    cull_.on = true;
    const auto c0 = std::chrono::steady_clock::now();
    // The margin: far above the spatial error of a sample classified by trim polygons flattened
    // within 1e-6 of the domain.
    const FaceCull cull = cull_faces(fa_, fb_, frames, 1e-4 * size_);
    const auto keep = [](std::vector<nurbs::TrimmedSurface>& faces, std::vector<int>& index,
                         const std::vector<char>& flags) {
      std::vector<nurbs::TrimmedSurface> kept;
      std::vector<int> kept_index;
      for (size_t f = 0; f < faces.size(); ++f)
        if (flags[f]) kept.push_back(std::move(faces[f])), kept_index.push_back(index[f]);
      faces = std::move(kept), index = std::move(kept_index);
    };
    keep(fa_, index_a_, cull.keep_a), keep(fb_, index_b_, cull.keep_b);
    cull_.faces_a = fa_.size(), cull_.faces_b = fb_.size(), cull_.face_pairs = cull.pairs;
    cull_.upper = cull.upper;
    cull_.seconds = nurbs::seconds_since(c0);
  }
  trimmed_ = any_trimmed(fa_) || any_trimmed(fb_);
  // The search on the CPU alone (coarse grids, the cell pairs within an upper bound refined in
  // double) where the models are small enough that the GPU's set-up would cost more: tried per
  // query once the coarse grids exist, before any GL context; over its budget the GPU takes over.
  const bool cpu_possible = options_.search == Search::CoarseToFine && !options_.voxel_stage;
  if (options_.engine == EngineChoice::Cpu && !cpu_possible)
    throw nurbs::RequestError("--engine cpu needs --search coarse-to-fine and --first-stage hierarchy");
  try {
    if (options_.engine != EngineChoice::Gpu && cpu_possible) {
      auto geometry = [&](std::vector<nurbs::TrimmedSurface>& faces, double coarse) {
        return std::async(std::launch::async, [&faces, this, coarse] {
          return prepare_geometry(std::move(faces), grid_tolerance_, options_.max_samples, options_.search, coarse);
        });
      };
      auto ga = geometry(fa_, coarse_a), gb = geometry(fb_, coarse_b);
      pair_.a = ga.get(), pair_.b = gb.get();
      // One query of models whose kept faces' coarse grids hold few cell pairs (a motion sequence
      // reuses A's hierarchy on the GPU from one motion to the next).
      try_cpu_ = options_.engine == EngineChoice::Cpu ||
                 (frames.size() == 1 && grid_cell_count(pair_.a) * grid_cell_count(pair_.b) <= kCpuClearanceStartPairs);
    } else {
      start_gpu();
      pair_ = prepare_pair(*gpu_, std::move(fa_), std::move(fb_), grid_tolerance_, options_.search,
                           options_.max_samples,
                           [&](const std::function<bool()>& geometry_done) {
                             compile_clearance_programs(*gpu_, options_.limits, options_.search, trimmed_,
                                                        geometry_done);
                           },
                           coarse_a, coarse_b);
      atlases_ = true;
    }
  } catch (const GridLimitError& e) {
    throw nurbs::RequestError(
        fmt::format("--tol {:g} --max-samples {}: {}", options_.tolerance, options_.max_samples, e.what()));
  }
  fa_.clear(), fb_.clear();
  if (!try_cpu_) ensure_gpu();
  // §5.4: the voxel grids once per model; per query the voxel pairs keep the faces that take part.
  if (options_.voxel_stage) {
    voxels_a_ = voxelize(pair_.a, {options_.voxels});
    voxels_b_ = voxelize(pair_.b, {options_.voxels});
  }
  if (gpu_) gpu_->finish();
  prepare_seconds_ = nurbs::seconds_since(t0);
}

void ClearancePair::start_gpu() {
  if (gpu_) return;
  if (start_) own_gpu_ = start_();
  if (!own_gpu_) throw std::logic_error("ClearancePair: the query needs a GL context and none was given");
  gpu_ = own_gpu_.get();
}

void ClearancePair::ensure_gpu() {
  if (gpu_ready_) return;
  gpu_ready_ = true;
  if (!atlases_) {  // the geometry alone so far: the GPU's set-up
    start_gpu();
    compile_clearance_programs(*gpu_, options_.limits, options_.search, trimmed_);
    try {
      prepare_atlases(*gpu_, pair_.a);
      prepare_atlases(*gpu_, pair_.b);
      atlases_ = true;
    } catch (const GridLimitError& e) {
      throw nurbs::RequestError(
          fmt::format("--tol {:g} --max-samples {}: {}", options_.tolerance, options_.max_samples, e.what()));
    }
  }
  gpu_->finish();
  if (options_.profile_queries) {  // the passes of the queries alone, each synchronised (Table 2 of the paper)
    gpu_->profiler().reset();
    gpu_->profiler().set_enabled(true);
    gpu_->profiler().set_sync(true);
  }
  cache_ = std::make_unique<ClearanceCache>();
}

Clearance ClearancePair::query_kept(const glm::dmat4& motion, ClearanceAnswer& out) {
  const PreparedModel &a = pair_.a, &b = pair_.b;
  // On the CPU the cell pairs start from those within the face cull's upper bound for this motion.
  if (try_cpu_) {
    const double upper = cull_faces(a.faces, b.faces, {&motion, 1}, 1e-4 * size_).upper;
    const long long budget = options_.engine == EngineChoice::Cpu ? -1 : kCpuClearanceStartPairs;
    if (auto c = clearance_cpu(a, b, motion, upper, budget)) {
      ++cpu_queries_;
      out.on_cpu = true;
      return *c;
    }
    ensure_gpu();
  }
  ++gpu_queries_;
  if (!options_.voxel_stage) return clearance(*gpu_, a, b, motion, nullptr, nullptr, options_.limits, cache_.get());
  const auto v0 = std::chrono::steady_clock::now();
  out.first_stage = voxel_stage(*gpu_, voxels_a_, voxels_b_, motion);
  out.first_stage_seconds = nurbs::seconds_since(v0);
  return clearance(*gpu_, a, b, motion, &out.first_stage->faces_a, &out.first_stage->faces_b, options_.limits);
}

ClearanceAnswer ClearancePair::query(const glm::dmat4& motion) {
  if (!prepared_) prepare({});
  if (!frames_.empty() && std::find(frames_.begin(), frames_.end(), motion) == frames_.end())
    throw std::invalid_argument("ClearancePair::query: the faces were culled for other placements of B");
  const auto t0 = std::chrono::steady_clock::now();
  ClearanceAnswer out;
  out.tolerance = tolerance_;
  Clearance c = query_kept(motion, out);
  out.seconds = nurbs::seconds_since(t0);
  // Widens c's bound by the gaps within reach; why it is not certified (empty: it may be).
  out.reason = model_reason_;
  if (!doubts_a_->empty() || !doubts_b_->empty()) {
    // Each side's gaps judged against the other's face boxes in its frame (docs/distance.md, "The
    // file's precision"). The witnesses: each answer point lies within its side's K (at most b) of
    // that side's faces (an exact surface point after the refinement, on a grid triangle before it),
    // so those face points lie within d + b of each other.
    const double d = c.distance, b = c.bound;
    const double low = std::isfinite(d - b) ? std::max(0.0, d - b) : 0.0;
    const double reach = low + doubts_a_->largest_gap() + doubts_b_->largest_gap();
    const glm::dmat4 back = glm::inverse(motion);
    std::vector<nurbs::Box> b_in_a, a_in_b;
    for (const nurbs::Box& x : boxes_b_) b_in_a.push_back(moved(x, motion));
    for (const nurbs::Box& x : boxes_a_) a_in_b.push_back(moved(x, back));
    std::optional<nurbs::FaceDoubts::Witness> wa, wb;
    if (c.found && glm::length(c.point_a - c.point_b) <= d * (1.0 + 1e-12) + 1e-300 && std::isfinite(b))
      wa = nurbs::FaceDoubts::Witness{c.point_a, b},
      wb = nurbs::FaceDoubts::Witness{glm::dvec3(back * glm::dvec4(c.point_b, 1.0)), b};
    const nurbs::FaceDoubts::Side sa = doubts_a_->side(b_in_a, low, reach, d, b, wa);
    const nurbs::FaceDoubts::Side sb = doubts_b_->side(a_in_b, low, reach, d, b, wb);
    const nurbs::FaceDoubts::Verdict v = nurbs::FaceDoubts::clearance(sa, sb, d, b);
    out.widen = v.widen;
    if (v.widen > 0.0) {
      const bool on_a = std::max(sa.gap, sa.cut) >= std::max(sb.gap, sb.cut);
      out.gap_model = on_a ? "A" : "B";
      out.gap_face = v.gap_face;  // the doubts index every face of the body, before the cull
      out.gap_face_id = v.gap_face_id, out.gap = v.gap;
    }
    c.bound += out.widen;
    if (out.reason.empty())
      out.reason = !sa.verdict.reason.empty() ? "A: " + sa.verdict.reason
                   : !sb.verdict.reason.empty() ? "B: " + sb.verdict.reason
                                                : "";
  }
  if (!out.reason.empty()) c.meets_tolerance = false;
  if (c.face_a >= 0) c.face_a = index_a_[size_t(c.face_a)];
  if (c.face_b >= 0) c.face_b = index_b_[size_t(c.face_b)];
  out.clearance = std::move(c);
  return out;
}

}  // namespace queries
