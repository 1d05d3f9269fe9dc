#include "queries/distance/voxel_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

#include "gpgpu/compact.h"
#include "gpgpu/layout.h"
#include "gpgpu/reduce.h"
#include "nurbs/model_ops.h"
#include "nurbs/stopwatch.h"
#include "nurbs/surface_eval.h"
#include "queries/shaders.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One face's inputs to the voxelization.
struct FaceInput {
  const nurbs::TrimmedSurface* face;
  const nurbs::FilipBound* bound;
  const nurbs::TrimPolygons* trim;
};

/// A grown cell box of one face.
struct CellBox {
  glm::dvec3 lo, hi;
  int face;
};

/// Samples of a grid in double, row-major (u fastest), and whether each is material.
struct Samples {
  std::vector<glm::dvec3> p;
  std::vector<char> material;
};
Samples evaluate(const FaceInput& f, const nurbs::ParamGrid& g) {
  Samples r;
  const bool trimmed = !f.face->loops.empty();
  for (double v : g.v)
    for (double u : g.u) {
      r.p.push_back(nurbs::surface_point(f.face->surface, u, v));
      r.material.push_back(!trimmed || nurbs::is_material(*f.trim, {u, v}));
    }
  return r;
}

/// Splits the steps of `g` so that no cell edge along a grid line is longer than `chord`: the
/// certified grid bounds flatness, not size, and the box of a large tilted cell would cover a slab
/// of voxels. Only tightness depends on this; K_e is computed per cell of the finer grid.
nurbs::ParamGrid split_long_cells(const nurbs::ParamGrid& g, const Samples& s, double chord) {
  const size_t nu = g.u.size(), nv = g.v.size();
  const auto split = [&](const std::vector<double>& t, size_t count, auto edge) {
    std::vector<double> out;
    for (size_t i = 0; i + 1 < t.size(); ++i) {
      double longest = 0.0;
      for (size_t j = 0; j < count; ++j) longest = std::max(longest, edge(i, j));
      const int k = std::clamp(int(std::ceil(longest / chord)), 1, 64);
      for (int q = 0; q < k; ++q) out.push_back(t[i] + (t[i + 1] - t[i]) * q / k);
    }
    out.push_back(t.back());
    return out;
  };
  nurbs::ParamGrid r;
  r.u = split(g.u, nv, [&](size_t i, size_t j) { return glm::length(s.p[j * nu + i + 1] - s.p[j * nu + i]); });
  r.v = split(g.v, nu, [&](size_t j, size_t i) { return glm::length(s.p[(j + 1) * nu + i] - s.p[j * nu + i]); });
  return r;
}

/// Per cell of `g` (row-major, u fastest): 1 where an edge of a trim loop may pass through it. An
/// edge marks every cell its parameter box overlaps, the box grown by twice the flattening
/// tolerance of PreparedModel::trims (1e-6 of the u width) so the true curve is covered too.
std::vector<char> crossed_cells(const nurbs::TrimPolygons& t, const nurbs::ParamGrid& g) {
  std::vector<char> out(size_t(g.cells_u()) * size_t(g.cells_v()), 0);
  const double eps = 2e-6 * std::max(g.u.back() - g.u.front(), g.v.back() - g.v.front());
  const auto range = [](const std::vector<double>& lines, double lo, double hi) {
    const int last = int(lines.size()) - 2;  // the last cell
    const int i0 = int(std::upper_bound(lines.begin(), lines.end(), lo) - lines.begin()) - 1;
    const int i1 = int(std::upper_bound(lines.begin(), lines.end(), hi) - lines.begin()) - 1;
    return std::pair{std::clamp(i0, 0, last), std::clamp(i1, 0, last)};
  };
  for (const auto& loop : t.loops)
    for (size_t k = 0; k < loop.size(); ++k) {
      const glm::dvec2 p = loop[k], q = loop[(k + 1) % loop.size()];
      const auto [i0, i1] = range(g.u, std::min(p.x, q.x) - eps, std::max(p.x, q.x) + eps);
      const auto [j0, j1] = range(g.v, std::min(p.y, q.y) - eps, std::max(p.y, q.y) + eps);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) out[size_t(j) * size_t(g.cells_u()) + size_t(i)] = 1;
    }
  return out;
}

