#include "nurbs/raycast/bicubic_patches.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>

#include "nurbs/bezier_extraction.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace nurbs::ray {
namespace {

glm::dvec3 lerp(const glm::dvec3& a, const glm::dvec3& b, double t) { return a + (b - a) * t; }

/// de Casteljau on a cubic: point and derivative.
void casteljau3(const glm::dvec3* q, double t, glm::dvec3& point, glm::dvec3& deriv) {
  const glm::dvec3 a = lerp(q[0], q[1], t), b = lerp(q[1], q[2], t), c = lerp(q[2], q[3], t);
  const glm::dvec3 d = lerp(a, b, t), e = lerp(b, c, t);
  point = lerp(d, e, t);
  deriv = 3.0 * (e - d);
}

/// The Bézier pieces of a surface, addressed by span indices, plus their break parameters.
struct Pieces {
  std::vector<BezierPatch> list;
  std::vector<double> ub, vb;  ///< span boundaries
  int nu = 0;
  const Surface& at(double u, double v) const {  // piece containing the open cell around (u, v)
    const int i = static_cast<int>(std::upper_bound(ub.begin(), ub.end(), u) - ub.begin()) - 1;
    const int j = static_cast<int>(std::upper_bound(vb.begin(), vb.end(), v) - vb.begin()) - 1;
    const int ic = std::clamp(i, 0, nu - 1), jc = std::clamp(j, 0, static_cast<int>(vb.size()) - 2);
    return list[static_cast<size_t>(jc) * nu + ic].surface;
  }
};

Pieces make_pieces(const Surface& s) {
  Pieces p;
  p.list = extract_bezier_patches(s);
  std::sort(p.list.begin(), p.list.end(), [](const BezierPatch& a, const BezierPatch& b) {
    return a.index_v != b.index_v ? a.index_v < b.index_v : a.index_u < b.index_u;
  });
  for (const auto& b : p.list) {
    if (b.index_v == 0) p.ub.push_back(b.range_u.min);
    if (b.index_u == 0) p.vb.push_back(b.range_v.min);
  }
  p.ub.push_back(p.list.back().range_u.max);
  p.vb.push_back(p.list.back().range_v.max);
  p.nu = static_cast<int>(p.ub.size()) - 1;
  return p;
}

/// Hermite bicubic of the cell [u0, u1] x [v0, v1] of one Bézier piece (see the header).
BicubicPatch hermite_patch(const Surface& piece, double u0, double u1, double v0, double v1) {
  BicubicPatch out;
  const double h = u1 - u0, k = v1 - v0;
  for (int cj = 0; cj < 2; ++cj)
    for (int ci = 0; ci < 2; ++ci) {
      const SurfaceDerivatives d = surface_derivatives(piece, ci ? u1 : u0, cj ? v1 : v0);
      const double su = ci ? -1.0 : 1.0, sv = cj ? -1.0 : 1.0;  // inward steps
      const int i0 = ci ? 3 : 0, j0 = cj ? 3 : 0, i1 = ci ? 2 : 1, j1 = cj ? 2 : 1;
      out.p[4 * j0 + i0] = d.s;
      out.p[4 * j0 + i1] = d.s + su * h / 3.0 * d.su;
      out.p[4 * j1 + i0] = d.s + sv * k / 3.0 * d.sv;
      out.p[4 * j1 + i1] = d.s + su * h / 3.0 * d.su + sv * k / 3.0 * d.sv + su * sv * h * k / 9.0 * d.suv;
    }
  out.range_u = {u0, u1};
  out.range_v = {v0, v1};
  out.box_min = out.box_max = out.p[0];
  for (const auto& q : out.p) {
    out.box_min = glm::min(out.box_min, q);
    out.box_max = glm::max(out.box_max, q);
  }
  return out;
}

double piece_error(const Surface& piece, const BicubicPatch& patch, int n) {
  double worst = 0.0;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const double s = (a + 0.5) / n, t = (b + 0.5) / n;
      const double u = patch.range_u.min + s * (patch.range_u.max - patch.range_u.min);
      const double v = patch.range_v.min + t * (patch.range_v.max - patch.range_v.min);
      worst = std::max(worst, glm::length(evaluate_patch(patch, s, t).s - surface_point(piece, u, v)));
    }
  return worst;
}

