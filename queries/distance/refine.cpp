#include "queries/distance/refine.h"

#include "queries/distance/cell_triangles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <optional>

#include "nurbs/distance/filip_bound.h"
#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/clearance.h"
#include "queries/distance/point_batch_trim.h"
#include "queries/distance/point_distance.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A parameter rectangle of one face: corners 0..3 at (u0, v0), (u1, v0), (u0, v1), (u1, v1).
struct Cell {
  int face = -1;
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  glm::dvec3 corner[4];
  unsigned material = 0;  ///< bit k: corner k lies inside the trim
  double k = 0;           ///< K_e of the rectangle
  glm::dvec3 lo{0.0}, hi{0.0};
  int32_t first_child = -1;  ///< children, once split: [first_child, first_child + children)
  int32_t children = 0;
  bool splittable = true;
  /// A cell one straight trim edge crosses: the material side of its two triangles, cut by that
  /// edge in (u, v) and mapped by the triangles' own affine maps (up to four triangles; 0 = none,
  /// the whole cell). Every material point of the cell lies within K_e of these pieces, so they
  /// give the pair search lower bounds that do not lag by the trimmed-away part of the cell.
  int pieces = 0;
  glm::dvec3 piece[4][3];
  glm::dvec2 piece_uv[4][3];

  [[nodiscard]] glm::dvec2 uv(int c) const { return cell_corner_uv(c, u0, u1, v0, v1); }
  /// Triangle t of the cell (cell_triangles.h: the diagonal of the GPU path's cells).
  void triangle(int t, glm::dvec3 out[3]) const {
    for (int k = 0; k < 3; ++k) out[k] = corner[kCellTriangle[t][k]];
  }
  /// (u, v) of the point with barycentric weights w in triangle t.
  [[nodiscard]] glm::dvec2 uv_at(int t, const glm::dvec3& w) const {
    return w.x * uv(kCellTriangle[t][0]) + w.y * uv(kCellTriangle[t][1]) + w.z * uv(kCellTriangle[t][2]);
  }
  /// The triangles that bound the cell's material for the lower bounds: the pieces, else the two
  /// triangles; with (u, v) at barycentric weights w.
  [[nodiscard]] int bound_triangles() const { return pieces > 0 ? pieces : 2; }
  void bound_triangle(int t, glm::dvec3 out[3]) const {
    if (pieces == 0) return triangle(t, out);
    for (int k = 0; k < 3; ++k) out[k] = piece[t][k];
  }
  [[nodiscard]] glm::dvec2 bound_uv_at(int t, const glm::dvec3& w) const {
    if (pieces == 0) return uv_at(t, w);
    return w.x * piece_uv[t][0] + w.y * piece_uv[t][1] + w.z * piece_uv[t][2];
  }
};

/// cross(b - a, p - a): positive left of the line ab, negative right.
double side_of(glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

/// Cuts the cell's two triangles by the straight trim edge ab, keeping the side `side` (the sign of
/// side_of on the material side); fills c.pieces (0 when nothing is left).
void cut_by_edge(Cell& c, glm::dvec2 a, glm::dvec2 b, double side) {
  const auto sign = [&](glm::dvec2 p) { return side * side_of(a, b, p); };
  c.pieces = 0;
  for (int t = 0; t < 2; ++t) {
    glm::dvec2 in[3];
    glm::dvec3 pos[3];
    for (int k = 0; k < 3; ++k) in[k] = c.uv(kCellTriangle[t][k]), pos[k] = c.corner[kCellTriangle[t][k]];
    // Sutherland-Hodgman against the half-plane sign >= 0: at most 4 vertices.
    glm::dvec2 out[4];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 p = in[k], q = in[(k + 1) % 3];
      const double sp = sign(p), sq = sign(q);
      if (sp >= 0.0) out[n++] = p;
      if ((sp >= 0.0) != (sq >= 0.0)) out[n++] = p + (q - p) * (sp / (sp - sq));
    }
    if (n < 3) continue;
    // The triangle's affine map from (u, v) to space: barycentric weights in its (u, v) triangle.
    const glm::dvec2 e1 = in[1] - in[0], e2 = in[2] - in[0];
    const double det = e1.x * e2.y - e1.y * e2.x;
    const auto map = [&](glm::dvec2 p) {
      const glm::dvec2 d = p - in[0];
      const double w1 = (d.x * e2.y - d.y * e2.x) / det, w2 = (e1.x * d.y - e1.y * d.x) / det;
      return (1.0 - w1 - w2) * pos[0] + w1 * pos[1] + w2 * pos[2];
    };
    for (int k = 1; k + 1 < n; ++k) {  // a fan
      const glm::dvec2 f[3] = {out[0], out[k], out[k + 1]};
      for (int j = 0; j < 3; ++j) c.piece[c.pieces][j] = map(f[j]), c.piece_uv[c.pieces][j] = f[j];
      ++c.pieces;
    }
  }
}

