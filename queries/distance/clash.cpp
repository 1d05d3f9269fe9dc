#include "queries/distance/clash.h"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/request_error.h"
#include "nurbs/stopwatch.h"

namespace queries {

namespace {

/// Thrown by the GL start of a pair tried off the calling thread: the pair is answered again on
/// the calling thread, which holds the GL context.
struct NeedsGpu {};

/// Each body as a model of its own, with the whole file's report and path: ClearancePair then
/// copies one body per side, not the whole assembly per pair, and judges the reader's doubts as
/// for `--body-a I --body-b J` of the file.
std::vector<nurbs::LoadedModel> split_bodies(const nurbs::LoadedModel& m) {
  nurbs::Model shell = m.model;
  shell.bodies.clear();
  std::vector<nurbs::LoadedModel> parts(m.model.bodies.size());
  for (size_t k = 0; k < parts.size(); ++k) {
    parts[k].model = shell;
    parts[k].model.bodies.push_back(m.model.bodies[k]);
    parts[k].report = m.report;
    parts[k].path = m.path;
  }
  return parts;
}

/// The box of a body's faces' control points (world coordinates): it holds the body's surfaces.
nurbs::Box control_points_box(const nurbs::Model& body) {
  nurbs::Box box{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
  for (const nurbs::TrimmedSurface& f : nurbs::world_faces(body)) {
    const nurbs::Box c = nurbs::control_box(f.surface);
    box.min = glm::min(box.min, c.min), box.max = glm::max(box.max, c.max);
  }
  return box;
}

/// The pairs asked for, or every pair i < j; RequestError naming the file for one it cannot answer.
std::vector<std::pair<int, int>> pairs_of(const ClashOptions& o, int bodies, const std::string& file) {
  if (bodies < 2)
    throw nurbs::RequestError(fmt::format("{}: {} {}; a clash report needs at least two (`nurbsgl info {}` lists them)",
                                          file, bodies, bodies == 1 ? "body" : "bodies", file));
  std::vector<std::pair<int, int>> pairs = o.pairs;
  if (pairs.empty())
    for (int i = 0; i < bodies; ++i)
      for (int j = i + 1; j < bodies; ++j) pairs.emplace_back(i, j);
  for (const auto& [i, j] : pairs)
    if (i < 0 || j < 0 || i >= bodies || j >= bodies || i == j)
      throw nurbs::RequestError(
          fmt::format("pair ({}, {}): {} has bodies 0..{}, and a pair names two of them", i, j, file, bodies - 1));
  return pairs;
}

/// The row's clearance as `clearance --body-a I --body-b J` answers it: B in place (one frame, the
/// identity), prepared for that frame.
void answer(ClashRow& row, const std::vector<nurbs::LoadedModel>& parts, const ClearanceOptions& o, gpgpu::Gpu* gpu,
            GpuStart start) {
  ClearancePair pair(parts[size_t(row.body_a)], &parts[size_t(row.body_b)], o, gpu, std::move(start));
  const glm::dmat4 in_place(1.0);
  pair.prepare({&in_place, 1});
  row.answer = pair.query(in_place);
  row.computed = true;
  row.engine = pair.engine_used();
  row.prepare_seconds = pair.prepare_seconds();
}

/// Intersecting pairs first, then by distance, then the rows left out by box distance; ties by bodies.
bool row_before(const ClashRow& x, const ClashRow& y) {
  const auto key = [](const ClashRow& r) {
    const Clearance& c = r.answer.clearance;
    return std::make_tuple(!r.computed, r.computed && !c.intersecting, r.computed ? c.distance : r.box_distance);
  };
  const auto kx = key(x), ky = key(y);
  if (kx != ky) return kx < ky;
  return std::make_pair(x.body_a, x.body_b) < std::make_pair(y.body_a, y.body_b);
}

}  // namespace

bool ClashRow::beyond(double min_clearance) const {
  return !computed || (!answer.clearance.intersecting && answer.clearance.distance > min_clearance);
}

std::string ClashReport::failure(bool strict) const {
  std::string lines;
  size_t failing = 0;
  for (const ClashRow& r : rows)
    if (r.computed)
      if (const std::string why = r.answer.failure(strict); !why.empty())
        ++failing, lines += fmt::format("\n  bodies {} ({}) and {} ({}): {}", r.body_a, r.name_a, r.body_b, r.name_b, why);
  if (lines.empty()) return {};
  return fmt::format("{} of {} computed pairs not certified:{}", failing, computed, lines);
}

ClashReport clash_report(const nurbs::LoadedModel& model, const ClashOptions& options, gpgpu::Gpu* gpu,
                         GpuStart start) {
  const auto t0 = nurbs::Clock::now();
  const std::string file = model.path.empty() ? model.model.source : model.path.string();
  const int bodies = int(model.model.bodies.size());
  const std::vector<std::pair<int, int>> pairs = pairs_of(options, bodies, file);
  const std::vector<nurbs::LoadedModel> parts = split_bodies(model);
  std::vector<nurbs::Box> boxes;
  for (const nurbs::LoadedModel& p : parts) boxes.push_back(control_points_box(p.model));

  ClashReport report;
  report.bodies = size_t(bodies);
  report.min_clearance = options.min_clearance;
  report.rows.resize(pairs.size());
  std::vector<size_t> todo;  // rows to compute
  for (size_t k = 0; k < pairs.size(); ++k) {
    ClashRow& r = report.rows[k];
    r.body_a = pairs[k].first, r.body_b = pairs[k].second;
    r.name_a = model.model.bodies[size_t(r.body_a)].name, r.name_b = model.model.bodies[size_t(r.body_b)].name;
    r.box_distance = nurbs::box_distance(boxes[size_t(r.body_a)], boxes[size_t(r.body_b)]);
    if (!(r.box_distance > options.min_clearance)) todo.push_back(k);
  }

  std::mutex lock;
  size_t done = 0;
  const auto tick = [&] {
    std::lock_guard<std::mutex> hold(lock);
    ++done;
    if (options.progress) options.progress(done, todo.size());
  };
  ClearanceOptions q = options.clearance;
  q.body_a.clear(), q.body_b.clear();  // each part holds its body alone
  // The CPU first on the hardware threads, where ClearancePair would try it: the coarse-to-fine
  // search without the voxel stage, unless the GPU is asked for. The CPU engine's pairs stay there
  // too, where ClearancePair refuses the settings it cannot run (no GL context started for that).
  const bool cpu_first = q.engine == EngineChoice::Cpu ||
                         (q.engine == EngineChoice::Auto && q.search == Search::CoarseToFine && !q.voxel_stage);
  std::vector<size_t> on_gpu;
  if (cpu_first) {
    std::vector<char> needs_gpu(todo.size(), 0);
    std::vector<std::exception_ptr> errors(todo.size());
    nurbs::parallel_for(todo.size(), options.threads, [&](size_t t, int) {
      ClashRow& r = report.rows[todo[t]];
      try {
        answer(r, parts, q, nullptr, []() -> std::unique_ptr<gpgpu::Gpu> { throw NeedsGpu{}; });
        tick();
      } catch (const NeedsGpu&) {
        needs_gpu[t] = 1;
      } catch (...) {
        errors[t] = std::current_exception();
      }
    });
    // The first error in pair order, whatever thread met it first.
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
    for (size_t t = 0; t < todo.size(); ++t)
      if (needs_gpu[t]) on_gpu.push_back(todo[t]);
  } else {
    on_gpu = todo;
  }
  for (size_t k : on_gpu) {
    if (!gpu) {
      if (!start) throw std::logic_error("clash_report: a pair needs a GL context and none was given");
      report.gpu = start(), gpu = report.gpu.get();
    }
    ClashRow& r = report.rows[k];
    answer(r, parts, q, gpu, {});
    tick();
  }

  for (const ClashRow& r : report.rows) {
    if (!r.computed) {
      ++report.beyond_boxes;
      continue;
    }
    ++report.computed;
    report.intersecting += r.answer.clearance.intersecting;
    report.beyond_computed += r.beyond(options.min_clearance);
    report.uncertified += !r.answer.meets() && !r.answer.limited_by_file();
    report.limited_by_file += r.answer.limited_by_file();
    ++(r.answer.on_cpu ? report.cpu_pairs : report.gpu_pairs);
  }
  std::stable_sort(report.rows.begin(), report.rows.end(), row_before);
  report.seconds = nurbs::seconds_since(t0);
  return report;
}

}  // namespace queries