/// Do the unit normals at the cell's corners, centre and edge midpoints all lie within the angle
/// acos(min_cos) of the centre's? (Degenerate points, e.g. poles, have no normal and are skipped.)
bool normals_within(const Surface& piece, const std::array<double, 4>& cell, double min_cos) {
  const double um = 0.5 * (cell[0] + cell[1]), vm = 0.5 * (cell[2] + cell[3]);
  auto normal = [&](double u, double v) {
    const SurfaceDerivatives d = surface_derivatives(piece, u, v);
    const glm::dvec3 n = glm::cross(d.su, d.sv);
    const double l = glm::length(n);
    return l > 0.0 ? n / l : glm::dvec3(0.0);
  };
  const glm::dvec3 c = normal(um, vm);
  if (c == glm::dvec3(0.0)) return true;
  const double us[3] = {cell[0], um, cell[1]}, vs[3] = {cell[2], vm, cell[3]};
  for (double v : vs)
    for (double u : us) {
      const glm::dvec3 n = normal(u, v);
      if (n != glm::dvec3(0.0) && glm::dot(n, c) < min_cos) return false;
    }
  return true;
}

/// §3.1 culling: keep a cell when any trim edge meets it (inflated by the flattening tolerance) or
/// its centre is material. A cell with neither lies wholly in one region, which is not material.
bool cell_kept(const TrimPolygons& trim, bool trimmed, glm::dvec2 lo, glm::dvec2 hi, double pad) {
  if (!trimmed) return true;
  if (is_material(trim, 0.5 * (lo + hi))) return true;
  const glm::dvec2 l = lo - pad, h = hi + pad;
  for (const auto& loop : trim.loops)
    for (size_t i = 0; i < loop.size(); ++i)
      if (segment_meets_box(loop[i], loop[(i + 1) % loop.size()], l, h)) return true;
  return false;
}

}  // namespace

PatchPoint evaluate_patch(const BicubicPatch& patch, double s, double t) {
  glm::dvec3 rows[4], drows[4];
  for (int j = 0; j < 4; ++j) casteljau3(&patch.p[4 * j], s, rows[j], drows[j]);
  PatchPoint out;
  casteljau3(rows, t, out.s, out.st);
  glm::dvec3 unused;
  casteljau3(drows, t, out.ss, unused);
  return out;
}

double sampled_error(const Surface& surface, const BicubicPatch& patch, int n) {
  return piece_error(surface, patch, n);
}