/// Least distance between a point and a box (Eqs. 9-12) and between two boxes (Eqs. 13-20).
double point_box(const glm::dvec3& p, const Cell& c) {
  return glm::length(glm::max(glm::max(c.lo - p, p - c.hi), glm::dvec3(0.0)));
}
double box_box(const Cell& a, const Cell& b) {
  return glm::length(glm::max(glm::max(a.lo - b.hi, b.lo - a.hi), glm::dvec3(0.0)));
}

/// How loose a cell's bounds are: K_e inside the trim and where one straight edge cuts the cell
/// (its pieces), the box diagonal on other trim edges.
double slack(const Cell& c) { return c.material == 15u || c.pieces > 0 ? c.k : glm::length(c.hi - c.lo); }

/// The cells of one model (mapped by a rigid motion), created from grid cells and split on demand.
class Cells {
 public:
  Cells(const PreparedModel& m, const glm::dmat4& motion)
      : m_(m),
        motion_(motion),
        inverse_(glm::inverse(motion)),
        grid_index_(m.faces.size()),
        banded_(m.faces.size()),
        material_rect_(m.faces.size()) {
    // Per trimmed face, the (u, v) box of its outer loops: no material lies outside it.
    for (size_t f = 0; f < m.faces.size(); ++f) {
      if (f >= m.trims.size()) break;
      const nurbs::TrimPolygons& t = m.trims[f];
      glm::dvec2 lo(kInf), hi(-kInf);
      for (size_t l = 0; l < t.loops.size(); ++l)
        if (l < t.outer.size() && t.outer[l])
          for (const glm::dvec2& p : t.loops[l]) lo = glm::min(lo, p), hi = glm::max(hi, p);
      if (lo.x <= hi.x && lo.y <= hi.y) material_rect_[f] = std::pair{lo, hi};
    }
  }

  /// Polishes (u, v) on `face` towards the closest point to q (q in moved coordinates). When the
  /// Newton point is trimmed away (the closest point often lies on a trim edge), the last material
  /// point on the way there from the material start uv, by bisection.
  glm::dvec2 polish(int face, const glm::dvec3& q, glm::dvec2 uv, int iterations) {
    const glm::dvec2 to =
        nurbs::project_point(m_.faces[size_t(face)].surface, glm::dvec3(inverse_ * glm::dvec4(q, 1.0)), uv, iterations);
    if (at(face, to).material) return to;
    glm::dvec2 in = uv, out = to;
    for (int k = 0; k < 16; ++k) {
      const glm::dvec2 mid = 0.5 * (in + out);
      (at(face, mid).material ? in : out) = mid;
    }
    return in;
  }

  std::vector<Cell> all;

  /// The cells of grid cells `grid` (their indices, in that order): each distinct one created once,
  /// on the hardware threads, appended in the order of first appearance (the sequential order).
  std::vector<uint32_t> add_grid_cells(const std::vector<FaceCell>& grid) {
    constexpr uint32_t kPending = std::numeric_limits<uint32_t>::max();
    std::vector<FaceCell> fresh;
    for (const FaceCell& c : grid)
      if (uint32_t& s = slot(c); s == 0) s = kPending, fresh.push_back(c);
    // The band index of each trimmed face the cells lie on, made here, before the threads read it:
    // a point query touches a few faces of a model of hundreds.
    for (const FaceCell& c : fresh)
      if (const auto f = size_t(c.face); !m_.faces[f].loops.empty() && !banded_[f]) banded_[f].emplace(m_.trims[f]);
    const size_t first = all.size();
    all.resize(first + fresh.size());
    nurbs::for_shares(fresh.size(), nurbs::share_count(fresh.size(), 256), [&](size_t, size_t begin, size_t end) {
      for (size_t n = begin; n < end; ++n) all[first + n] = grid_cell(fresh[n]);
    });
    for (size_t n = 0; n < fresh.size(); ++n) slot(fresh[n]) = uint32_t(first + n + 1);
    std::vector<uint32_t> out;
    out.reserve(grid.size());
    for (const FaceCell& c : grid) out.push_back(slot(c) - 1);
    return out;
  }

