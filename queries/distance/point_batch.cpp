#include "queries/distance/point_batch.h"

#include "queries/distance/cell_triangles.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <queue>
#include <stdexcept>
#include <thread>
#include <utility>

#include "gpgpu/layout.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
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

/// Indices of `points` sorted by the Morton code of their position in the cube of half side
/// `half` about `centre` (10 bits per axis, outside points clamped to its faces).
std::vector<uint32_t> morton_order(std::span<const glm::dvec3> points, const glm::dvec3& centre, double half) {
  const auto spread = [](uint32_t v) {  // 10 bits -> every third of 30
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    return (v | (v << 2)) & 0x09249249u;
  };
  std::vector<std::pair<uint32_t, uint32_t>> keyed(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 t = glm::clamp((points[i] - centre) / (2.0 * std::max(half, 1e-300)) + 0.5, 0.0, 1.0);
    const glm::uvec3 c(t * 1023.0);
    keyed[i] = {spread(c.x) | (spread(c.y) << 1) | (spread(c.z) << 2), uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(points.size());
  for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
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

void PointBatch::init_model() {
  const PreparedModel& m = m_;
  glm::dvec3 lo(kInf), hi(-kInf);
  double k = 0.0, budget = 0.0;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    k = std::max(k, m.grids[f].k_e);
    budget = std::max(budget, float_budget(m.faces[f].surface));
    const nurbs::Box box = nurbs::control_box(m.faces[f].surface);
    lo = glm::min(lo, box.min);
    hi = glm::max(hi, box.max);
  }
  model_bound_ = k + budget;
  budget_.resize(m.faces.size()), grow_.resize(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    budget_[f] = float_budget(m.faces[f].surface);
    grow_[f] = m.grids[f].k_e + budget_[f];
  }
  grow_max_ = grow_.empty() ? 0.0 : *std::max_element(grow_.begin(), grow_.end());
  trim_edges_.resize(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f)
    if (!m.faces[f].loops.empty()) trim_edges_[f] = TrimEdges(m.trims[f], m.grids[f].grid);
  radius_ = m.faces.empty() ? 0.0 : 0.5 * glm::length(hi - lo);
}

PointBatch::PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBoxes boxes) : gpu_(gpu), m_(m), boxes_(boxes) {
  init_model();
  for (const FaceAtlas& fa : m.atlases) {
    // Level 0 padded to powers of two, so that every level halves exactly (mip sizes round down).
    const int w0 = pow2_at_least(fa.plan.width), h0 = pow2_at_least(fa.plan.height);
    int levels = 1;
    while ((std::max(w0, h0) >> levels) > 0) ++levels;
    Atlas at;
    at.w0 = w0, at.h0 = h0, at.levels = levels;
    const size_t index = size_t(&fa - m.atlases.data());
    // The axis-aligned pyramid on the GPU; the oriented one is built on the CPU below.
    if (boxes_ == PointBoxes::Aabb) {
      at.lo = gpgpu::Texture(w0, h0, gpgpu::Format::RGBA32F, levels);
      at.hi = gpgpu::Texture(w0, h0, gpgpu::Format::RGBA32F, levels);
      build_aabb_pyramid(at, fa, index);
    }
    at.samples = fa.points.read();
    at.slot_of = fa.slot_of.read();
    at.mask = fa.mask.read();
    at.crossed = m.crossed[index].read();
    upload_trim_cells(at, index);
    if (boxes_ == PointBoxes::Oriented) build_oriented_pyramid(at, index);
    atlases_.push_back(std::move(at));
  }
}

void PointBatch::build_aabb_pyramid(Atlas& at, const FaceAtlas& fa, size_t index) {
  const glm::vec3 o(m_.centre);
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
                             {"u_crossed", &m_.crossed[index]}};
  gpgpu::Texture* boxes[] = {&at.lo, &at.hi};
  gpu_.run("point_batch_leaf", leaf, in, boxes, gpgpu::Region{0, 0, fa.plan.width, fa.plan.height});
  gpgpu::Program& merge = queries::program(gpu_, "aabb_merge.frag");
  for (int l = 1; l < at.levels; ++l) {
    const gpgpu::Input fine[] = {{"u_lo", &at.lo, l - 1}, {"u_hi", &at.hi, l - 1}};
    gpu_.run("point_batch_merge", merge, fine, boxes, std::nullopt, l);
  }
}

