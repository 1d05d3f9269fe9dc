#include "queries/distance/clearance.h"

#include "queries/distance/cell_triangles.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <tuple>

#include "gpgpu/compact.h"
#include "gpgpu/layout.h"
#include "gpgpu/polygon_fill.h"
#include "gpgpu/reduce.h"
#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/intersection.h"
#include "queries/distance/material_distance.h"
#include "queries/distance/refine.h"
#include "queries/shaders.h"

namespace queries {

bool upper_from_samples(const ClearanceLimits& limits, bool coarse_to_fine) {
  if (limits.upper != ClearanceLimits::Upper::Auto) return limits.upper == ClearanceLimits::Upper::Samples;
  return coarse_to_fine;
}

long long host_pairs_used(const ClearanceLimits& limits, bool coarse_to_fine) {
  return limits.host_pairs >= 0 ? limits.host_pairs : coarse_to_fine ? 65536 : 0;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The programs of a query, named once for the passes and for compile_clearance_programs.
// `samples`: with the face samples of ClearanceLimits::Upper::Samples (SAMPLE_UPPER).
gpgpu::Program& leaf_program(gpgpu::Gpu& gpu, bool samples) {
  if (samples) return queries::program(gpu, "aabb_leaf.frag", {{"TRIM_CROSSED", "1"}, {"SAMPLE_UPPER", "1"}});
  return queries::program(gpu, "aabb_leaf.frag", {{"TRIM_CROSSED", "1"}});
}
gpgpu::Program& merge_program(gpgpu::Gpu& gpu, bool samples) {
  return samples ? queries::program(gpu, "aabb_merge.frag", {{"SAMPLE_UPPER", "1"}}) : queries::program(gpu, "aabb_merge.frag");
}
gpgpu::Program& pairs_program(gpgpu::Gpu& gpu, bool samples) {
  return samples ? queries::program(gpu, "aabb_pairs_minmax.frag", {{"SAMPLE_UPPER", "1"}})
                 : queries::program(gpu, "aabb_pairs_minmax.frag");
}

/// A box hierarchy: level 0 = the leaves (one per atlas texel), the last level 1 x 1; with the
/// face samples of Upper::Samples, a sample per node (empty without).
struct Hierarchy {
  std::vector<gpgpu::Texture> lo, hi, sample;
};

Hierarchy build(gpgpu::Gpu& gpu, const PreparedModel& m, size_t atlas, const glm::dmat4& motion,
                const glm::dvec3& origin, const std::vector<char>* faces, bool samples) {
  const FaceAtlas& at = m.atlases[atlas];
  Hierarchy h;
  h.lo.emplace_back(at.plan.width, at.plan.height, gpgpu::Format::RGBA32F);
  h.hi.emplace_back(at.plan.width, at.plan.height, gpgpu::Format::RGBA32F);
  if (samples) h.sample.emplace_back(at.plan.width, at.plan.height, gpgpu::Format::RGBA32F);
  gpgpu::Program& leaf = leaf_program(gpu, samples);
  const glm::mat4 mf(motion);
  leaf.set_mat4("u_motion", &mf[0][0]);
  const glm::vec3 o(origin);
  leaf.set("u_origin", o.x, o.y, o.z);
  // Faces left out by a first stage (voxel_stage.h) get a negative growth: their leaves are empty.
  const gpgpu::Texture* grow = &m.grow[atlas];
  gpgpu::Texture filtered;
  if (faces) {
    std::vector<float> g = m.grow[atlas].read();  // (growth, budget) per slot
    for (size_t sl = 0; sl < at.plan.slots.size(); ++sl)
      if (!(*faces)[size_t(at.plan.slots[sl].face)]) g[2 * sl] = -1.0f;
    filtered = gpgpu::Texture(int(g.size() / 2), 1, gpgpu::Format::RG32F);
    filtered.upload(g);
    grow = &filtered;
  }
  const gpgpu::Input in[] = {{"u_points", &at.points},
                             {"u_slot_of", &at.slot_of},
                             {"u_mask", &at.mask},
                             {"u_grow", grow},
                             {"u_crossed", &m.crossed[atlas]}};
  std::vector<gpgpu::Texture*> out = {&h.lo.back(), &h.hi.back()};
  if (samples) out.push_back(&h.sample.back());
  gpu.run("aabb_leaf", leaf, in, out);
  gpgpu::Program& merge = merge_program(gpu, samples);
  while (h.lo.back().width() > 1 || h.lo.back().height() > 1) {
    const int w = (h.lo.back().width() + 1) / 2, hh = (h.lo.back().height() + 1) / 2;
    gpgpu::Texture lo(w, hh, gpgpu::Format::RGBA32F), hi(w, hh, gpgpu::Format::RGBA32F);
    gpgpu::Texture sample = samples ? gpgpu::Texture(w, hh, gpgpu::Format::RGBA32F) : gpgpu::Texture();
    std::vector<gpgpu::Input> min = {{"u_lo", &h.lo.back()}, {"u_hi", &h.hi.back()}};
    std::vector<gpgpu::Texture*> mout = {&lo, &hi};
    if (samples) min.push_back({"u_sample", &h.sample.back()}), mout.push_back(&sample);
    gpu.run("aabb_merge", merge, min, mout);
    h.lo.push_back(std::move(lo));
    h.hi.push_back(std::move(hi));
    if (samples) h.sample.push_back(std::move(sample));
  }
  return h;
}

/// One hierarchy per atlas of the model.
std::vector<Hierarchy> build_all(gpgpu::Gpu& gpu, const PreparedModel& m, const glm::dmat4& motion,
                                 const glm::dvec3& origin, const std::vector<char>* faces, bool samples) {
  std::vector<Hierarchy> out;
  for (size_t k = 0; k < m.atlases.size(); ++k) out.push_back(build(gpu, m, k, motion, origin, faces, samples));
  return out;
}

/// The two triangles of cell c of model m (cell_triangles.h), in double, mapped by `motion`.
CellTriangles cell_triangles(const PreparedModel& m, const FaceCell& c, const glm::dmat4& motion) {
  const nurbs::Surface& s = m.faces[size_t(c.face)].surface;
  const nurbs::ParamGrid& g = m.grids[size_t(c.face)].grid;
  const double u0 = g.u[size_t(c.i)], u1 = g.u[size_t(c.i) + 1], v0 = g.v[size_t(c.j)], v1 = g.v[size_t(c.j) + 1];
  glm::dvec3 corner[4];
  for (int k = 0; k < 4; ++k) {
    const glm::dvec2 uv = cell_corner_uv(k, u0, u1, v0, v1);
    corner[k] = glm::dvec3(motion * glm::dvec4(nurbs::surface_point(s, uv.x, uv.y), 1.0));
  }
  return queries::cell_triangles(corner, u0, u1, v0, v1);
}

/// The distinct cells of one side of the leaf pairs (sorted), with their triangles and K_e: the
/// faithful leaf pass looks them up instead of evaluating each cell's corners once per pair (the
/// bearing against its copy: 4.3 M leaf pairs over far fewer cells).
struct CellTable {
  std::vector<FaceCell> cells;
  std::vector<CellTriangles> tris;
  std::vector<double> k;
  [[nodiscard]] size_t index(const FaceCell& c) const {
    return size_t(std::lower_bound(cells.begin(), cells.end(), c, less) - cells.begin());
  }
  static bool less(const FaceCell& x, const FaceCell& y) {
    return std::tie(x.face, x.j, x.i) < std::tie(y.face, y.j, y.i);
  }
};
CellTable cell_table(const PreparedModel& m, std::vector<FaceCell> cells, const glm::dmat4& motion) {
  CellTable t;
  std::sort(cells.begin(), cells.end(), CellTable::less);
  cells.erase(std::unique(cells.begin(), cells.end(),
                          [](const FaceCell& x, const FaceCell& y) {
                            return !CellTable::less(x, y) && !CellTable::less(y, x);
                          }),
              cells.end());
  t.cells = std::move(cells);
  t.tris.resize(t.cells.size());
  t.k.resize(t.cells.size());
  nurbs::for_shares(t.cells.size(), nurbs::share_count(t.cells.size(), 1024), [&](size_t, size_t begin, size_t end) {
    for (size_t n = begin; n < end; ++n) {
      const FaceCell& c = t.cells[n];
      t.tris[n] = cell_triangles(m, c, motion);
      t.k[n] =
          nurbs::grid_cell_k(m.bounds[size_t(c.face)], m.grids[size_t(c.face)].grid, c.i, c.j, nurbs::KNorm::Euclidean);
    }
  });
  return t;
}

}  // namespace

struct ClearanceCache::Impl {
  const PreparedModel* a = nullptr;
  bool samples = false;       ///< built with face samples (Upper::Samples)
  std::vector<Hierarchy> ha;  ///< one per atlas
};

ClearanceCache::ClearanceCache() : impl(std::make_unique<Impl>()) {}
ClearanceCache::~ClearanceCache() = default;

namespace {

/// The level-by-level descent of one atlas pair (hierarchies ha of A, hb of B): returns the
/// surviving leaf records (xa, ya, xb, yb), 4 floats each; adds the pairs per level to `per_level`;
/// `upper` carries the least upper bound U across atlas pairs (any pair's U bounds the distance).
std::vector<float> descend(gpgpu::Gpu& gpu, const Hierarchy& ha, const Hierarchy& hb, const ClearanceLimits& limits,
                           long long host_pairs, double& shared_upper, std::vector<long long>& per_level) {
  // The surviving pairs: records (xa, ya, xb, yb) at the current levels. The search starts at the
  // finest levels whose node pairs number at most limits.start_pairs (the roots when 1).
  const long long start_pairs = std::max(1LL, limits.start_pairs);
  int la = int(ha.lo.size()) - 1, lb = int(hb.lo.size()) - 1;
  auto nodes = [](const Hierarchy& h, int l) {
    return static_cast<long long>(h.lo[size_t(l)].width()) * h.lo[size_t(l)].height();
  };
  while (la > 0 || lb > 0) {
    const bool down_a = la > 0 && (la >= lb || lb == 0);
    const int na = down_a ? la - 1 : la, nb = down_a ? lb : lb - 1;
    if (nodes(ha, na) * nodes(hb, nb) > start_pairs) break;
    la = na, lb = nb;
  }
  std::vector<float> start;
  const gpgpu::Texture &ta = ha.lo[size_t(la)], &tb = hb.lo[size_t(lb)];
  for (int ya = 0; ya < ta.height(); ++ya)
    for (int xa = 0; xa < ta.width(); ++xa)
      for (int yb = 0; yb < tb.height(); ++yb)
        for (int xb = 0; xb < tb.width(); ++xb) start.insert(start.end(), {float(xa), float(ya), float(xb), float(yb)});
  long long count = static_cast<long long>(start.size() / 4);
  const gpgpu::Layout2D start_layout = gpgpu::layout_pow2(count, 4096);
  start.resize(size_t(start_layout.width) * size_t(start_layout.height) * 4, 0.0f);
  gpgpu::Texture pairs(start_layout.width, start_layout.height, gpgpu::Format::RGBA32F);
  pairs.upload(start);
  const bool samples = !ha.sample.empty() && !hb.sample.empty();
  gpgpu::Program& prog = pairs_program(gpu, samples);
  const int max_size = gpu.info().max_texture_size;
  size_t level = 0;
  auto record = [&](long long kept) {
    if (per_level.size() <= level) per_level.resize(level + 1, 0);
    per_level[level++] += kept;
  };
  // A level whose child pairs do not fit one target runs in chunks of pairs: every chunk's least
  // upper bound first, then each chunk pruned by the least of them and compacted, the kept records
  // joined on the CPU (a rare case: fine tolerances on models of hundreds of faces, or two models
  // close over a large area, such as the 213-face bearing against its copy: 17.6 M pairs survive its
  // level 5). More survivors than one chunk stay on the host for the next level (`host`).
  const int side = std::min(max_size, 4096);
  const long long chunk_pairs = std::min(limits.chunk_pairs, static_cast<long long>(side) * side / 16);
  // Survivors of a level too many for one texture stay on the host; the next level uploads them a
  // chunk at a time (`pairs` then holds that chunk alone, at offset 0).
  std::vector<float> host;
  bool on_host = false;
  auto load_chunk = [&](long long offset) {  // -> (offset within `pairs`, pairs there)
    if (!on_host) return std::pair<long long, long long>(offset, count);
    const long long n = std::min(chunk_pairs, count - offset);
    const gpgpu::Layout2D l = gpgpu::layout_pow2(n, side);
    std::vector<float> slice(host.begin() + ptrdiff_t(4 * offset), host.begin() + ptrdiff_t(4 * (offset + n)));
    slice.resize(size_t(l.width) * size_t(l.height) * 4, 0.0f);
    pairs = gpgpu::Texture(l.width, l.height, gpgpu::Format::RGBA32F);
    pairs.upload(slice);
    return std::pair<long long, long long>(0, n);
  };
  auto run_pairs = [&](long long chunk, const gpgpu::Layout2D& out, gpgpu::Texture* minmax, gpgpu::Texture* records) {
    const auto [offset, in_pairs] = load_chunk(chunk);
    prog.set("u_pair_count", int(in_pairs));
    prog.set("u_pair_offset", int(offset));
    prog.set("u_out_width", out.width);
    std::vector<gpgpu::Input> in = {{"u_pairs", &pairs},
                                    {"u_lo_a", &ha.lo[size_t(la)]},
                                    {"u_hi_a", &ha.hi[size_t(la)]},
                                    {"u_lo_b", &hb.lo[size_t(lb)]},
                                    {"u_hi_b", &hb.hi[size_t(lb)]}};
    if (samples) in.insert(in.end(), {{"u_sample_a", &ha.sample[size_t(la)]}, {"u_sample_b", &hb.sample[size_t(lb)]}});
    gpgpu::Texture* targets[] = {minmax, records};
    gpu.run("aabb_pairs_minmax", prog, in, targets);
  };
  auto pair_pass = [&](long long chunk, const gpgpu::Layout2D& out, gpgpu::Texture* minmax, gpgpu::Texture* records) {
    run_pairs(chunk, out, minmax, records);
    const double u = gpgpu::reduce_min(gpu, *minmax, 1, limits.reduce_block);
    shared_upper = std::min(shared_upper, u);
    return std::min(u, shared_upper);
  };
  // Lower bound within U (a relative 1e-5 above it covers the float rounding of both).
  auto cut_of = [](double upper) { return std::isfinite(upper) ? float(upper * (1 + 1e-5)) : -1.0f; };
  auto prune = [&](double upper, gpgpu::Texture* minmax, gpgpu::Texture* records) {
    // Tested by the stream reduction itself (compact_at_most: no predicate pass).
    return gpgpu::compact_at_most(gpu, *minmax, cut_of(upper), *records, limits.compact_fanout);
  };
  // ClearanceLimits::host_pairs: U and the survivors of a small level from one read-back, with the
  // GPU passes' arithmetic (a float minimum of G ignoring NaN, then R <= the same float cut).
  auto host_prune = [&](const gpgpu::Layout2D& out, gpgpu::Texture* minmax, gpgpu::Texture* records) {
    run_pairs(0, out, minmax, records);
    gpu.profiler().begin("aabb_pairs_host_prune");
    const long long n = count * 16;
    const gpgpu::Region rows{0, 0, out.width, int((n + out.width - 1) / out.width)};
    const std::vector<float> mm = minmax->read(rows), rec = records->read(rows);
    // reduce_min's CPU twin (a minimum of floats, NaN ignored: the same value).
    const double u =
        gpgpu::reduce_cpu(std::span<const float>(mm).first(size_t(2 * n)), 2,
                          {gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min})[1];
    shared_upper = std::min(shared_upper, u);
    const float cut = cut_of(std::min(u, shared_upper));
    std::vector<float> kept;
    for (long long k = 0; k < n; ++k)
      if (mm[size_t(2 * k)] <= cut)
        kept.insert(kept.end(), rec.begin() + ptrdiff_t(4 * k), rec.begin() + ptrdiff_t(4 * k + 4));
    count = static_cast<long long>(kept.size() / 4);
    if (count > 0) {
      const gpgpu::Layout2D l = gpgpu::layout_pow2(count, side);
      kept.resize(size_t(l.width) * size_t(l.height) * 4, 0.0f);
      pairs = gpgpu::Texture(l.width, l.height, gpgpu::Format::RGBA32F);
      pairs.upload(kept);
    }
    gpu.profiler().end();
  };
  while ((la > 0 || lb > 0) && count > 0) {
    const int da = la > 0 ? 1 : 0, db = lb > 0 ? 1 : 0;
    la -= da;
    lb -= db;
    prog.set("u_descend", da, db);
    if (count <= chunk_pairs && !on_host) {
      const gpgpu::Layout2D out = gpgpu::layout_pow2(count * 16, side);
      gpgpu::PooledTexture minmax = gpu.acquire(out.width, out.height, gpgpu::Format::RG32F);
      gpgpu::PooledTexture records = gpu.acquire(out.width, out.height, gpgpu::Format::RGBA32F);
      if (count * 16 <= host_pairs) {
        host_prune(out, minmax.get(), records.get());
      } else {
        const double upper = pair_pass(0, out, minmax.get(), records.get());
        gpgpu::Compacted c = prune(upper, minmax.get(), records.get());
        count = c.count;
        pairs = std::move(c.records);
      }
    } else {
      const gpgpu::Layout2D out = gpgpu::layout_pow2(chunk_pairs * 16, side);  // one chunk's children
      gpgpu::PooledTexture minmax = gpu.acquire(out.width, out.height, gpgpu::Format::RG32F);
      gpgpu::PooledTexture records = gpu.acquire(out.width, out.height, gpgpu::Format::RGBA32F);
      double upper = kInf;
      for (long long off = 0; off < count; off += chunk_pairs)
        upper = std::min(upper, double(pair_pass(off, out, minmax.get(), records.get())));
      std::vector<float> kept;
      for (long long off = 0; off < count; off += chunk_pairs) {
        pair_pass(off, out, minmax.get(), records.get());
        const gpgpu::Compacted c = prune(upper, minmax.get(), records.get());
        const std::vector<float> part = c.count > 0 ? c.read_records() : std::vector<float>{};
        kept.insert(kept.end(), part.begin(), part.end());
      }
      count = static_cast<long long>(kept.size() / 4);
      on_host = count > chunk_pairs;
      if (on_host) {
        host = std::move(kept);
      } else if (host = {}; count > 0) {
        const gpgpu::Layout2D l = gpgpu::layout_pow2(count, side);
        kept.resize(size_t(l.width) * size_t(l.height) * 4, 0.0f);
        pairs = gpgpu::Texture(l.width, l.height, gpgpu::Format::RGBA32F);
        pairs.upload(kept);
      }
    }
    record(count);
  }
  std::vector<float> recs = on_host ? std::move(host) : count > 0 ? pairs.read() : std::vector<float>{};
  recs.resize(size_t(4 * count));
  return recs;
}

}  // namespace

void compile_clearance_programs(gpgpu::Gpu& gpu, const ClearanceLimits& limits, Search search, bool trimmed,
                                const std::function<bool()>& geometry_done) {
  // llvmpipe makes a program's machine code at its first draw, per set of bound texture formats
  // (and whether their sizes are powers of 2): 7-8 ms for the evaluation program, which would
  // otherwise stall the atlas right after the geometry threads. One texel on inputs shaped as an
  // atlas's (a slot table of another size than a power of 2, the coefficient arrays of one) makes
  // it here, beside those threads.
  using F = gpgpu::Format;
  gpgpu::Texture slot_of(3, 3, F::R32F), slots(1, 1, F::RGBA32F), basis(1, 1, F::RGBA32F), ctrl(1, 1, F::RGBA32F);
  gpgpu::Texture points(1, 1, F::RGBA32F);
  const gpgpu::Input in[] = {{"u_slot_of", &slot_of}, {"u_slots", &slots}, {"u_basis", &basis}, {"u_ctrl", &ctrl}};
  gpgpu::Texture* out[] = {&points};
  gpu.run("surface_eval_atlas_first_draw", atlas_program(gpu), in, out);
  if (trimmed) gpgpu::compile_polygon_fill(gpu);  // trim masks
  const bool samples = upper_from_samples(limits, search == Search::CoarseToFine);
  leaf_program(gpu, samples);
  merge_program(gpu, samples);
  pairs_program(gpu, samples);
  const bool may_wait = search == Search::CoarseToFine && limits.host_pairs != 0 && geometry_done;
  if (may_wait && geometry_done()) return;
  gpgpu::reduce_program(gpu, limits.reduce_block);
  if (may_wait && geometry_done()) return;
  gpgpu::compile_compact(gpu, limits.compact_fanout, true);
}

namespace {

/// r with the answer of a refinement.
Clearance with_refined(Clearance r, const Refined& f) {
  r.found = f.found;
  r.distance = f.distance;
  r.bound = f.bound;
  r.point_a = f.point_a, r.point_b = f.point_b;
  r.uv_a = f.uv_a, r.uv_b = f.uv_b;
  r.face_a = f.face_a, r.face_b = f.face_b;
  r.on_trim_edge = f.on_trim_edge;
  r.meets_tolerance = f.meets_tolerance;
  r.rounds = f.rounds;
  r.refined_cells = f.cells;
  r.most_pairs = f.most_pairs;
  return r;
}

/// Clearance::intersecting: a common point sought from the closest pair when the distance is
/// within its bound of zero (Newton on both faces, intersection.h): two surface points within a
/// thousandth of the query's tolerance (above the coordinates' double rounding).
Clearance with_intersection(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b, Clearance r) {
  if (!r.found || r.face_a < 0 || r.face_b < 0 || r.distance > r.bound) return r;
  const auto fa = size_t(r.face_a), fb = size_t(r.face_b);
  const double tol = 1e-3 * (a.tolerance + b.tolerance) + 1e-14 * (glm::length(r.point_a) + glm::length(r.point_b));
  if (const auto x =
          find_intersection(a.faces[fa], a.trims[fa], r.uv_a, b.faces[fb], b.trims[fb], r.uv_b, motion_b, tol)) {
    r.intersecting = true;
    r.intersection = x->point;
    r.intersection_residual = x->residual;
  }
  return r;
}

}  // namespace

HierarchyLevels clearance_hierarchy(gpgpu::Gpu& gpu, const PreparedModel& m, size_t atlas, const glm::dmat4& motion,
                                    const glm::dvec3& origin) {
  const Hierarchy h = build(gpu, m, atlas, motion, origin, nullptr, false);
  HierarchyLevels out;
  for (size_t l = 0; l < h.lo.size(); ++l) {
    out.size.emplace_back(h.lo[l].width(), h.lo[l].height());
    out.lo.push_back(h.lo[l].read());
    out.hi.push_back(h.hi[l].read());
  }
  return out;
}

std::vector<glm::vec2> clearance_pair_bounds(gpgpu::Gpu& gpu, const PreparedModel& a, const PreparedModel& b,
                                             const glm::dmat4& motion_b, int la, int lb,
                                             const std::vector<glm::ivec4>& pairs) {
  const Hierarchy ha = build(gpu, a, 0, glm::dmat4(1.0), a.centre, nullptr, false);
  const Hierarchy hb = build(gpu, b, 0, motion_b, a.centre, nullptr, false);
  std::vector<float> records;
  for (const glm::ivec4& p : pairs) records.insert(records.end(), {float(p.x), float(p.y), float(p.z), float(p.w)});
  const gpgpu::Layout2D in_layout = gpgpu::layout_pow2(std::max<int64_t>(1, int64_t(pairs.size())), 4096);
  records.resize(size_t(in_layout.width) * size_t(in_layout.height) * 4, 0.0f);
  gpgpu::Texture in_pairs(in_layout.width, in_layout.height, gpgpu::Format::RGBA32F);
  in_pairs.upload(records);
  const gpgpu::Layout2D out = gpgpu::layout_pow2(std::max<int64_t>(1, 16 * int64_t(pairs.size())), 4096);
  gpgpu::Texture minmax(out.width, out.height, gpgpu::Format::RGBA32F),
      recs(out.width, out.height, gpgpu::Format::RGBA32F);
  gpgpu::Program& prog = pairs_program(gpu, false);
  prog.set("u_pair_count", int(pairs.size()));
  prog.set("u_pair_offset", 0);
  prog.set("u_out_width", out.width);
  prog.set("u_descend", 0, 0);
  const gpgpu::Input in[] = {{"u_pairs", &in_pairs},
                             {"u_lo_a", &ha.lo[size_t(la)]},
                             {"u_hi_a", &ha.hi[size_t(la)]},
                             {"u_lo_b", &hb.lo[size_t(lb)]},
                             {"u_hi_b", &hb.hi[size_t(lb)]}};
  gpgpu::Texture* targets[] = {&minmax, &recs};
  gpu.run("aabb_pairs_minmax", prog, in, targets);
  const std::vector<float> v = minmax.read();
  std::vector<glm::vec2> result;
  for (size_t k = 0; k < pairs.size(); ++k) result.emplace_back(v[4 * 16 * k], v[4 * 16 * k + 1]);
  return result;
}

std::optional<Clearance> clearance_cpu(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                                       double upper, long long max_start_pairs) {
  if (a.search != Search::CoarseToFine || b.search != Search::CoarseToFine)
    throw std::invalid_argument("clearance_cpu: the models must be prepared with Search::CoarseToFine");
  const auto t0 = std::chrono::steady_clock::now();
  const std::optional<Refined> f = refine_all_pairs(a, b, motion_b, a.tolerance + b.tolerance, upper, max_start_pairs);
  if (!f) return std::nullopt;
  Clearance r;
  r.refine_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.start_pairs = f->start_pairs;
  return with_intersection(a, b, motion_b, with_refined(std::move(r), *f));
}

Clearance clearance(gpgpu::Gpu& gpu, const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                    const std::vector<char>* faces_a, const std::vector<char>* faces_b, const ClearanceLimits& limits,
                    ClearanceCache* cache) {
  const glm::dvec3 origin = a.centre;
  std::vector<Hierarchy> own_a;
  const bool cached = cache && !faces_a;
  const bool coarse_to_fine = a.search == Search::CoarseToFine || b.search == Search::CoarseToFine;
  const bool samples = upper_from_samples(limits, coarse_to_fine);
  const long long host_pairs = host_pairs_used(limits, coarse_to_fine);
  if (cached && (cache->impl->a != &a || cache->impl->samples != samples)) {
    cache->impl->ha = build_all(gpu, a, glm::dmat4(1.0), origin, nullptr, samples);
    cache->impl->a = &a;
    cache->impl->samples = samples;
  }
  if (!cached) own_a = build_all(gpu, a, glm::dmat4(1.0), origin, faces_a, samples);
  const std::vector<Hierarchy>& ha = cached ? cache->impl->ha : own_a;
  const std::vector<Hierarchy> hb = build_all(gpu, b, motion_b, origin, faces_b, samples);
  Clearance r;
  // Every atlas of A against every atlas of B, the least upper bound shared (§5.1-5.2 per pair).
  std::vector<std::pair<FaceCell, FaceCell>> leaves;
  double upper = kInf;
  for (size_t ia = 0; ia < ha.size(); ++ia)
    for (size_t ib = 0; ib < hb.size(); ++ib) {
      const std::vector<float> recs = descend(gpu, ha[ia], hb[ib], limits, host_pairs, upper, r.pairs_per_level);
      for (size_t k = 0; k + 3 < recs.size(); k += 4) {
        const auto ca = a.cell_at(ia, int(recs[k]), int(recs[k + 1]));
        const auto cb = b.cell_at(ib, int(recs[k + 2]), int(recs[k + 3]));
        if (ca && cb) leaves.emplace_back(*ca, *cb);
      }
    }
  // Leaf pairs: two triangles per cell on each side, in double.
  r.leaf_pairs = static_cast<long long>(leaves.size());
  if (a.search == Search::CoarseToFine || b.search == Search::CoarseToFine) {
    // Candidates refined in double until the answer is proven within T (refine.h).
    const auto t0 = std::chrono::steady_clock::now();
    const Refined f = refine_pairs(a, b, motion_b, leaves, a.tolerance + b.tolerance);
    r.refine_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return with_intersection(a, b, motion_b, with_refined(std::move(r), f));
  }
  // The leaf pairs in contiguous shares over the hardware threads, merged in share order with a
  // strict "<" (the sequential loop's answer: the first pair of least distance).
  // §5.3: a closest point inside a trimmed region is discarded and the search goes on: such
  // triangle pairs wait, and those still below the best material pair are searched over their
  // material parts (material_distance.h).
  struct Waiting {
    size_t leaf;
    int i, j;
    double distance;
  };
  struct Best {
    bool found = false;
    double distance = kInf, ka = 0.0, kb = 0.0;
    glm::dvec3 pa{0.0}, pb{0.0};
    glm::dvec2 uva{0.0}, uvb{0.0};
    int face_a = -1, face_b = -1;
    std::vector<Waiting> waiting;
  };
  std::vector<FaceCell> cells_a, cells_b;
  cells_a.reserve(leaves.size()), cells_b.reserve(leaves.size());
  for (const auto& [ca, cb] : leaves) cells_a.push_back(ca), cells_b.push_back(cb);
  const CellTable table_a = cell_table(a, std::move(cells_a), glm::dmat4(1.0));
  const CellTable table_b = cell_table(b, std::move(cells_b), motion_b);
  // Band indexes of the trimmed faces that take part (is_material's answer, in fewer steps).
  auto banded = [&](const PreparedModel& m, const CellTable& t) {
    std::vector<std::optional<BandedTrim>> out(m.faces.size());
    for (const FaceCell& c : t.cells)
      if (!m.faces[size_t(c.face)].loops.empty() && !out[size_t(c.face)])
        out[size_t(c.face)].emplace(m.trims[size_t(c.face)]);
    return out;
  };
  const std::vector<std::optional<BandedTrim>> banded_a = banded(a, table_a), banded_b = banded(b, table_b);
  std::vector<Best> shares(nurbs::share_count(leaves.size(), 4096));
  nurbs::for_shares(leaves.size(), shares.size(), [&](size_t share, size_t begin, size_t end) {
    Best& s = shares[share];
    for (size_t k = begin; k < end; ++k) {
      const auto& [ca, cb] = leaves[k];
      const size_t ia = table_a.index(ca), ib = table_b.index(cb);
      s.ka = std::max(s.ka, table_a.k[ia]);
      s.kb = std::max(s.kb, table_b.k[ib]);
      const CellTriangles &ta = table_a.tris[ia], &tb = table_b.tris[ib];
      const nurbs::TrimmedSurface &fa = a.faces[size_t(ca.face)], &fb = b.faces[size_t(cb.face)];
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          glm::dvec3 pa, pb, wa, wb;
          const double d = triangle_distance(ta.p[i], tb.p[j], pa, pb, wa, wb);
          if (d >= s.distance) continue;
          const glm::dvec2 uva = wa.x * ta.uv[i][0] + wa.y * ta.uv[i][1] + wa.z * ta.uv[i][2];
          const glm::dvec2 uvb = wb.x * tb.uv[j][0] + wb.y * tb.uv[j][1] + wb.z * tb.uv[j][2];
          if ((!fa.loops.empty() && !banded_a[size_t(ca.face)]->is_material(uva)) ||
              (!fb.loops.empty() && !banded_b[size_t(cb.face)]->is_material(uvb))) {
            s.waiting.push_back({k, i, j, d});
            continue;
          }
          s.found = true;
          s.distance = d;
          s.pa = pa, s.pb = pb, s.uva = uva, s.uvb = uvb;
          s.face_a = ca.face, s.face_b = cb.face;
        }
    }
  });
  double ka = 0.0, kb = 0.0;
  r.distance = kInf;
  std::vector<Waiting> waiting;
  for (const Best& s : shares) {
    ka = std::max(ka, s.ka), kb = std::max(kb, s.kb);
    waiting.insert(waiting.end(), s.waiting.begin(), s.waiting.end());
    if (!s.found || !(s.distance < r.distance)) continue;
    r.found = true;
    r.distance = s.distance;
    r.point_a = s.pa, r.point_b = s.pb, r.uv_a = s.uva, r.uv_b = s.uvb;
    r.face_a = s.face_a, r.face_b = s.face_b;
  }
  // The waiting pairs nearest first, while they can still beat the best material pair; trim edges
  // indexed for a face when one of its cells first needs them.
  std::sort(waiting.begin(), waiting.end(), [](const Waiting& x, const Waiting& y) {
    return std::tie(x.distance, x.leaf, x.i, x.j) < std::tie(y.distance, y.leaf, y.i, y.j);
  });
  FaceTrimEdges edges_a(a), edges_b(b);
  // A cell's trim pieces once (table index -> pieces; a cell meets many partners).
  std::map<size_t, std::vector<TrimPiece>> pieces_a, pieces_b;
  auto pieces = [](std::map<size_t, std::vector<TrimPiece>>& cache, const TrimEdges* e, const CellTable& t, size_t k) {
    auto it = cache.find(k);
    if (it != cache.end()) return &it->second;
    std::vector<TrimPiece>& out = cache[k];
    if (e) e->pieces(t.cells[k].i, t.cells[k].j, t.tris[k].corners().data(), out);
    return &out;
  };
  for (const Waiting& w : waiting) {
    if (!(w.distance < r.distance)) break;
    const auto& [ca, cb] = leaves[w.leaf];
    const size_t ia = table_a.index(ca), ib = table_b.index(cb);
    const CellTriangles &ta = table_a.tris[ia], &tb = table_b.tris[ib];
    const TrimEdges *ea = edges_a(ca.face), *eb = edges_b(cb.face);
    const MaterialPair m =
        material_pair_distance({ta.p[w.i], ta.uv[w.i], w.i, ea, pieces(pieces_a, ea, table_a, ia)},
                               {tb.p[w.j], tb.uv[w.j], w.j, eb, pieces(pieces_b, eb, table_b, ib)}, r.distance);
    if (!m.found) continue;
    r.found = r.on_trim_edge = true;
    r.distance = m.distance;
    r.point_a = m.point_a, r.point_b = m.point_b, r.uv_a = m.uv_a, r.uv_b = m.uv_b;
    r.face_a = ca.face, r.face_b = cb.face;
  }
  // Theorem 1 over the material parts: every candidate pair's triangles within K of their surfaces.
  r.bound = ka + kb;
  return with_intersection(a, b, motion_b, std::move(r));
}

}  // namespace queries