  /// The surface point at uv of `face` (moved) and whether it is material.
  struct Sample {
    glm::dvec3 p{0.0};
    bool material = false;
  };
  /// Whether uv of `face` is material (no evaluation).
  [[nodiscard]] bool material_uv(int face, glm::dvec2 uv) const {
    return m_.faces[size_t(face)].loops.empty() || banded_[size_t(face)]->is_material(uv);
  }
  Sample at(int face, glm::dvec2 uv) const {
    const nurbs::TrimmedSurface& f = m_.faces[size_t(face)];
    const glm::dvec3 q = glm::dvec3(motion_ * glm::dvec4(nurbs::surface_point(f.surface, uv.x, uv.y), 1.0));
    return {q, f.loops.empty() || banded_[size_t(face)]->is_material(uv)};
  }

  /// Splits cell i 2 x 2 (once); children with no material are culled.
  void split(uint32_t i) {
    if (all[i].first_child >= 0 || !all[i].splittable) return;
    const Cell p = all[i];
    const double um = 0.5 * (p.u0 + p.u1), vm = 0.5 * (p.v0 + p.v1);
    // The 3 x 3 samples of the children: the parent's corners and five new ones.
    Sample s[3][3];
    s[0][0] = {p.corner[0], bool(p.material & 1)};
    s[2][0] = {p.corner[1], bool(p.material & 2)};
    s[0][2] = {p.corner[2], bool(p.material & 4)};
    s[2][2] = {p.corner[3], bool(p.material & 8)};
    const double us[3] = {p.u0, um, p.u1}, vs[3] = {p.v0, vm, p.v1};
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y)
        if (x == 1 || y == 1) s[x][y] = at(p.face, {us[x], vs[y]});
    const auto first = int32_t(all.size());
    for (int cy = 0; cy < 2; ++cy)
      for (int cx = 0; cx < 2; ++cx) {
        Cell c;
        c.face = p.face;
        c.u0 = us[cx], c.u1 = us[cx + 1], c.v0 = vs[cy], c.v1 = vs[cy + 1];
        for (int k = 0; k < 4; ++k) set_corner(c, k, s[cx + (k & 1)][cy + (k >> 1)]);
        if (c.material == 0 && !trim_crosses(c)) continue;  // entirely trimmed away
        finish(c);
        all.push_back(c);
      }
    all[i].first_child = first;
    all[i].children = int32_t(all.size()) - first;
  }

  /// Whether a cell's corner is trimmed or a trim edge crosses it: an answer there may lie on the
  /// trim edge (Refined::on_trim_edge).
  [[nodiscard]] bool on_trim_edge(const Cell& c) const { return c.material != 15u || trim_crosses(c); }
  /// Whether material may lie in the cell: a material corner, or a trim edge crossing it.
  [[nodiscard]] bool may_hold_material(const Cell& c) const { return c.material != 0u || trim_crosses(c); }

 private:
  /// Index + 1 of the cell of grid cell c (0: none yet); a face's table is made when it first appears.
  uint32_t& slot(const FaceCell& c) {
    std::vector<uint32_t>& t = grid_index_[size_t(c.face)];
    const nurbs::ParamGrid& g = m_.grids[size_t(c.face)].grid;
    if (t.empty()) t.assign(size_t(g.cells_u()) * size_t(g.cells_v()), 0);
    return t[size_t(c.j) * size_t(g.cells_u()) + size_t(c.i)];
  }

  /// The cell of grid cell c, its corners evaluated (thread-safe: reads the model only).
  Cell grid_cell(const FaceCell& c) const {
    const nurbs::ParamGrid& g = m_.grids[size_t(c.face)].grid;
    Cell cell;
    cell.face = c.face;
    cell.u0 = g.u[size_t(c.i)], cell.u1 = g.u[size_t(c.i) + 1];
    cell.v0 = g.v[size_t(c.j)], cell.v1 = g.v[size_t(c.j) + 1];
    for (int k = 0; k < 4; ++k) set_corner(cell, k, at(cell.face, cell.uv(k)));
    finish(cell);
    return cell;
  }

  static void set_corner(Cell& c, int k, const Sample& s) {
    c.corner[k] = s.p;
    if (s.material) c.material |= 1u << k;
  }

  void finish(Cell& c) const {
    c.k = nurbs::filip_k_rect(m_.bounds[size_t(c.face)], {c.u0, c.u1}, {c.v0, c.v1}, nurbs::KNorm::Euclidean);
    c.lo = glm::min(glm::min(c.corner[0], c.corner[1]), glm::min(c.corner[2], c.corner[3]));
    c.hi = glm::max(glm::max(c.corner[0], c.corner[1]), glm::max(c.corner[2], c.corner[3]));
    // Grown by K_e and the rounding of the double evaluation (a few ulp of the coordinates).
    double grow = c.k + 1e-14 * std::max(glm::length(c.lo), glm::length(c.hi));
    // A cell one straight trim edge crosses: its material side (cut_by_edge), and the box of that.
    if (const std::optional<BandedTrim>& b = banded_[size_t(c.face)]; b && c.material != 0u && c.material != 15u) {
      const auto edges = b->edges_in_box({c.u0, c.v0}, {c.u1, c.v1}, 2);
      if (edges.size() == 1) {
        const auto [a, e] = edges.front();
        // The material side: that of the material corners, every trimmed corner on the other side.
        double r[4], side = 0.0;
        for (int k = 0; k < 4; ++k) {
          r[k] = side_of(a, e, c.uv(k));
          if (((c.material >> k) & 1u) && side == 0.0 && r[k] != 0.0) side = r[k] > 0.0 ? 1.0 : -1.0;
        }
        bool consistent = side != 0.0;
        for (int k = 0; k < 4; ++k)
          consistent = consistent && ((c.material >> k) & 1u ? side * r[k] >= 0.0 : side * r[k] <= 0.0);
        if (consistent) cut_by_edge(c, a, e, side);
        if (c.pieces > 0) {
          glm::dvec3 lo(kInf), hi(-kInf);
          for (int t = 0; t < c.pieces; ++t)
            for (const glm::dvec3& q : c.piece[t]) lo = glm::min(lo, q), hi = glm::max(hi, q);
          c.lo = glm::max(c.lo, lo), c.hi = glm::min(c.hi, hi);
          c.lo -= glm::dvec3(grow);
          c.hi += glm::dvec3(grow);
          set_splittable(c);
          return;
        }
      }
    }
    // A cell reaching beyond its face's outer loops (faces whose domain has a margin around the
    // trim, as planes read from STEP and IGES do) holds its material in the overlap: its box is the
    // overlap's, a lower bound that no longer lags by the margin. (Parallel plane edges 143.5 mm
    // apart kept a lower bound 7e-4 short, the width of one plane's margin, while their equidistant
    // cell pairs grew fourfold a round until the budget ran out.)
    if (const auto& r = material_rect_[size_t(c.face)]) {
      const double u0 = std::max(c.u0, r->first.x), u1 = std::min(c.u1, r->second.x);
      const double v0 = std::max(c.v0, r->first.y), v1 = std::min(c.v1, r->second.y);
      if (u0 <= u1 && v0 <= v1 && (u0 > c.u0 || u1 < c.u1 || v0 > c.v0 || v1 < c.v1)) {
        const double k = nurbs::filip_k_rect(m_.bounds[size_t(c.face)], {u0, u1}, {v0, v1}, nurbs::KNorm::Euclidean);
        glm::dvec3 lo(kInf), hi(-kInf);
        for (const glm::dvec2 uv : {glm::dvec2(u0, v0), glm::dvec2(u1, v0), glm::dvec2(u0, v1), glm::dvec2(u1, v1)}) {
          const glm::dvec3 q = at(c.face, uv).p;
          lo = glm::min(lo, q), hi = glm::max(hi, q);
        }
        c.lo = lo, c.hi = hi;
        grow = k + 1e-14 * std::max(glm::length(lo), glm::length(hi));
      }
    }
    c.lo -= glm::dvec3(grow);
    c.hi += glm::dvec3(grow);
    set_splittable(c);
  }

  void set_splittable(Cell& c) const {
    const nurbs::Interval du = nurbs::surface_domain_u(m_.faces[size_t(c.face)].surface);
    const nurbs::Interval dv = nurbs::surface_domain_v(m_.faces[size_t(c.face)].surface);
    c.splittable = c.u1 - c.u0 > 1e-12 * du.width() && c.v1 - c.v0 > 1e-12 * dv.width();
  }

  /// Whether an edge of the face's trim polygons meets the cell's rectangle (then material may lie
  /// inside even with every corner trimmed).
  bool trim_crosses(const Cell& c) const {
    const std::optional<BandedTrim>& b = banded_[size_t(c.face)];
    return b && b->meets_box({c.u0, c.v0}, {c.u1, c.v1});
  }

  const PreparedModel& m_;
  glm::dmat4 motion_, inverse_;
  std::vector<std::vector<uint32_t>> grid_index_;  ///< per face, by grid cell: slot()
  std::vector<std::optional<BandedTrim>> banded_;  ///< per trimmed face of a cell (is_material, edge-box)
  /// Per trimmed face with outer loops: the (u, v) box of those loops (finish clips boxes to it).
  std::vector<std::optional<std::pair<glm::dvec2, glm::dvec2>>> material_rect_;
};

