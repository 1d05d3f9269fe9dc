#include "queries/distance/point_batch.h"

#include "queries/distance/point_batch_descent.h"

#include "queries/distance/cell_triangles.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>

#include "gpgpu/layout.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/stopwatch.h"
#include "nurbs/trim_classify.h"
#include "queries/shaders.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();

int pow2_at_least(int n) {
  int p = 1;
  while (p < n) p *= 2;
  return p;
}

}  // namespace

double batch_grid_tolerance(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance) {
  if (faces.empty()) return tolerance;
  const BatchFloatFloor floor(faces);
  // The float terms at a point 2 radii from the centre (the model's box grown by its size).
  return std::max(0.5 * tolerance, tolerance - floor.budget - 2.0 * kFloatSlack * 3.0 * floor.radius);
}

BatchFloatFloor::BatchFloatFloor(const std::vector<nurbs::TrimmedSurface>& faces) {
  if (faces.empty()) return;
  glm::dvec3 lo(kInf), hi(-kInf);
  for (const nurbs::TrimmedSurface& f : faces) {
    const nurbs::Box box = nurbs::control_box(f.surface);
    lo = glm::min(lo, box.min), hi = glm::max(hi, box.max);
    budget = std::max(budget, float_budget(f.surface));
  }
  centre = 0.5 * (lo + hi);
  radius = 0.5 * glm::length(hi - lo);
}

double BatchFloatFloor::at(const glm::dvec3& p) const {
  return budget + 2.0 * kFloatSlack * (glm::length(p - centre) + radius);
}

long long estimate_batch_bytes(const PreparedModel& m, int atlas_side, PointBoxes boxes) {
  // Per atlas texel: points (RGBA32F) on the GPU, the samples, masks, slot and
  // trimmed-cell indices again on the CPU, the uploads' staging: about 100 bytes. Per pyramid
  // texel: oriented boxes 3 RGBA32F on the GPU and on the CPU (96 bytes), axis-aligned 2 (64).
  // Each with a fifth more (the measured peaks of the shared models at 1e-4 and 1e-5 lie below).
  constexpr long long kAtlasTexel = 120, kDriver = 160LL << 20;
  const long long pyramid_texel = boxes == PointBoxes::Oriented ? 115 : 77;
  std::vector<std::pair<int, int>> sizes;
  for (const nurbs::CertifiedGrid& cg : m.grids) sizes.emplace_back(int(cg.grid.u.size()), int(cg.grid.v.size()));
  std::vector<int> unpacked;
  long long bytes = kDriver;
  for (const AtlasPlan& plan :
       plan_atlases(sizes, atlas_side, static_cast<long long>(atlas_side) * atlas_side, unpacked)) {
    const long long w0 = pow2_at_least(plan.width), h0 = pow2_at_least(plan.height);  // the pyramid's level 0
    bytes += kAtlasTexel * plan.width * plan.height + pyramid_texel * (w0 * h0 * 4 / 3);
  }
  return bytes;
}

PreparedModel prepare_batch_geometry(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance,
                                     long long max_samples, int atlas_side, PointBoxes boxes, long long max_bytes) {
  try {
    PreparedModel m = prepare_geometry(faces, batch_grid_tolerance(faces, tolerance), max_samples);
    bool fits = estimate_batch_bytes(m, atlas_side, boxes) <= max_bytes;
    for (const nurbs::CertifiedGrid& g : m.grids)
      fits = fits && int(g.grid.u.size()) <= atlas_side && int(g.grid.v.size()) <= atlas_side;
    if (fits) return m;
  } catch (const GridLimitError&) {  // a face beyond max_samples at T: its coarse grid below
  }
  return prepare_geometry(faces, tolerance, max_samples, Search::CoarseToFine);
}


