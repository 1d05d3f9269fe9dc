#include "queries/distance/point_distance.h"

#include "queries/distance/cell_triangles.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <set>
#include <stdexcept>
#include <tuple>

#include "gpgpu/compact.h"
#include "gpgpu/reduce.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/material_distance.h"
#include "queries/distance/refine.h"
#include "queries/shaders.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The closest point of a triangle (or a cell) on the CPU.
struct CellHit {
  double distance = kInf;
  glm::dvec3 point{0.0};
  glm::dvec2 uv{0.0};
};

/// The corners of cell (i, j) in TrimEdges order: (u_{i + (k & 1)}, v_{j + (k >> 1)}).
std::array<glm::dvec3, 4> cell_corners(const nurbs::Surface& s, const nurbs::ParamGrid& g, int i, int j) {
  std::array<glm::dvec3, 4> c;
  for (int k = 0; k < 4; ++k)
    c[size_t(k)] = nurbs::surface_point(s, g.u[size_t(i + (k & 1))], g.v[size_t(j + (k >> 1))]);
  return c;
}

/// The closest points to p of the two triangles of cell (i, j) (cell_triangles.h), with their (u, v).
std::array<CellHit, 2> triangle_hits(const nurbs::Surface& s, const nurbs::ParamGrid& g, int i, int j,
                                     const glm::dvec3& p) {
  const auto c = cell_corners(s, g, i, j);
  const CellTriangles tri =
      cell_triangles(c.data(), g.u[size_t(i)], g.u[size_t(i) + 1], g.v[size_t(j)], g.v[size_t(j) + 1]);
  std::array<CellHit, 2> hits;
  for (int t = 0; t < 2; ++t) {
    glm::dvec3 w;
    const glm::dvec3 q = closest_on_triangle(p, tri.p[t][0], tri.p[t][1], tri.p[t][2], w);
    hits[size_t(t)] = {glm::length(q - p), q, tri.uv_at(t, w)};
  }
  return hits;
}

/// One candidate cell evaluated on the CPU: the closer of its two triangles.
CellHit cell_hit(const nurbs::Surface& s, const nurbs::ParamGrid& g, int i, int j, const glm::dvec3& p) {
  const auto h = triangle_hits(s, g, i, j, p);
  return h[1].distance < h[0].distance ? h[1] : h[0];
}

}  // namespace

glm::dvec3 closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                               glm::dvec3& w) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return w = {1, 0, 0}, a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return w = {0, 1, 0}, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 > d3) {
    const double t = d1 / (d1 - d3);
    return w = {1 - t, t, 0}, a + t * ab;
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return w = {0, 0, 1}, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 > d6) {
    const double t = d2 / (d2 - d6);
    return w = {1 - t, 0, t}, a + t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0 && (d4 - d3) + (d5 - d6) > 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return w = {0, 1 - t, t}, b + t * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, t = vc * denom;
  return w = {1 - v - t, v, t}, a + v * ab + t * ac;
}

void set_refined(PointDistance& r, const Refined& f) {
  r.found = f.found;
  r.distance = f.distance;
  r.point = f.point_a;
  r.uv = f.uv_a;
  r.face = f.face_a;
  r.bound = f.bound;
  r.point_bound = std::sqrt(4 * f.bound * f.distance + f.bound * f.bound);
  r.on_trim_edge = f.on_trim_edge;
  r.meets_tolerance = f.meets_tolerance;
  r.rounds = f.rounds;
  r.refined_cells = f.cells;
}

PointDistanceQuery::PointDistanceQuery(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                                       long long max_samples, Search search)
    : gpu_(gpu), m_(prepare_model(gpu, std::move(faces), tolerance, max_samples, search)) {}