double PointBatch::slack(const glm::dvec3& p) const { return kFloatSlack * (glm::length(p - m_.centre) + radius_); }

std::vector<std::vector<BatchCell>> PointBatch::descend_gpu(std::span<const glm::dvec3> points,
                                                            std::span<const double> within) {
  std::vector<std::vector<BatchCell>> out(atlases_.size());
  if (points.empty()) return out;
  // Neighbouring fragments run in lockstep (SIMD lanes, warps), each as long as its slowest point:
  // points sorted along a Morton curve and laid out in 4 x 4 tiles keep the lanes' paths alike.
  const std::vector<uint32_t> order = morton_order(points, m_.centre, 2.0 * radius_);
  const int max_size = std::min(gpu_.info().max_texture_size, kAtlasSide);
  int width = 4;
  while (width < max_size && int64_t(width) * width < int64_t(points.size())) width *= 2;
  const int64_t tiles_per_row = width / 4, tiles = (int64_t(points.size()) + 15) / 16;
  const int height = int(4 * ((tiles + tiles_per_row - 1) / tiles_per_row));
  if (height > max_size) throw std::length_error(fmt::format("PointBatch: {} points in one batch", points.size()));
  const auto texel_of = [&](size_t i) {  // slot i of the sorted points -> texel index
    const int64_t tile = int64_t(i >> 4), t = int64_t(i & 15);
    return size_t((4 * (tile / tiles_per_row) + (t >> 2)) * width + 4 * (tile % tiles_per_row) + (t & 3));
  };
  std::vector<float> q(size_t(width) * size_t(height) * 4, 0.0f);
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::vec3 d(points[order[i]] - m_.centre);
    std::copy_n(&d.x, 3, q.begin() + ptrdiff_t(4 * texel_of(i)));
    if (!within.empty()) q[4 * texel_of(i) + 3] = float(std::max(within[order[i]], 0.0));
  }
  gpgpu::PooledTexture pts = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  pts->upload(q);
  gpgpu::PooledTexture res = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  const bool oriented = boxes_ == PointBoxes::Oriented;
  gpgpu::Program& prog =
      oriented ? queries::program(gpu_, "point_batch.frag", {{"ORIENTED", "1"}}) : queries::program(gpu_, "point_batch.frag");
  const glm::vec3 o(m_.centre);
  prog.set("u_origin", o.x, o.y, o.z);
  prog.set("u_count", int(points.size()));
  prog.set("u_width", width);
  prog.set("u_slack", float(kFloatSlack));
  prog.set("u_radius", float(radius_));
  prog.set("u_two", 2);
  prog.set("u_trim_width", kTrimTextureWidth);
  prog.set("u_trim_on", trim_on_gpu_ ? 1 : 0);
  for (size_t a = 0; a < atlases_.size(); ++a) {
    prog.set("u_top", atlases_[a].levels - 1);
    prog.set("u_size", atlases_[a].w0, atlases_[a].h0);
    Atlas& at = atlases_[a];
    ensure_uploaded(at, a);
    const gpgpu::Input in_aabb[] = {{"u_points", pts.get()},
                                    {"u_lo", &at.lo},
                                    {"u_hi", &at.hi},
                                    {"u_samples", &m_.atlases[a].points},
                                    {"u_trim_cell", &at.trim_cell_tex},
                                    {"u_trim_head", &at.trim_head_tex},
                                    {"u_trim_segs", &at.trim_segs_tex}};
    const gpgpu::Input in_obb[] = {{"u_points", pts.get()},
                                   {"u_obb0", &at.obb[0]},
                                   {"u_obb1", &at.obb[1]},
                                   {"u_obb2", &at.obb[2]},
                                   {"u_samples", &m_.atlases[a].points},
                                   {"u_trim_cell", &at.trim_cell_tex},
                                   {"u_trim_head", &at.trim_head_tex},
                                   {"u_trim_segs", &at.trim_segs_tex}};
    gpgpu::Texture* target[] = {res.get()};
    if (oriented)
      gpu_.run("point_batch", prog, in_obb, target);
    else
      gpu_.run("point_batch", prog, in_aabb, target);
    const std::vector<float> r = res->read();
    out[a].resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const float* v = &r[4 * texel_of(i)];
      const bool cut = v[3] < 0.0f;
      out[a][order[i]] = {double(v[0]), int(v[1]), int(v[2]), (long long)(cut ? -1.0f - v[3] : v[3]), cut};
    }
  }
  return out;
}