PointBatch::PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBoxes boxes) : gpu_(gpu), g_(m, boxes) {
  for (const FaceAtlas& fa : m.atlases) {
    // Level 0 padded to powers of two, so that every level halves exactly (mip sizes round down).
    const int w0 = pow2_at_least(fa.plan.width), h0 = pow2_at_least(fa.plan.height);
    int levels = 1;
    while ((std::max(w0, h0) >> levels) > 0) ++levels;
    Atlas at;
    at.w0 = w0, at.h0 = h0, at.levels = levels;
    const size_t index = size_t(&fa - m.atlases.data());
    // The axis-aligned pyramid on the GPU; the oriented one is built on the CPU below.
    if (g_.boxes == PointBoxes::Aabb) {
      at.lo = gpgpu::Texture(w0, h0, gpgpu::Format::RGBA32F, levels);
      at.hi = gpgpu::Texture(w0, h0, gpgpu::Format::RGBA32F, levels);
      build_aabb_pyramid(at, fa, index);
    }
    at.samples = fa.points.read();
    at.slot_of = fa.slot_of.read();
    at.mask = fa.mask.read();
    at.crossed = m.crossed[index].read();
    upload_trim_cells(at, index);
    if (g_.boxes == PointBoxes::Oriented) build_oriented_pyramid(at, index);
    g_.atlases.push_back(std::move(at));
  }
}

void PointBatch::build_aabb_pyramid(Atlas& at, const FaceAtlas& fa, size_t index) {
  const glm::vec3 o(g_.m.centre);
  gpgpu::Program& fill = queries::program(gpu_, "fill_constant.frag");
  for (gpgpu::Texture* t : {&at.lo, &at.hi}) {  // empty boxes in the padding
    const float v = t == &at.lo ? kInfF : -kInfF;
    fill.set("u_value", v, v, v, v);
    gpgpu::Texture* out[] = {t};
    gpu_.run("point_batch_empty", fill, {}, out);
  }
  gpgpu::Texture no_growth(std::max<int>(1, int(fa.plan.slots.size())), 1, gpgpu::Format::R32F);
  no_growth.upload(std::vector<float>(size_t(no_growth.width()), 0.0f));
  gpgpu::Program& leaf = queries::program(gpu_, "aabb_leaf.frag", {{"TRIM_CROSSED", "1"}});
  const glm::mat4 identity(1.0f);
  leaf.set_mat4("u_motion", &identity[0][0]);
  leaf.set("u_origin", o.x, o.y, o.z);
  const gpgpu::Input in[] = {{"u_points", &fa.points},
                             {"u_slot_of", &fa.slot_of},
                             {"u_mask", &fa.mask},
                             {"u_grow", &no_growth},
                             {"u_crossed", &g_.m.crossed[index]}};
  gpgpu::Texture* boxes[] = {&at.lo, &at.hi};
  gpu_.run("point_batch_leaf", leaf, in, boxes, gpgpu::Region{0, 0, fa.plan.width, fa.plan.height});
  gpgpu::Program& merge = queries::program(gpu_, "aabb_merge.frag");
  for (int l = 1; l < at.levels; ++l) {
    const gpgpu::Input fine[] = {{"u_lo", &at.lo, l - 1}, {"u_hi", &at.hi, l - 1}};
    gpu_.run("point_batch_merge", merge, fine, boxes, std::nullopt, l);
  }
}