PointDistance PointDistanceQuery::query(const glm::dvec3& p) {
  PointDistance r;
  const long long host_cells = host_cells_used();
  auto on_host = [&](const FaceAtlas& at) {
    return static_cast<long long>(at.plan.width) * at.plan.height <= host_cells;
  };
  // Pass 1 and the reduction, per atlas: R = min, G = max distance to each cell's box; U = min G.
  // Atlases pruned on the CPU read the pass back instead (host_cells).
  std::vector<gpgpu::PooledTexture> minmax;
  std::vector<std::vector<float>> read(m_.atlases.size());
  double upper = kInf;
  const glm::vec3 q(p - m_.centre), o(m_.centre);
  for (size_t a = 0; a < m_.atlases.size(); ++a) {
    const FaceAtlas& at = m_.atlases[a];
    minmax.push_back(gpu_.acquire(at.plan.width, at.plan.height, gpgpu::Format::RG32F));
    gpgpu::Program& prog = queries::program(gpu_, "point_aabb_minmax.frag", {{"TRIM_CROSSED", "1"}});
    prog.set("u_point", q.x, q.y, q.z);
    prog.set("u_origin", o.x, o.y, o.z);
    const gpgpu::Input in[] = {{"u_points", &at.points},
                               {"u_slot_of", &at.slot_of},
                               {"u_mask", &at.mask},
                               {"u_grow", &m_.grow[a]},
                               {"u_crossed", &m_.crossed[a]}};
    gpgpu::Texture* out[] = {minmax.back().get()};
    gpu_.run("point_aabb_minmax", prog, in, out);
    if (on_host(at)) {
      read[a] = minmax.back()->read();  // reduce_min's CPU twin: the same minimum, NaN ignored
      upper = std::min(upper, gpgpu::reduce_cpu(read[a], 2,
                                                {gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min,
                                                 gpgpu::ReduceOp::Min})[1]);
    } else {
      upper = std::min(upper, double(gpgpu::reduce_min(gpu_, *minmax.back().get(), 1)));
    }
    r.cells += static_cast<long long>(at.plan.width) * at.plan.height;
  }
  r.upper = upper;
  // Pass 2: the cells whose lower bound is within U (a relative 1e-5 above it covers float rounding
  // of both), compacted and read back.
  const float cut = std::isfinite(upper) ? float(upper * (1 + 1e-5)) : std::numeric_limits<float>::max();
  std::vector<FaceCell> cells;
  for (size_t a = 0; a < m_.atlases.size(); ++a) {
    const FaceAtlas& at = m_.atlases[a];
    if (on_host(at)) {  // threshold_le's test, in texel order as the compaction keeps them
      for (size_t k = 0; 2 * k < read[a].size(); ++k)
        if (read[a][2 * k] <= cut)
          if (const auto cell = m_.cell_at(a, int(k % size_t(at.plan.width)), int(k / size_t(at.plan.width))))
            cells.push_back(*cell);
      continue;
    }
    gpgpu::PooledTexture keep = gpu_.acquire(at.plan.width, at.plan.height, gpgpu::Format::R8);
    gpgpu::Program& prog = queries::program(gpu_, "threshold_le.frag");
    prog.set("u_cut", cut);
    const gpgpu::Input in[] = {{"u_values", minmax[a].get()}};
    gpgpu::Texture* out[] = {keep.get()};
    gpu_.run("threshold_le", prog, in, out);
    const gpgpu::Compacted c = gpgpu::compact(gpu_, *keep.get(), *minmax[a].get());
    if (c.count == 0) continue;
    for (uint32_t idx : c.read_source())
      if (const auto cell = m_.cell_at(a, int(idx % uint32_t(at.plan.width)), int(idx / uint32_t(at.plan.width))))
        cells.push_back(*cell);
  }
  r.candidates = static_cast<long long>(cells.size());
  if (m_.search == Search::CoarseToFine) {  // candidates refined in double until they meet T (refine.h)
    set_refined(r, refine_point(m_, cells, p, m_.tolerance));
    return r;
  }
  // Faithful: two triangles per candidate cell in double. §5.3: a triangle's closest point inside
  // a trimmed region is discarded and the search goes on over the triangle's material part, whose
  // closest point then lies on a trim edge inside the cell (material_distance.h).
  struct Candidate {
    CellHit hit;
    int face, i, j;
    bool trimmed;
  };
  std::vector<Candidate> cands;
  double k = 0.0;
  for (const FaceCell& c : cells) {
    const nurbs::Surface& s = m_.faces[size_t(c.face)].surface;
    const nurbs::ParamGrid& g = m_.grids[size_t(c.face)].grid;
    k = std::max(k, nurbs::grid_cell_k(m_.bounds[size_t(c.face)], g, c.i, c.j, nurbs::KNorm::Euclidean));
    const bool trimmed = !m_.faces[size_t(c.face)].loops.empty();
    for (const CellHit& h : triangle_hits(s, g, c.i, c.j, p))
      cands.push_back({h, c.face, c.i, c.j, trimmed && !nurbs::is_material(m_.trims[size_t(c.face)], h.uv)});
  }
  // Nearest first (ties in cell order): the material ones, then the trimmed ones still nearer.
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Candidate& x, const Candidate& y) { return x.hit.distance < y.hit.distance; });
  const Candidate* win = nullptr;
  for (const Candidate& c : cands)
    if (!c.trimmed) {
      win = &c;
      break;
    }
  if (win) {
    r.found = true;
    r.distance = win->hit.distance, r.point = win->hit.point, r.uv = win->hit.uv, r.face = win->face;
    if (!m_.faces[size_t(win->face)].loops.empty()) {
      const auto& g = m_.grids[size_t(win->face)].grid;
      for (int corner = 0; corner < 4; ++corner)
        if (!nurbs::is_material(m_.trims[size_t(win->face)],
                                {g.u[size_t(win->i + (corner & 1))], g.v[size_t(win->j + (corner >> 1))]}))
          r.on_trim_edge = true;
    }
  }
  FaceTrimEdges edges(m_);                       // indexed when a cell of the face first needs them
  std::set<std::tuple<int, int, int>> searched;  // cells whose trim pieces were read (both triangles')
  for (const Candidate& c : cands) {
    if (r.found && !(c.hit.distance < r.distance)) break;
    if (!c.trimmed || !searched.insert({c.face, c.i, c.j}).second) continue;
    const auto corners = cell_corners(m_.faces[size_t(c.face)].surface, m_.grids[size_t(c.face)].grid, c.i, c.j);
    TrimEdgeHit hit{r.found ? r.distance : kInf};
    if (!edges(c.face)->closest(p, c.i, c.j, corners.data(), hit)) continue;
    r.found = r.on_trim_edge = true;
    r.distance = hit.distance, r.point = hit.point, r.uv = hit.uv, r.face = c.face;
  }
  // Theorem 1 over the material parts: every candidate cell's triangles lie within K of the surface.
  r.bound = k;
  r.point_bound = std::sqrt(4 * r.bound * r.distance + r.bound * r.bound);
  return r;
}