FaceCell PointBatch::cell_corners(size_t a, int x, int y, glm::dvec3 corners[4]) const {
  const Atlas& at = atlases_[a];
  const AtlasPlan& plan = m_.atlases[a].plan;
  const AtlasSlot& sl = plan.slots[size_t(at.slot_of[size_t(y) * size_t(plan.width) + size_t(x)])];
  for (int k = 0; k < 4; ++k) {
    const float* s = &at.samples[4 * (size_t(y + (k >> 1)) * size_t(plan.width) + size_t(x + (k & 1)))];
    corners[k] = glm::dvec3(s[0], s[1], s[2]);
  }
  return {sl.face, x - sl.x, y - sl.y};
}

PointDistance PointBatch::cell_result(const glm::dvec3& p, size_t a, int x, int y, bool trim_edge, int triangle) const {
  glm::dvec3 corner[4];
  const FaceCell cell = cell_corners(a, x, y, corner);
  const auto f = size_t(cell.face);
  const int i = cell.i, j = cell.j;
  const nurbs::ParamGrid& g = m_.grids[f].grid;
  // The cell's two triangles (cell_triangles.h), with their corners' parameters.
  const CellTriangles tri =
      cell_triangles(corner, g.u[size_t(i)], g.u[size_t(i) + 1], g.v[size_t(j)], g.v[size_t(j) + 1]);
  PointDistance r;
  r.distance = kInf;
  for (int t = 0; t < 2; ++t) {
    if (triangle >= 0 && t != triangle) continue;
    glm::dvec3 w;
    const glm::dvec3 c = closest_on_triangle(p, tri.p[t][0], tri.p[t][1], tri.p[t][2], w);
    const double d = glm::length(c - p);
    if (d < r.distance) r.distance = d, r.point = c, r.uv = tri.uv_at(t, w);
  }
  r.found = true;
  r.face = cell.face;
  if (trim_edge && !m_.faces[f].loops.empty())
    for (int c = 0; c < 4; ++c)
      if (!trim_edges_[f].is_material({g.u[size_t(i + (c & 1))], g.v[size_t(j + (c >> 1))]})) r.on_trim_edge = true;
  const double k = model_bound_ + 2.0 * slack(p);
  r.bound = k;
  r.point_bound = std::sqrt(4 * k * r.distance + k * k);
  return r;
}

bool PointBatch::material(const PointDistance& r) const {
  const auto f = size_t(r.face);
  return m_.faces[f].loops.empty() || trim_edges_[f].is_material(r.uv);
}