VoxelGrid build(const std::vector<FaceInput>& in, const VoxelizeOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  VoxelGrid g;
  g.n = o.n;
  g.face_count = int(in.size());
  glm::dvec3 clo(kInf), chi(-kInf);  // control boxes: they hold the surfaces
  for (const FaceInput& f : in) {
    const nurbs::Box b = nurbs::control_box(f.face->surface);
    clo = glm::min(clo, b.min);
    chi = glm::max(chi, b.max);
  }
  if (in.empty()) clo = chi = glm::dvec3(0.0);
  const double voxel = std::max({chi.x - clo.x, chi.y - clo.y, chi.z - clo.z, 1e-300}) / o.n;
  std::vector<CellBox> cells;
  std::vector<glm::dvec3> material;  // exact surface points on material: the witnesses
  glm::dvec3 ulo(kInf), uhi(-kInf);
  for (int f = 0; f < int(in.size()); ++f) {
    const FaceInput& face = in[size_t(f)];
    const nurbs::ParamGrid coarse = nurbs::certified_grid(*face.bound, o.cell_fraction * voxel, {1LL << 20}).grid;
    const nurbs::ParamGrid grid = split_long_cells(coarse, evaluate(face, coarse), 0.5 * voxel);
    const Samples s = evaluate(face, grid);
    const size_t nu = grid.u.size();
    const std::vector<char> crossed = o.skip_trimmed_cells && !face.face->loops.empty()
                                          ? crossed_cells(*face.trim, grid)
                                          : std::vector<char>(size_t(grid.cells_u()) * size_t(grid.cells_v()), 1);
    for (size_t k = 0; k < s.p.size(); ++k)
      if (s.material[k]) material.push_back(s.p[k]);
    for (int j = 0; j < grid.cells_v(); ++j)
      for (int i = 0; i < grid.cells_u(); ++i) {
        ++g.cells;
        const size_t c[4] = {size_t(j) * nu + size_t(i), size_t(j) * nu + size_t(i) + 1, size_t(j + 1) * nu + size_t(i),
                             size_t(j + 1) * nu + size_t(i) + 1};
        // No material corner and no trim edge through it: the whole cell is trimmed away.
        if (!crossed[size_t(j) * size_t(grid.cells_u()) + size_t(i)] &&
            !(s.material[c[0]] || s.material[c[1]] || s.material[c[2]] || s.material[c[3]])) {
          ++g.skipped_cells;
          continue;
        }
        const double k = nurbs::grid_cell_k(*face.bound, grid, i, j, nurbs::KNorm::Euclidean);
        CellBox b{glm::min(glm::min(s.p[c[0]], s.p[c[1]]), glm::min(s.p[c[2]], s.p[c[3]])) - glm::dvec3(k),
                  glm::max(glm::max(s.p[c[0]], s.p[c[1]]), glm::max(s.p[c[2]], s.p[c[3]])) + glm::dvec3(k), f};
        if (!std::isfinite(k)) b = {clo, chi, f};  // no bound: the face may be anywhere in its hull
        ulo = glm::min(ulo, b.lo);
        uhi = glm::max(uhi, b.hi);
        cells.push_back(b);
      }
  }
  // The grid box: the grown cells clipped to the control boxes, no side under 1/n of the largest.
  glm::dvec3 lo = cells.empty() ? clo : glm::max(ulo, clo), hi = cells.empty() ? chi : glm::min(uhi, chi);
  const double big = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
  for (int a = 0; a < 3; ++a)
    if (hi[a] - lo[a] < big / o.n) {
      const double mid = 0.5 * (lo[a] + hi[a]);
      lo[a] = mid - 0.5 * big / o.n;
      hi[a] = mid + 0.5 * big / o.n;
    }
  g.lo = lo;
  g.h = (hi - lo) / double(o.n);
  const auto index = [&](const glm::dvec3& x) {
    glm::ivec3 r;
    for (int a = 0; a < 3; ++a) r[a] = int(std::clamp(std::floor((x[a] - lo[a]) / g.h[a]), 0.0, o.n - 1.0));
    return r;
  };
  // Face references: (voxel, face) keys, sorted and unique, become the CSR lists.
  std::vector<long long> refs;
  for (const CellBox& b : cells) {
    const glm::ivec3 i0 = index(b.lo), i1 = index(b.hi);
    for (int z = i0.z; z <= i1.z; ++z)
      for (int y = i0.y; y <= i1.y; ++y)
        for (int x = i0.x; x <= i1.x; ++x) refs.push_back((x + o.n * (y + o.n * (long long)z)) * g.face_count + b.face);
  }
  std::sort(refs.begin(), refs.end());
  refs.erase(std::unique(refs.begin(), refs.end()), refs.end());
  for (long long r : refs) {
    const int v = int(r / g.face_count);
    if (g.voxels.empty() || g.voxels.back() != v) {
      g.voxels.push_back(v);
      g.face_begin.push_back(int(g.faces.size()));
    }
    g.faces.push_back(int(r % g.face_count));
  }
  g.face_begin.push_back(int(g.faces.size()));
  g.witness.assign(g.voxels.size(), 0);
  for (const glm::dvec3& x : material) {
    const glm::ivec3 i = index(x);
    const auto it = std::lower_bound(g.voxels.begin(), g.voxels.end(), i.x + o.n * (i.y + o.n * i.z));
    if (it != g.voxels.end() && *it == i.x + o.n * (i.y + o.n * i.z)) g.witness[size_t(it - g.voxels.begin())] = 1;
  }
  g.seconds = nurbs::seconds_since(t0);
  return g;
}