PointDistance point_distance_cpu(const nurbs::Surface& s, const nurbs::FilipBound& b, const nurbs::ParamGrid& g,
                                 const glm::dvec3& p) {
  const int nu = g.cells_u(), nv = g.cells_v();
  std::vector<glm::dvec3> pts;
  for (double v : g.v)
    for (double u : g.u) pts.push_back(nurbs::surface_point(s, u, v));
  const double grow = nurbs::grid_k(b, g, nurbs::KNorm::Euclidean);
  std::vector<double> dmin(size_t(nu) * size_t(nv));
  double upper = kInf;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      glm::dvec3 lo(kInf), hi(-kInf);
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3& q = pts[size_t(j + (k >> 1)) * g.u.size() + size_t(i + (k & 1))];
        lo = glm::min(lo, q), hi = glm::max(hi, q);
      }
      const glm::dvec3 c = 0.5 * (lo + hi), B = 0.5 * (hi - lo) + glm::dvec3(grow), D = glm::abs(p - c);
      upper = std::min(upper, glm::length(D + B));                                             // Eqs. (5)-(8)
      dmin[size_t(j) * size_t(nu) + size_t(i)] = glm::length(glm::max(D - B, glm::dvec3(0)));  // Eqs. (9)-(12)
    }
  PointDistance r;
  r.cells = static_cast<long long>(nu) * nv;
  r.upper = upper;
  r.distance = kInf;
  double k = 0.0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      if (dmin[size_t(j) * size_t(nu) + size_t(i)] > upper) continue;
      ++r.candidates;
      k = std::max(k, nurbs::grid_cell_k(b, g, i, j, nurbs::KNorm::Euclidean));
      const CellHit h = cell_hit(s, g, i, j, p);
      if (h.distance < r.distance) r.distance = h.distance, r.point = h.point, r.uv = h.uv;
    }
  r.found = true;
  r.face = 0;
  r.bound = k;
  r.point_bound = std::sqrt(4 * k * r.distance + k * k);
  return r;
}

}  // namespace queries