PointDistance PointBatch::finish(const glm::dvec3& p, const std::vector<BatchCell>& best, long long& fallbacks,
                                 long long& trimmed, double within) const {
  size_t win = best.size();
  long long tested = 0;
  for (size_t a = 0; a < best.size(); ++a) {
    tested += best[a].tested;
    if (best[a].x >= 0 && (win == best.size() || best[a].distance < best[win].distance)) win = a;
  }
  PointDistance r;
  if (win < best.size()) r = cell_result(p, win, best[win].x, best[win].y);
  if (r.found && !material(r)) {  // §5.3: the closest triangle point lies in a trimmed region
    ++trimmed;
    if (trim_on_gpu_) r = material_cell(p, win, best[win].x, best[win].y);
    if (!trim_on_gpu_ || !r.found) {  // (or the float pass judged a point within rounding of a trim edge)
      ++fallbacks;
      r = search_material(p, within);
    }
  }
  r.candidates = tested;
  if (m_.search == Search::CoarseToFine) return refine(p, r, within, m_.tolerance);
  if (refine_to_ > 0.0 && r.found && r.bound > refine_to_) return refine(p, r, within, refine_to_);
  return r;
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
  stats_.gpu_seconds = on_gpu ? seconds_since(t0) : 0.0;
  const auto t1 = std::chrono::steady_clock::now();
  // The searches of points whose winner is trimmed, the points whose walk was cut, the refinement's
  // candidates and the CPU engine read the CPU pyramids: built before the threads.
  bool any_cut = false;
  for (const auto& per_atlas : cells)
    for (const BatchCell& c : per_atlas) any_cut |= c.cut;
  bool trimmed = false;
  for (size_t f = 0; f < m_.faces.size(); ++f) trimmed |= !m_.faces[f].loops.empty();
  if (boxes_ == PointBoxes::Aabb && (!on_gpu || any_cut || trimmed || m_.search == Search::CoarseToFine))
    for (Atlas& at : atlases_) build_cpu_pyramid(at);
  // Per point independent work on the CPU (the pass is over): one contiguous share per thread, at
  // least 128 points each (the tests' batches of hundreds run on two threads).
  std::vector<PointDistance> out(points.size());
  const size_t threads = nurbs::share_count(points.size(), on_gpu ? 128 : 16);
  std::vector<long long> fallbacks(threads, 0), in_trim(threads, 0), tested(threads, 0), cut(threads, 0),
      refined(threads, 0);
  // The points along a Morton curve, as the GPU pass lays them out: neighbours walk the same boxes
  // and cells, which then stay in the caches (in input order each point fetches its own).
  const std::vector<uint32_t> order = morton_order(points, m_.centre, 2.0 * radius_);
  nurbs::for_shares(points.size(), threads, [&](size_t t, size_t begin, size_t end) {
    std::vector<BatchCell> best(atlases_.size());
    for (size_t k = begin; k < end; ++k) {
      const size_t i = order[k];
      const double wanted = within.empty() ? 0.0 : within[i];
      if (on_gpu) {
        bool was_cut = false;
        for (size_t a = 0; a < atlases_.size(); ++a) {
          best[a] = cells[a][i];
          if (best[a].cut)  // the twin's walk
            best[a] = descend_cpu(a, points[i], wanted), was_cut = true;
        }
        cut[t] += was_cut;
      } else {  // the twin's walk in every atlas, pruned by the best cell of the atlases before
        double w = wanted;
        for (size_t a = 0; a < atlases_.size(); ++a) {
          best[a] = descend_cpu(a, points[i], w);
          if (best[a].x >= 0) w = best[a].distance;
        }
      }
      out[i] = finish(points[i], best, fallbacks[t], in_trim[t], wanted);
      tested[t] += out[i].candidates;
      refined[t] += out[i].refined_cells;
    }
  });
  for (size_t t = 0; t < threads; ++t)
    stats_.fallbacks += fallbacks[t], stats_.trimmed += in_trim[t], stats_.cells_tested += tested[t],
        stats_.cut += cut[t], stats_.refined_cells += refined[t];
  stats_.cpu_seconds = seconds_since(t1);
  return out;
}

void PointBatch::ensure_uploaded(Atlas& at, size_t a) {
  if (at.uploaded) return;
  at.upload_trim_textures(m_.atlases[a].plan);
  if (boxes_ == PointBoxes::Oriented) at.upload_oriented_pyramid();
  at.uploaded = true;
}

std::vector<float> PointBatch::gpu_level(size_t a, int level, bool hi) const {
  return (hi ? atlases_[a].hi : atlases_[a].lo).read_level(level);
}

PointBatch::PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBatchState state)
    : gpu_(gpu), m_(m), boxes_(PointBoxes::Oriented) {
  if (state.atlases.size() != m.atlases.size())
    throw std::invalid_argument("PointBatch: the state is of another model");
  init_model();
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
    atlases_.push_back(std::move(at));
  }
}

PointBatchStateView PointBatch::state_view() const {
  if (boxes_ != PointBoxes::Oriented) throw std::logic_error("PointBatch::state_view: oriented boxes only");
  PointBatchStateView s;
  for (size_t a = 0; a < atlases_.size(); ++a) {
    const Atlas& at = atlases_[a];
    PointBatchStateView::Atlas& sa = s.atlases.emplace_back();
    sa.plan = &m_.atlases[a].plan;
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