/// The children of cell i to pair with (itself when it is not split).
std::pair<uint32_t, uint32_t> children_of(Cells& cells, uint32_t i, bool split) {
  if (!split || !cells.all[i].splittable) return {i, 1};
  cells.split(i);
  return {uint32_t(cells.all[i].first_child), uint32_t(cells.all[i].children)};
}

}  // namespace

Refined refine_point(const PreparedModel& m, const std::vector<FaceCell>& start, const glm::dvec3& p, double tolerance,
                     RefineLimits limits) {
  Cells cells(m, glm::dmat4(1.0));
  std::vector<uint32_t> cand = cells.add_grid_cells(start);
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  Refined r;
  r.distance = kInf;
  double lower = kInf;
  uint32_t best_cell = 0;
  auto offer = [&](const glm::dvec3& q, glm::dvec2 uv, int face, uint32_t cell) {
    const double d = glm::length(q - p);
    if (d < r.distance) r.distance = d, r.point_a = q, r.uv_a = uv, r.face_a = face, best_cell = cell;
  };
  std::vector<double> low(cand.size());
  while (!cand.empty()) {
    r.most_pairs = std::max(r.most_pairs, static_cast<long long>(cand.size()));
    // Upper bounds: material corners, then the surface at the closest triangle point's (u, v).
    for (uint32_t i : cand) {
      const Cell& c = cells.all[i];
      for (int k = 0; k < 4; ++k)
        if (c.material & (1u << k)) offer(c.corner[k], c.uv(k), c.face, i);
    }
    // Lower bounds: the point-box distance, and the distance to the cell's triangles less K_e.
    low.resize(cand.size());
    double nearest = kInf;
    uint32_t near_cell = 0;
    glm::dvec2 near_uv(0.0);
    for (size_t n = 0; n < cand.size(); ++n) {
      const Cell& c = cells.all[cand[n]];
      low[n] = point_box(p, c);
      if (low[n] > r.distance) continue;
      double tri_low = kInf;
      for (int t = 0; t < 2; ++t) {
        glm::dvec3 tri[3], w;
        c.triangle(t, tri);
        const double d = glm::length(closest_on_triangle(p, tri[0], tri[1], tri[2], w) - p);
        tri_low = std::min(tri_low, d);
        if (d < nearest) nearest = d, near_cell = cand[n], near_uv = c.uv_at(t, w);
      }
      low[n] = std::max(low[n], tri_low - c.k);
    }
    if (std::isfinite(nearest)) {
      const int face = cells.all[near_cell].face;
      const Cells::Sample q = cells.at(face, near_uv);
      if (q.material) offer(q.p, near_uv, face, near_cell);
      // A tighter upper bound: Newton from the best point so far (kept only where material).
      if (r.face_a >= 0) {
        const glm::dvec2 uv = cells.polish(r.face_a, p, r.uv_a, 8);
        const Cells::Sample polished = cells.at(r.face_a, uv);
        if (polished.material) offer(polished.p, uv, r.face_a, best_cell);
      }
    }
    std::vector<uint32_t> next;
    double next_lower = kInf;
    for (size_t n = 0; n < cand.size(); ++n) {
      if (low[n] > r.distance) continue;
      if (low[n] >= r.distance - tolerance || !cells.all[cand[n]].splittable) {
        lower = std::min(lower, low[n]);
        if (low[n] < r.distance - tolerance) r.meets_tolerance = false;
        continue;
      }
      next.push_back(cand[n]);
      next_lower = std::min(next_lower, low[n]);
    }
    if (next.empty()) break;
    if (4 * static_cast<long long>(next.size()) > limits.max_pairs || r.rounds >= limits.max_rounds) {
      lower = std::min(lower, next_lower);
      r.meets_tolerance = false;
      break;
    }
    cand.clear();
    for (uint32_t i : next) {
      const auto [first, n] = children_of(cells, i, true);
      for (uint32_t c = first; c < first + n; ++c) cand.push_back(c);
    }
    ++r.rounds;
  }
  r.cells = static_cast<long long>(cells.all.size());
  if (!std::isfinite(r.distance)) return r;
  r.found = true;
  r.point_b = p;
  r.bound = r.distance - std::min(lower, r.distance);
  r.on_trim_edge = cells.on_trim_edge(cells.all[best_cell]);
  return r;
}