/// Voxel boxes, B's refitted under `motion` (box of the 8 moved corners).
std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes(const VoxelGrid& g, const glm::dmat4& motion) {
  std::vector<std::pair<glm::dvec3, glm::dvec3>> out;
  out.reserve(g.voxels.size());
  for (int v : g.voxels) {
    const auto [lo, hi] = g.box(v);
    glm::dvec3 mlo(kInf), mhi(-kInf);
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      const glm::dvec3 m(motion * glm::dvec4(corner, 1.0));
      mlo = glm::min(mlo, m);
      mhi = glm::max(mhi, m);
    }
    out.emplace_back(mlo, mhi);
  }
  return out;
}

/// Marks the face pairs of kept voxel pair (ia, ib) (positions in voxels) in a Fa x Fb table.
void mark_faces(const VoxelGrid& a, const VoxelGrid& b, size_t ia, size_t ib, std::vector<char>& mark) {
  for (int s = a.face_begin[ia]; s < a.face_begin[ia + 1]; ++s)
    for (int t = b.face_begin[ib]; t < b.face_begin[ib + 1]; ++t)
      mark[size_t(a.faces[size_t(s)]) * size_t(b.face_count) + size_t(b.faces[size_t(t)])] = 1;
}

VoxelStage start(const VoxelGrid& a, const VoxelGrid& b) {
  VoxelStage r;
  r.voxels_a = (long long)a.voxels.size();
  r.voxels_b = (long long)b.voxels.size();
  r.voxel_pairs = r.voxels_a * r.voxels_b;
  return r;
}

void finish(const VoxelGrid& a, const VoxelGrid& b, const std::vector<char>& mark, VoxelStage& r) {
  r.faces_a.assign(size_t(a.face_count), 0);
  r.faces_b.assign(size_t(b.face_count), 0);
  for (int fa = 0; fa < a.face_count; ++fa)
    for (int fb = 0; fb < b.face_count; ++fb)
      if (mark[size_t(fa) * size_t(b.face_count) + size_t(fb)]) {
        r.face_pairs.emplace_back(fa, fb);
        r.faces_a[size_t(fa)] = r.faces_b[size_t(fb)] = 1;
      }
}

/// A float box that holds the double one: lo rounded down, hi up.
glm::vec4 round_out(const glm::dvec3& x, double dir, float w) {
  glm::vec4 f(glm::vec3(x), w);
  for (int a = 0; a < 3; ++a)
    if ((double(f[a]) - x[a]) * dir < 0) f[a] = std::nextafter(f[a], float(dir * kInf));
  return f;
}