std::vector<BicubicPatch> bicubic_patches(const TrimmedSurface& face, int face_index, const BicubicOptions& options,
                                          BicubicStats* stats) {
  const Pieces pieces = make_pieces(face.surface);
  std::vector<double> ub = pieces.ub, vb = pieces.vb;
  const double diag = std::hypot(ub.back() - ub.front(), vb.back() - vb.front());
  const bool trimmed = !face.loops.empty();
  const double flat = options.trim_flatten * diag;
  const TrimPolygons trim = trimmed ? flatten_trim(face, flat) : TrimPolygons{};
  BicubicStats st;
  struct CellCheck {
    double error = -1.0;  ///< sampled error, -1 = culled
    bool flat = true;     ///< normals within max_turn_degrees of each other
  };
  std::map<std::array<double, 4>, CellCheck> cache;
  const double min_cos = std::cos(options.max_turn_degrees * 3.14159265358979323846 / 180.0);
  auto cell_check = [&](size_t i, size_t j) {
    const std::array<double, 4> key{ub[i], ub[i + 1], vb[j], vb[j + 1]};
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    CellCheck c;
    if (cell_kept(trim, trimmed, {key[0], key[2]}, {key[1], key[3]}, 2.0 * flat)) {
      const Surface& piece = pieces.at(0.5 * (key[0] + key[1]), 0.5 * (key[2] + key[3]));
      const BicubicPatch patch = hermite_patch(piece, key[0], key[1], key[2], key[3]);
      c.error = piece_error(piece, patch, options.samples);
      // Small cells stay as they are: around a pole the normals turn in every cell that touches it.
      if (options.max_turn_degrees > 0.0 && glm::length(patch.box_max - patch.box_min) > 100.0 * options.tolerance)
        c.flat = normals_within(piece, key, min_cos);
    }
    cache.emplace(key, c);
    return c;
  };
  auto cell_error = [&](size_t i, size_t j) { return cell_check(i, j).error; };
  const double limit = options.margin * options.tolerance;
  // Splits for the normal turn alone take at most kTurnRounds rounds (each halves the grid lines
  // through turning cells): on wildly wavy nets the conforming grid would otherwise multiply.
  constexpr int kTurnRounds = 3;
  int turn_rounds = 0;
  for (st.rounds = 0;; ++st.rounds) {
    std::vector<char> split_u(ub.size() - 1, 0), split_v(vb.size() - 1, 0);
    bool any = false, turn_only = false;
    for (size_t j = 0; j + 1 < vb.size(); ++j)
      for (size_t i = 0; i + 1 < ub.size(); ++i) {
        const CellCheck c = cell_check(i, j);
        if (c.error <= limit && (c.flat || turn_rounds >= kTurnRounds)) continue;
        turn_only = turn_only || c.error <= limit;
        // Split across the direction of larger curvature h^2 |Suu| vs k^2 |Svv| (both when close).
        const double uc = 0.5 * (ub[i] + ub[i + 1]), vc = 0.5 * (vb[j] + vb[j + 1]);
        const SurfaceDerivatives d = surface_derivatives(pieces.at(uc, vc), uc, vc);
        const double h = ub[i + 1] - ub[i], k = vb[j + 1] - vb[j];
        const double eu = h * h * glm::length(d.suu), ev = k * k * glm::length(d.svv);
        if (eu >= 0.25 * ev) split_u[i] = 1;
        if (ev >= 0.25 * eu) split_v[j] = 1;
        any = true;
      }
    if (!any) break;
    turn_rounds += turn_only ? 1 : 0;
    const size_t cells = (ub.size() - 1) * (vb.size() - 1);
    if (st.rounds >= options.max_rounds || cells > static_cast<size_t>(options.max_cells)) {
      st.converged = false;
      break;
    }
    auto refine = [](std::vector<double>& br, const std::vector<char>& split) {
      std::vector<double> out;
      for (size_t i = 0; i + 1 < br.size(); ++i) {
        out.push_back(br[i]);
        if (split[i]) out.push_back(0.5 * (br[i] + br[i + 1]));
      }
      out.push_back(br.back());
      br = std::move(out);
    };
    refine(ub, split_u);
    refine(vb, split_v);
  }
  std::vector<BicubicPatch> out;
  for (size_t j = 0; j + 1 < vb.size(); ++j)
    for (size_t i = 0; i + 1 < ub.size(); ++i) {
      const double e = cell_error(i, j);
      if (e < 0.0) {
        ++st.culled;
        continue;
      }
      st.max_sampled_error = std::max(st.max_sampled_error, e);
      const Surface& piece = pieces.at(0.5 * (ub[i] + ub[i + 1]), 0.5 * (vb[j] + vb[j + 1]));
      out.push_back(hermite_patch(piece, ub[i], ub[i + 1], vb[j], vb[j + 1]));
      out.back().face = face_index;
    }
  st.patches = static_cast<int>(out.size());
  if (stats) *stats = st;
  return out;
}

}  // namespace nurbs::ray