namespace {

/// uv of `face` if material, else the first material point a tiny step from it towards `centre`
/// (nullopt: none): a point of a cut cell's piece often lies on the cutting trim edge itself, where
/// the classification may go either way.
std::optional<glm::dvec2> material_near(const Cells& cells, int face, glm::dvec2 uv, glm::dvec2 centre) {
  if (cells.material_uv(face, uv)) return uv;
  for (double t : {1e-9, 1e-6, 1e-3})
    if (const glm::dvec2 moved = uv + t * (centre - uv); cells.material_uv(face, moved)) return moved;
  return std::nullopt;
}

/// The pair search of refine_pairs from the cell pairs `pairs` (indices into ca.all, cb.all).
Refined search_pairs(Cells& ca, Cells& cb, std::vector<std::pair<uint32_t, uint32_t>> pairs, double tolerance,
                     const RefineLimits& limits) {
  Refined r;
  r.distance = kInf;
  double lower = kInf;
  std::pair<uint32_t, uint32_t> best{0, 0};
  auto offer = [&](const glm::dvec3& qa, const glm::dvec3& qb, glm::dvec2 uva, glm::dvec2 uvb, uint32_t i, uint32_t j) {
    const double d = glm::length(qa - qb);
    if (d >= r.distance) return;
    r.distance = d;
    r.point_a = qa, r.point_b = qb;
    r.uv_a = uva, r.uv_b = uvb;
    r.face_a = ca.all[i].face, r.face_b = cb.all[j].face;
    best = {i, j};
  };
  std::vector<double> low;
  while (!pairs.empty()) {
    r.most_pairs = std::max(r.most_pairs, static_cast<long long>(pairs.size()));
    // Per pair independent work in contiguous shares over the hardware threads; each share keeps
    // its first strict minimum, merged in share order: the sequential answer at any thread count.
    const size_t shares = nurbs::share_count(pairs.size(), 2048);
    // Upper bounds: material corner pairs, then the surfaces at the closest triangle points' (u, v).
    struct Corner {
      double d = kInf;
      glm::dvec3 qa{0.0}, qb{0.0};
      glm::dvec2 uva{0.0}, uvb{0.0};
      uint32_t i = 0, j = 0;
    };
    std::vector<Corner> corners(shares);
    nurbs::for_shares(pairs.size(), shares, [&](size_t t, size_t begin, size_t end) {
      Corner& c = corners[t];
      c.d = r.distance;  // only improvements count
      for (size_t n = begin; n < end; ++n) {
        const auto [i, j] = pairs[n];
        const Cell &x = ca.all[i], &y = cb.all[j];
        for (int k = 0; k < 4; ++k)
          for (int l = 0; l < 4; ++l)
            if ((x.material & (1u << k)) && (y.material & (1u << l))) {
              const double d = glm::length(x.corner[k] - y.corner[l]);
              if (d < c.d) c = {d, x.corner[k], y.corner[l], x.uv(k), y.uv(l), i, j};
            }
      }
    });
    for (const Corner& c : corners)
      if (c.d < r.distance) offer(c.qa, c.qb, c.uva, c.uvb, c.i, c.j);
    // Lower bounds: box-box, and the distance of the cells' triangles less K_a + K_b.
    low.resize(pairs.size());
    struct Nearest {
      double d = kInf;
      size_t pair = 0;
      glm::dvec2 a{0.0}, b{0.0};  ///< material (u, v) at (or a tiny step inside from) the nearest points
    };
    std::vector<Nearest> nearests(shares);
    const double split_below = r.distance - tolerance;
    nurbs::for_shares(pairs.size(), shares, [&](size_t share, size_t begin, size_t end) {
      Nearest& near = nearests[share];
      for (size_t n = begin; n < end; ++n) {
        const Cell &x = ca.all[pairs[n].first], &y = cb.all[pairs[n].second];
        low[n] = box_box(x, y);
        if (low[n] > r.distance) continue;
        double tri_low = kInf;
        bool split = false;
        for (int s = 0; s < x.bound_triangles() && !split; ++s)
          for (int t = 0; t < y.bound_triangles() && !split; ++t) {
            glm::dvec3 ta[3], tb[3], pa, pb, wa, wb;
            x.bound_triangle(s, ta);
            y.bound_triangle(t, tb);
            const double d = triangle_distance(ta, tb, pa, pb, wa, wb);
            tri_low = std::min(tri_low, d);
            // The nearest triangle points whose (u, v) are material on both sides (a whole cell's
            // triangles reach into its trimmed part, whose points give no upper bound).
            if (d < near.d) {
              const glm::dvec3 third(1.0 / 3.0);
              const auto ua = material_near(ca, x.face, x.bound_uv_at(s, wa), x.bound_uv_at(s, third));
              const auto ub =
                  ua ? material_near(cb, y.face, y.bound_uv_at(t, wb), y.bound_uv_at(t, third)) : std::nullopt;
              if (ub) near = {d, n, *ua, *ub};
            }
            // Split for certain (its least triangle distance can only be lower): the box is its
            // lower bound, and the pair's other triangles are left to its children.
            split = low[n] < split_below && d - x.k - y.k < split_below;
          }
        if (!split) low[n] = std::max(low[n], tri_low - x.k - y.k);
      }
    });
    Nearest nearest;
    for (const Nearest& n : nearests)
      if (n.d < nearest.d) nearest = n;
    if (std::isfinite(nearest.d)) {
      const auto [i, j] = pairs[nearest.pair];
      // The triangles' nearest points with material (u, v) (material_near): true surface points there.
      const Cells::Sample qa = ca.at(ca.all[i].face, nearest.a), qb = cb.at(cb.all[j].face, nearest.b);
      if (qa.material && qb.material) offer(qa.p, qb.p, nearest.a, nearest.b, i, j);
      // A tighter upper bound: alternating Newton projections from the best pair so far, each
      // step a pair of true surface points (kept only where both are material).
      glm::dvec2 ua = r.uv_a, ub = r.uv_b;
      glm::dvec3 pa = r.point_a;
      const auto [bi, bj] = best;
      for (int it = 0; it < 4 && r.face_a >= 0; ++it) {
        ub = cb.polish(r.face_b, pa, ub, 6);
        const Cells::Sample sb = cb.at(r.face_b, ub);
        ua = ca.polish(r.face_a, sb.p, ua, 6);
        const Cells::Sample sa = ca.at(r.face_a, ua);
        if (!sa.material || !sb.material) break;
        offer(sa.p, sb.p, ua, ub, bi, bj);
        pa = sa.p;
      }
    }
    std::vector<std::pair<uint32_t, uint32_t>> next;
    double next_lower = kInf;
    for (size_t n = 0; n < pairs.size(); ++n) {
      const auto [i, j] = pairs[n];
      if (low[n] > r.distance) continue;
      if (low[n] >= r.distance - tolerance || (!ca.all[i].splittable && !cb.all[j].splittable)) {
        lower = std::min(lower, low[n]);
        if (low[n] < r.distance - tolerance) r.meets_tolerance = false;
        continue;
      }
      next.emplace_back(i, j);
      next_lower = std::min(next_lower, low[n]);
    }
    if (std::getenv("NURBSGL_REFINE_DEBUG"))
      std::fprintf(stderr, "round %d: %zu pairs, U %.9g, %zu to split, next lower %.9g\n", r.rounds, pairs.size(),
                   r.distance, next.size(), next_lower);
    if (next.empty()) break;
    if (16 * static_cast<long long>(next.size()) > limits.max_pairs || r.rounds >= limits.max_rounds) {
      lower = std::min(lower, next_lower);
      r.meets_tolerance = false;
      break;
    }
    pairs.clear();
    for (const auto& [i, j] : next) {
      // Split the side that holds most of the pair's error (both when they are close): K_e for a
      // cell inside the trim, its extent for one on a trim edge (there the gap to the closest
      // material point shrinks with the cell's size, not with K_e).
      const double ki = slack(ca.all[i]), kj = slack(cb.all[j]);
      bool si = ca.all[i].splittable && ki >= 0.25 * kj, sj = cb.all[j].splittable && kj >= 0.25 * ki;
      if (!si && !sj) si = ca.all[i].splittable, sj = !si;  // one side at least (both unsplittable settled)
      const auto [fi, ni] = children_of(ca, i, si);
      const auto [fj, nj] = children_of(cb, j, sj);
      for (uint32_t x = fi; x < fi + ni; ++x)
        for (uint32_t y = fj; y < fj + nj; ++y) pairs.emplace_back(x, y);
    }
    ++r.rounds;
  }
  r.cells = static_cast<long long>(ca.all.size() + cb.all.size());
  if (!std::isfinite(r.distance)) return r;
  r.found = true;
  r.bound = r.distance - std::min(lower, r.distance);
  r.on_trim_edge = ca.on_trim_edge(ca.all[best.first]) || cb.on_trim_edge(cb.all[best.second]);
  return r;
}

}  // namespace