std::vector<PointDistance> PointBatch::query(std::span<const glm::dvec3> points, std::span<const double> within) {
  if (!within.empty() && within.size() != points.size())
    throw std::invalid_argument("PointBatch::query: one `within` per point, or none");
  if (points.size() > points_per_pass_) {  // pass by pass, figures summed
    PointBatchStats total;
    std::vector<PointDistance> out;
    out.reserve(points.size());
    const auto progress = std::move(progress_);  // the parts report none of their own
    progress_ = nullptr;
    for (size_t s = 0; s < points.size(); s += points_per_pass_) {
      const size_t count = std::min(points_per_pass_, points.size() - s);
      const auto part = query(points.subspan(s, count), within.empty() ? within : within.subspan(s, count));
      out.insert(out.end(), part.begin(), part.end());
      if (progress) progress(s + count, points.size());
      total.points += stats_.points, total.cells_tested += stats_.cells_tested, total.fallbacks += stats_.fallbacks;
      total.trimmed += stats_.trimmed;
      total.cut += stats_.cut;
      total.refined_cells += stats_.refined_cells;
      total.gpu_seconds += stats_.gpu_seconds, total.cpu_seconds += stats_.cpu_seconds;
    }
    stats_ = total;
    progress_ = progress;
    return out;
  }
  stats_ = {};
  stats_.points = static_cast<long long>(points.size());
  const bool on_gpu = engine_ == BatchEngine::Gpu;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::vector<BatchCell>> cells;
  if (on_gpu) cells = descend_gpu(points, within);
  stats_.gpu_seconds = on_gpu ? nurbs::seconds_since(t0) : 0.0;
  const auto t1 = std::chrono::steady_clock::now();
  // The searches of points whose winner is trimmed, the points whose walk was cut, the refinement's
  // candidates and the CPU engine read the CPU pyramids: built before the threads.
  bool any_cut = false;
  for (const auto& per_atlas : cells)
    for (const BatchCell& c : per_atlas) any_cut |= c.cut;
  bool trimmed = false;
  for (size_t f = 0; f < g_.m.faces.size(); ++f) trimmed |= !g_.m.faces[f].loops.empty();
  if (g_.boxes == PointBoxes::Aabb && (!on_gpu || any_cut || trimmed || g_.m.search == Search::CoarseToFine))
    for (size_t a = 0; a < g_.atlases.size(); ++a) build_cpu_pyramid(g_, a, g_.atlases[a]);
  // Per point independent work on the CPU (the pass is over): one contiguous share per thread, at
  // least 128 points each (the tests' batches of hundreds run on two threads).
  std::vector<PointDistance> out(points.size());
  const size_t threads = nurbs::share_count(points.size(), on_gpu ? 128 : 16);
  std::vector<long long> fallbacks(threads, 0), in_trim(threads, 0), tested(threads, 0), cut(threads, 0),
      refined(threads, 0);
  // The points along a Morton curve, as the GPU pass lays them out: neighbours walk the same boxes
  // and cells, which then stay in the caches (in input order each point fetches its own).
  const std::vector<uint32_t> order = morton_order(points, g_.m.centre, 2.0 * g_.radius);
  const BatchFinish finish = finishing();
  nurbs::for_shares(points.size(), threads, [&](size_t t, size_t begin, size_t end) {
    std::vector<BatchCell> best(g_.atlases.size());
    for (size_t k = begin; k < end; ++k) {
      const size_t i = order[k];
      const double wanted = within.empty() ? 0.0 : within[i];
      if (on_gpu) {
        bool was_cut = false;
        for (size_t a = 0; a < g_.atlases.size(); ++a) {
          best[a] = cells[a][i];
          if (best[a].cut)  // the twin's walk
            best[a] = queries::descend_cpu(g_, a, points[i], wanted, trim_on_gpu_), was_cut = true;
        }
        cut[t] += was_cut;
      } else {  // the twin's walk in every atlas, pruned by the best cell of the atlases before
        double w = wanted;
        for (size_t a = 0; a < g_.atlases.size(); ++a) {
          best[a] = queries::descend_cpu(g_, a, points[i], w, trim_on_gpu_);
          if (best[a].x >= 0) w = best[a].distance;
        }
      }
      out[i] = finish.finish(points[i], best, fallbacks[t], in_trim[t], wanted);
      tested[t] += out[i].candidates;
      refined[t] += out[i].refined_cells;
    }
  });
  for (size_t t = 0; t < threads; ++t)
    stats_.fallbacks += fallbacks[t], stats_.trimmed += in_trim[t], stats_.cells_tested += tested[t],
        stats_.cut += cut[t], stats_.refined_cells += refined[t];
  stats_.cpu_seconds = nurbs::seconds_since(t1);
  return out;
}

void PointBatch::ensure_uploaded(Atlas& at, size_t a) {
  if (at.uploaded) return;
  at.upload_trim_textures(g_.m.atlases[a].plan);
  if (g_.boxes == PointBoxes::Oriented) at.upload_oriented_pyramid();
  at.uploaded = true;
}

BatchCell PointBatch::descend_cpu(size_t a, const glm::dvec3& p, double within) {
  if (g_.boxes == PointBoxes::Aabb) build_cpu_pyramid(g_, a, g_.atlases[a]);  // the oriented one exists from the start
  return queries::descend_cpu(g_, a, p, within, trim_on_gpu_);
}

