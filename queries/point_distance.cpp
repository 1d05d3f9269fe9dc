#include "queries/point_distance.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>

#include "gpgpu/compact.h"
#include "gpgpu/reduce.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/refine.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One candidate cell evaluated on the CPU: the closer of its two triangles.
struct CellHit {
  double distance = kInf;
  glm::dvec3 point{0.0};
  glm::dvec2 uv{0.0};
};

CellHit cell_hit(const nurbs::Surface& s, const nurbs::ParamGrid& g, int i, int j, const glm::dvec3& p) {
  const double u0 = g.u[size_t(i)], u1 = g.u[size_t(i) + 1], v0 = g.v[size_t(j)], v1 = g.v[size_t(j) + 1];
  const glm::dvec3 a = nurbs::surface_point(s, u0, v0), b = nurbs::surface_point(s, u1, v0);
  const glm::dvec3 c = nurbs::surface_point(s, u0, v1), d = nurbs::surface_point(s, u1, v1);
  // The two triangles of the (i, j)-(i+1, j+1) diagonal, with their corners' parameters.
  const glm::dvec3 tri[2][3] = {{a, b, d}, {a, d, c}};
  const glm::dvec2 par[2][3] = {{{u0, v0}, {u1, v0}, {u1, v1}}, {{u0, v0}, {u1, v1}, {u0, v1}}};
  CellHit best;
  for (int t = 0; t < 2; ++t) {
    glm::dvec3 w;
    const glm::dvec3 q = closest_on_triangle(p, tri[t][0], tri[t][1], tri[t][2], w);
    const double dist = glm::length(q - p);
    if (dist < best.distance) best = {dist, q, w.x * par[t][0] + w.y * par[t][1] + w.z * par[t][2]};
  }
  return best;
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
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return w = {1 - t, t, 0}, a + t * ab;
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return w = {0, 0, 1}, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return w = {1 - t, 0, t}, a + t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return w = {0, 1 - t, t}, b + t * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, t = vc * denom;
  return w = {1 - v - t, v, t}, a + v * ab + t * ac;
}

PointDistanceQuery::PointDistanceQuery(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                                       long long max_samples, Search search)
    : gpu_(gpu), m_(prepare_model(gpu, std::move(faces), tolerance, max_samples, search)) {}

PointDistance PointDistanceQuery::query(const glm::dvec3& p) {
  PointDistance r;
  // Pass 1 and the reduction, per atlas: R = min, G = max distance to each cell's box; U = min G.
  std::vector<gpgpu::PooledTexture> minmax;
  double upper = kInf;
  const glm::vec3 q(p - m_.centre), o(m_.centre);
  for (size_t a = 0; a < m_.atlases.size(); ++a) {
    const FaceAtlas& at = m_.atlases[a];
    minmax.push_back(gpu_.acquire(at.plan.width, at.plan.height, gpgpu::Format::RG32F));
    gpgpu::Program& prog = gpu_.program("point_aabb_minmax.frag", {{"TRIM_CROSSED", "1"}});
    prog.set("u_point", q.x, q.y, q.z);
    prog.set("u_origin", o.x, o.y, o.z);
    const gpgpu::Input in[] = {{"u_points", &at.points},
                               {"u_slot_of", &at.slot_of},
                               {"u_mask", &at.mask},
                               {"u_grow", &m_.grow[a]},
                               {"u_crossed", &m_.crossed[a]}};
    gpgpu::Texture* out[] = {minmax.back().get()};
    gpu_.run("point_aabb_minmax", prog, in, out);
    upper = std::min(upper, double(gpgpu::reduce_min(gpu_, *minmax.back().get(), 1)));
    r.cells += static_cast<long long>(at.plan.width) * at.plan.height;
  }
  r.upper = upper;
  // Pass 2: the cells whose lower bound is within U (a relative 1e-5 above it covers float rounding
  // of both), compacted and read back.
  const float cut = std::isfinite(upper) ? float(upper * (1 + 1e-5)) : std::numeric_limits<float>::max();
  std::vector<FaceCell> cells;
  for (size_t a = 0; a < m_.atlases.size(); ++a) {
    const FaceAtlas& at = m_.atlases[a];
    gpgpu::PooledTexture keep = gpu_.acquire(at.plan.width, at.plan.height, gpgpu::Format::R8);
    gpgpu::Program& prog = gpu_.program("threshold_le.frag");
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
    const Refined f = refine_point(m_, cells, p, m_.tolerance);
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
    return r;
  }
  // Faithful: two triangles per candidate cell in double.
  struct Candidate {
    CellHit hit;
    int face, i, j;
  };
  std::vector<Candidate> cands;
  for (const FaceCell& c : cells)
    cands.push_back(
        {cell_hit(m_.faces[size_t(c.face)].surface, m_.grids[size_t(c.face)].grid, c.i, c.j, p), c.face, c.i, c.j});
  // On the CPU: the closest triangle point that is material (§5.3); K_e maxed over the candidates.
  std::sort(cands.begin(), cands.end(),
            [](const Candidate& x, const Candidate& y) { return x.hit.distance < y.hit.distance; });
  double k = 0.0;
  for (const Candidate& c : cands)
    k = std::max(k, nurbs::grid_cell_k(m_.bounds[size_t(c.face)], m_.grids[size_t(c.face)].grid, c.i, c.j,
                                       nurbs::KNorm::Euclidean));
  for (const Candidate& c : cands) {
    const nurbs::TrimmedSurface& f = m_.faces[size_t(c.face)];
    if (!f.loops.empty()) {
      const nurbs::TrimPolygons& trim = m_.trims[size_t(c.face)];
      if (!nurbs::is_material(trim, c.hit.uv)) continue;
      const auto& g = m_.grids[size_t(c.face)].grid;
      for (int corner = 0; corner < 4; ++corner)
        if (!nurbs::is_material(trim, {g.u[size_t(c.i + (corner & 1))], g.v[size_t(c.j + (corner >> 1))]}))
          r.on_trim_edge = true;
    }
    r.found = true;
    r.distance = c.hit.distance;
    r.point = c.hit.point;
    r.uv = c.hit.uv;
    r.face = c.face;
    break;
  }
  // Theorem 1 holds for the closest triangle point of all candidates; when closer ones were
  // discarded as trimmed (their cells may still hold material up to the trim edge), the proven
  // bound widens to reach down to them, and the answer is on a trim edge (§5.3's looser case).
  r.bound = k;
  if (r.found && !cands.empty() && cands.front().hit.distance < r.distance) {
    r.bound = std::max(k, r.distance - cands.front().hit.distance + k);
    r.on_trim_edge = true;
  }
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