/// lo and hi textures (RGBA32F, layout_pow2: no integer division in the pass): xyz relative to
/// `origin`, w = witness flag in lo.
std::pair<gpgpu::Texture, gpgpu::Texture> upload_boxes(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& bx,
                                                       const std::vector<char>& witness, const glm::dvec3& origin,
                                                       int max_size) {
  const gpgpu::Layout2D l = gpgpu::layout_pow2(std::max<int64_t>(1, int64_t(bx.size())), max_size);
  std::vector<float> lo(size_t(l.capacity()) * 4, 0.0f), hi(size_t(l.capacity()) * 4, 0.0f);
  for (size_t k = 0; k < bx.size(); ++k) {
    const glm::vec4 l4 = round_out(bx[k].first - origin, -1.0, witness[k] ? 1.0f : 0.0f);
    const glm::vec4 h4 = round_out(bx[k].second - origin, 1.0, 0.0f);
    std::copy(&l4[0], &l4[0] + 4, lo.begin() + std::ptrdiff_t(4 * k));
    std::copy(&h4[0], &h4[0] + 4, hi.begin() + std::ptrdiff_t(4 * k));
  }
  std::pair<gpgpu::Texture, gpgpu::Texture> t{gpgpu::Texture(l.width, l.height, gpgpu::Format::RGBA32F),
                                              gpgpu::Texture(l.width, l.height, gpgpu::Format::RGBA32F)};
  t.first.upload(lo);
  t.second.upload(hi);
  return t;
}

/// Positions in g.voxels in Morton (Z) order of the voxel coordinates: consecutive voxels are
/// close in all three axes, so a tile's rows (or columns) have a small hull.
std::vector<size_t> morton_order(const VoxelGrid& g) {
  const auto key = [&](int v) {
    const int c[3] = {v % g.n, (v / g.n) % g.n, v / (g.n * g.n)};
    uint64_t k = 0;
    for (int bit = 0; bit < 21; ++bit)
      for (int a = 0; a < 3; ++a) k |= uint64_t((c[a] >> bit) & 1) << (3 * bit + a);
    return k;
  };
  std::vector<std::pair<uint64_t, size_t>> keys;
  for (size_t k = 0; k < g.voxels.size(); ++k) keys.emplace_back(key(g.voxels[k]), k);
  std::sort(keys.begin(), keys.end());
  std::vector<size_t> order;
  for (const auto& k : keys) order.push_back(k.second);
  return order;
}

/// Boxes and witness flags of `g` in `order`, B's refitted under `motion`.
struct OrderedBoxes {
  std::vector<std::pair<glm::dvec3, glm::dvec3>> box;
  std::vector<char> witness;
};
OrderedBoxes ordered_boxes(const VoxelGrid& g, const glm::dmat4& motion, const std::vector<size_t>& order) {
  const auto bx = boxes(g, motion);
  OrderedBoxes r;
  for (size_t k : order) {
    r.box.push_back(bx[k]);
    r.witness.push_back(g.witness[k]);
  }
  return r;
}

/// An upper bound of the clearance from one witness pair, in O(voxels): the witness voxel of A
/// nearest the centre of B's boxes, and the witness voxel of B nearest to that one. Seeds the cut
/// of the first tiles; +inf when a side has no witness.
double seed_upper(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& ba, const std::vector<char>& wa,
                  const std::vector<std::pair<glm::dvec3, glm::dvec3>>& bb, const std::vector<char>& wb) {
  const auto nearest = [](const auto& bx, const std::vector<char>& w, const glm::dvec3& p) {
    size_t best = bx.size();
    double d = kInf;
    for (size_t k = 0; k < bx.size(); ++k)
      if (w[k] && glm::length(0.5 * (bx[k].first + bx[k].second) - p) < d) {
        d = glm::length(0.5 * (bx[k].first + bx[k].second) - p);
        best = k;
      }
    return best;
  };
  glm::dvec3 centre(0.0);
  for (const auto& x : bb) centre += 0.5 * (x.first + x.second) / double(bb.size());
  const size_t i = nearest(ba, wa, centre);
  if (i == ba.size()) return kInf;
  const size_t j = nearest(bb, wb, 0.5 * (ba[i].first + ba[i].second));
  return j == bb.size() ? kInf : box_box_minmax(ba[i].first, ba[i].second, bb[j].first, bb[j].second).second;
}

/// Lower bound of every pair of a tile: the distance of the box of its rows' boxes (A, from a0,
/// h of them) and the box of its columns' boxes (B, from b0, w of them).
double tile_lower(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& ba, size_t a0, size_t h,
                  const std::vector<std::pair<glm::dvec3, glm::dvec3>>& bb, size_t b0, size_t w) {
  const auto hull = [](const auto& bx, size_t k0, size_t count) {
    std::pair<glm::dvec3, glm::dvec3> u{glm::dvec3(kInf), glm::dvec3(-kInf)};
    for (size_t k = k0; k < k0 + count; ++k) u = {glm::min(u.first, bx[k].first), glm::max(u.second, bx[k].second)};
    return u;
  };
  const auto [lo1, hi1] = hull(ba, a0, h);
  const auto [lo2, hi2] = hull(bb, b0, w);
  return box_box_minmax(lo1, hi1, lo2, hi2).first;
}

}  // namespace