PointDistance PointBatch::query_cpu(const glm::dvec3& p, double within) {
  std::vector<BatchCell> best;
  for (size_t a = 0; a < g_.atlases.size(); ++a) best.push_back(descend_cpu(a, p, within));  // builds the pyramids
  long long fallbacks = 0, trimmed = 0;
  return finishing().finish(p, best, fallbacks, trimmed, within);
}

const std::vector<float>& PointBatch::cpu_level(size_t a, int level, bool hi) {
  build_cpu_pyramid(g_, a, g_.atlases[a]);
  return (hi ? g_.atlases[a].cpu_hi : g_.atlases[a].cpu_lo)[size_t(level)];
}

std::vector<float> PointBatch::gpu_level(size_t a, int level, bool hi) const {
  return (hi ? g_.atlases[a].hi : g_.atlases[a].lo).read_level(level);
}

PointBatch::PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBatchState state)
    : gpu_(gpu), g_(m, PointBoxes::Oriented) {
  if (state.atlases.size() != m.atlases.size())
    throw std::invalid_argument("PointBatch: the state is of another model");
  for (PointBatchState::Atlas& sa : state.atlases) {
    Atlas at;
    at.w0 = sa.w0, at.h0 = sa.h0, at.levels = sa.levels;
    at.samples = std::move(sa.samples), at.slot_of = std::move(sa.slot_of), at.mask = std::move(sa.mask);
    at.crossed = std::move(sa.crossed), at.trim_cell = std::move(sa.trim_cell);
    at.trim_head = std::move(sa.trim_head), at.trim_segs = std::move(sa.trim_segs);
    const size_t texels = size_t(sa.plan.width) * size_t(sa.plan.height);
    if (at.samples.size() != 4 * texels || at.slot_of.size() != texels || at.mask.size() != texels ||
        at.crossed.size() != texels || at.trim_cell.size() != texels || sa.obb.size() != size_t(at.levels))
      throw std::invalid_argument("PointBatch: the state's arrays do not match its atlas");
    at.cpu_obb.assign(size_t(at.levels), {});
    for (int l = 0; l < at.levels; ++l) {
      const size_t n = size_t(at.level_width(l)) * size_t(at.level_height(l));
      PointBatchState::Level& in = sa.obb[size_t(l)];
      Atlas::ObbLevel& out = at.cpu_obb[size_t(l)];
      for (size_t k = 0; k < 3; ++k)
        if (in.boxes[k].size() != 4 * in.texels.size()) throw std::invalid_argument("PointBatch: a bad state level");
      out.index.assign(n, -1);
      for (size_t t = 0; t < in.texels.size(); ++t) {
        if (in.texels[t] >= n || (t > 0 && in.texels[t] <= in.texels[t - 1]))
          throw std::invalid_argument("PointBatch: a state texel outside its level or out of order");
        out.index[in.texels[t]] = int32_t(t);
      }
      out.texels = std::move(in.texels), out.boxes = std::move(in.boxes);
    }
    g_.atlases.push_back(std::move(at));
  }
}

PointBatchStateView PointBatch::state_view() const {
  if (g_.boxes != PointBoxes::Oriented) throw std::logic_error("PointBatch::state_view: oriented boxes only");
  PointBatchStateView s;
  for (size_t a = 0; a < g_.atlases.size(); ++a) {
    const Atlas& at = g_.atlases[a];
    PointBatchStateView::Atlas& sa = s.atlases.emplace_back();
    sa.plan = &g_.m.atlases[a].plan;
    sa.w0 = at.w0, sa.h0 = at.h0, sa.levels = at.levels;
    sa.samples = at.samples, sa.slot_of = at.slot_of, sa.mask = at.mask, sa.crossed = at.crossed;
    sa.trim_cell = at.trim_cell, sa.trim_head = at.trim_head, sa.trim_segs = at.trim_segs;
    for (int l = 0; l < at.levels; ++l) {
      const Atlas::ObbLevel& level = at.cpu_obb[size_t(l)];
      sa.obb.push_back({level.texels, {level.boxes[0], level.boxes[1], level.boxes[2]}});
    }
  }
  return s;
}

PointBatchState PointBatch::export_state() const { return copy_state(state_view()); }

}  // namespace queries