Refined refine_pairs(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                     const std::vector<std::pair<FaceCell, FaceCell>>& start, double tolerance, RefineLimits limits) {
  Cells ca(a, glm::dmat4(1.0)), cb(b, motion_b);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  std::vector<FaceCell> xs, ys;
  xs.reserve(start.size()), ys.reserve(start.size());
  for (const auto& [x, y] : start) xs.push_back(x), ys.push_back(y);
  const std::vector<uint32_t> ia = ca.add_grid_cells(xs), ib = cb.add_grid_cells(ys);
  for (size_t n = 0; n < start.size(); ++n) pairs.emplace_back(ia[n], ib[n]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return search_pairs(ca, cb, std::move(pairs), tolerance, limits);
}

long long grid_cell_count(const PreparedModel& m) {
  long long n = 0;
  for (const nurbs::CertifiedGrid& g : m.grids) n += static_cast<long long>(g.grid.cells_u()) * g.grid.cells_v();
  return n;
}

std::optional<Refined> refine_all_pairs(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                                        double tolerance, double upper, long long max_start_pairs,
                                        RefineLimits limits) {
  Cells ca(a, glm::dmat4(1.0)), cb(b, motion_b);
  // Every grid cell that holds material (a material corner, or a trim edge crossing it).
  auto cells_of = [](const PreparedModel& m, Cells& cells) {
    std::vector<FaceCell> all;
    for (size_t f = 0; f < m.grids.size(); ++f)
      for (int j = 0; j < m.grids[f].grid.cells_v(); ++j)
        for (int i = 0; i < m.grids[f].grid.cells_u(); ++i) all.push_back({int(f), i, j});
    std::vector<uint32_t> index = cells.add_grid_cells(all), kept;
    for (uint32_t k : index)
      if (cells.may_hold_material(cells.all[k])) kept.push_back(k);
    return kept;
  };
  std::vector<uint32_t> xs = cells_of(a, ca), ys = cells_of(b, cb);
  // A first upper bound from two material corners: A's nearest to the centre of B's cells, B's
  // nearest to that, and back. (None where a side's cells have no material corner: thin faces
  // between grid lines. Such a side once gave the other side's corner as its own, and an upper
  // bound of 0 that pruned every pair: a nut and a bolt of an assembly, 21.1 apart, "not found".)
  auto nearest = [](const Cells& cells, const std::vector<uint32_t>& index, const glm::dvec3& to) {
    double best = kInf;
    std::optional<glm::dvec3> at;
    for (uint32_t k : index)
      for (int c = 0; c < 4; ++c)
        if (cells.all[k].material & (1u << c))
          if (const double d = glm::length(cells.all[k].corner[c] - to); d < best)
            best = d, at = cells.all[k].corner[c];
    return at;
  };
  glm::dvec3 centre(0.0);
  for (uint32_t y : ys) centre += 0.5 * (cb.all[y].lo + cb.all[y].hi) / double(ys.size());
  std::optional<glm::dvec3> pa = nearest(ca, xs, centre);
  for (int round = 0; round < 2 && pa; ++round) {
    const std::optional<glm::dvec3> pb = nearest(cb, ys, *pa);
    if (!pb) break;
    upper = std::min(upper, glm::length(*pa - *pb));
    pa = nearest(ca, xs, *pb);
  }
  // The cells of each side within the upper bound of the other side's box, then their pairs whose
  // boxes lie within it.
  auto near_box = [&](const Cells& cells, std::vector<uint32_t>& index, const Cells& other,
                      const std::vector<uint32_t>& other_index) {
    Cell box;
    box.lo = glm::dvec3(kInf), box.hi = glm::dvec3(-kInf);
    for (uint32_t k : other_index)
      box.lo = glm::min(box.lo, other.all[k].lo), box.hi = glm::max(box.hi, other.all[k].hi);
    std::erase_if(index, [&](uint32_t k) { return box_box(cells.all[k], box) > upper; });
  };
  near_box(ca, xs, cb, ys);
  near_box(cb, ys, ca, xs);
  if (max_start_pairs >= 0 && static_cast<long long>(xs.size()) * static_cast<long long>(ys.size()) > max_start_pairs)
    return std::nullopt;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> rows(nurbs::share_count(xs.size(), 64));
  nurbs::for_shares(xs.size(), rows.size(), [&](size_t share, size_t begin, size_t end) {
    for (size_t n = begin; n < end; ++n)
      for (uint32_t y : ys)
        if (box_box(ca.all[xs[n]], cb.all[y]) <= upper) rows[share].emplace_back(xs[n], y);
  });
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (const auto& row : rows) pairs.insert(pairs.end(), row.begin(), row.end());
  Refined r = search_pairs(ca, cb, std::move(pairs), tolerance, limits);
  r.start_pairs = static_cast<long long>(xs.size()) * static_cast<long long>(ys.size());
  return r;
}

}  // namespace queries