std::pair<glm::dvec3, glm::dvec3> VoxelGrid::box(int v) const {
  const glm::dvec3 i(v % n, (v / n) % n, v / (n * n));
  return {lo + h * i, lo + h * (i + 1.0)};
}

VoxelGrid voxelize(const PreparedModel& m, const VoxelizeOptions& options) {
  std::vector<FaceInput> in;
  for (size_t f = 0; f < m.faces.size(); ++f) in.push_back({&m.faces[f], &m.bounds[f], &m.trims[f]});
  return build(in, options);
}

VoxelGrid voxelize(const std::vector<nurbs::TrimmedSurface>& faces, const VoxelizeOptions& options) {
  std::vector<nurbs::FilipBound> bounds;
  std::vector<nurbs::TrimPolygons> trims;
  std::vector<FaceInput> in;
  for (const auto& f : faces) {
    bounds.push_back(nurbs::filip_bound(f.surface));
    trims.push_back(f.loops.empty() ? nurbs::TrimPolygons{}
                                    : nurbs::flatten_trim(f, nurbs::query_flatten_tolerance(f.surface)));
  }
  for (size_t f = 0; f < faces.size(); ++f) in.push_back({&faces[f], &bounds[f], &trims[f]});
  return build(in, options);
}

std::pair<double, double> box_box_minmax(const glm::dvec3& lo1, const glm::dvec3& hi1, const glm::dvec3& lo2,
                                         const glm::dvec3& hi2) {
  const glm::dvec3 b1 = 0.5 * (hi1 - lo1), b2 = 0.5 * (hi2 - lo2);
  const glm::dvec3 dc = glm::abs(0.5 * (lo1 + hi1) - 0.5 * (lo2 + hi2));
  return {glm::length(glm::max(dc - b1 - b2, glm::dvec3(0.0))), glm::length(dc + b1 + b2)};  // Eqs. (13)-(20)
}

VoxelStage voxel_stage_cpu(const VoxelGrid& a, const VoxelGrid& b, const glm::dmat4& motion_b,
                           const VoxelOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  VoxelStage r = start(a, b);
  const auto ba = boxes(a, glm::dmat4(1.0)), bb = boxes(b, motion_b);
  r.upper = kInf;
  for (size_t i = 0; i < ba.size(); ++i)
    for (size_t j = 0; j < bb.size(); ++j)
      if (a.witness[i] && b.witness[j])
        r.upper = std::min(r.upper, box_box_minmax(ba[i].first, ba[i].second, bb[j].first, bb[j].second).second);
  const double cut = r.upper * (1 + options.slack);
  std::vector<char> mark(size_t(a.face_count) * size_t(b.face_count), 0);
  for (size_t i = 0; i < ba.size(); ++i)
    for (size_t j = 0; j < bb.size(); ++j) {
      const double lower = box_box_minmax(ba[i].first, ba[i].second, bb[j].first, bb[j].second).first;
      r.borderline_pairs += std::abs(lower - cut) <= 1e-6 * cut ? 1 : 0;
      if (lower <= cut) {
        ++r.surviving_pairs;
        mark_faces(a, b, i, j, mark);
      }
    }
  finish(a, b, mark, r);
  r.timings.total = nurbs::seconds_since(t0);
  return r;
}

VoxelStage voxel_stage(gpgpu::Gpu& gpu, const VoxelGrid& a, const VoxelGrid& b, const glm::dmat4& motion_b,
                       const VoxelOptions& options) {
  auto t = std::chrono::steady_clock::now();
  const auto t0 = t;
  const auto lap = [&](double& field) {
    gpu.finish();
    field += nurbs::seconds_since(t);
    t = std::chrono::steady_clock::now();
  };
  VoxelStage r = start(a, b);
  std::vector<char> mark(size_t(a.face_count) * size_t(b.face_count), 0);
  r.upper = kInf;
  if (r.voxel_pairs == 0) {
    finish(a, b, mark, r);
    return r;
  }
  const int max_size = gpu.info().max_texture_size, side = std::min(options.max_tile, max_size);
  const glm::dvec3 origin = a.lo + 0.5 * double(a.n) * a.h;  // keeps coordinates small in float
  // Rows and columns in Morton order (tiles compact in space); order_* maps them back to voxels.
  const std::vector<size_t> order_a = morton_order(a), order_b = morton_order(b);
  const OrderedBoxes oa = ordered_boxes(a, glm::dmat4(1.0), order_a), ob = ordered_boxes(b, motion_b, order_b);
  const auto &ba = oa.box, &bb = ob.box;
  const auto ta = upload_boxes(ba, oa.witness, origin, max_size), tb = upload_boxes(bb, ob.witness, origin, max_size);
  // One sweep over the tiles: each tile's candidates are kept against the best U so far (never
  // below the final U, so a superset), with their lower bounds, and filtered by the final U below.
  double running = seed_upper(ba, oa.witness, bb, ob.witness) * (1 + 1e-6);  // a float margin above it
  lap(r.timings.upload);
  gpgpu::Program& prog = queries::program(gpu, "voxel_pairs_minmax.frag");
  gpgpu::Program& thr = queries::program(gpu, "threshold_le.frag");
  const gpgpu::Input in[] = {
      {"u_lo_a", &ta.first}, {"u_hi_a", &ta.second}, {"u_lo_b", &tb.first}, {"u_hi_b", &tb.second}};
  struct Candidate {
    size_t ia, ib;
    float lower;
  };
  std::vector<Candidate> cands;
  const auto cut_of = [&](double u) {
    return std::isfinite(u) ? float(u * (1 + options.slack)) : std::numeric_limits<float>::max();
  };
  // Tiles nearest first (by the distance of their rows' and columns' hulls): U falls fast, and with
  // cull_tiles the far ones are skipped. The result does not depend on the order.
  std::vector<std::pair<double, std::pair<size_t, size_t>>> tiles;
  for (size_t a0 = 0; a0 < ba.size(); a0 += size_t(side))
    for (size_t b0 = 0; b0 < bb.size(); b0 += size_t(side))
      tiles.push_back(
          {tile_lower(ba, a0, std::min(size_t(side), ba.size() - a0), bb, b0, std::min(size_t(side), bb.size() - b0)),
           {a0, b0}});
  std::sort(tiles.begin(), tiles.end());
  r.tiles = int(tiles.size());
  for (const auto& [lower, tile] : tiles) {
    const auto [a0, b0] = tile;
    const size_t h = std::min(size_t(side), ba.size() - a0), w = std::min(size_t(side), bb.size() - b0);
    // Its pairs' max >= min >= the hulls' distance: a tile beyond the cut holds no answer.
    if (options.cull_tiles && lower > 1.0001 * double(cut_of(running))) {
      ++r.culled_tiles;
      continue;
    }
    gpgpu::PooledTexture mm = gpu.acquire(int(w), int(h), gpgpu::Format::RG32F);
    prog.set("u_offset", int(b0), int(a0));
    gpgpu::Texture* out[] = {mm.get()};
    gpu.run("voxel_pairs_minmax", prog, in, out);
    lap(r.timings.minmax);
    const double u = gpgpu::reduce_min(gpu, *mm, 1);
    r.upper = std::min(r.upper, u);
    running = std::min(running, u);
    lap(r.timings.reduce);
    gpgpu::PooledTexture keep = gpu.acquire(int(w), int(h), gpgpu::Format::R8);
    thr.set("u_cut", cut_of(running));
    const gpgpu::Input tin[] = {{"u_values", mm.get()}};
    gpgpu::Texture* tout[] = {keep.get()};
    gpu.run("threshold_le", thr, tin, tout);
    const gpgpu::Compacted c = gpgpu::compact(gpu, *keep, *mm);
    lap(r.timings.compact);
    const std::vector<uint32_t> src = c.read_source();
    const std::vector<float> rec = c.read_records();
    for (int64_t k = 0; k < c.count; ++k)
      cands.push_back({a0 + src[size_t(k)] / w, b0 + src[size_t(k)] % w, rec[size_t(2 * k)]});
    lap(r.timings.readback);
  }
  const float cut = cut_of(r.upper);
  for (const Candidate& c : cands)
    if (c.lower <= cut) {
      ++r.surviving_pairs;
      mark_faces(a, b, order_a[c.ia], order_b[c.ib], mark);
    }
  finish(a, b, mark, r);
  lap(r.timings.readback);
  r.timings.total = nurbs::seconds_since(t0);
  return r;
}

}  // namespace queries
