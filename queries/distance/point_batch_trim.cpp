#include "queries/distance/point_batch_trim.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace queries {
namespace {

/// Index of the cell of `knots` holding x (clamped to the first and last cell).
int cell_index(const std::vector<double>& knots, double x) {
  const auto it = std::upper_bound(knots.begin(), knots.end(), x);
  return std::clamp(int(it - knots.begin()) - 1, 0, int(knots.size()) - 2);
}

/// Liang-Barsky: the parameter range [l0, l1] of a + l d, l in [0, 1], inside the box [lo, hi]^2;
/// false when it misses the box.
bool clip_to_square(glm::dvec2 a, glm::dvec2 d, double lo, double hi, double& l0, double& l1) {
  l0 = 0.0, l1 = 1.0;
  for (int c = 0; c < 2; ++c)
    for (const auto& [q, r] : {std::pair{-d[c], a[c] - lo}, std::pair{d[c], hi - a[c]}}) {
      if (q == 0.0) {
        if (r < 0.0) return false;
        continue;
      }
      const double l = r / q;
      if (q < 0.0) l0 = std::max(l0, l);
      if (q > 0.0) l1 = std::min(l1, l);
    }
  return l0 <= l1;
}

}  // namespace

TrimEdges::TrimEdges(const nurbs::TrimPolygons& trim, const nurbs::ParamGrid& grid)
    : trim_(&trim),
      grid_(&grid),
      side_step_(1e-9 * std::max(grid.u.back() - grid.u.front(), grid.v.back() - grid.v.front())),
      banded_(trim) {
  const int nu = grid.cells_u();
  // The edge's cells in order: those of its ends and of the middles of its pieces between the grid
  // lines it crosses (a walk in steps shorter than the narrowest cell would take 1e10 steps on
  // faces with a knot span 1e-9 of their domain wide). Consecutive cells are the same or
  // neighbours; the piece between them touches at most their two cells and the two corner cells.
  std::vector<int64_t> keys;
  std::vector<double> at;  // the edge's parameters at its ends and grid-line crossings
  const auto crossings = [&at](const std::vector<double>& lines, double a, double b) {
    if (a == b) return;
    const double lo = std::min(a, b), hi = std::max(a, b);
    for (auto it = std::upper_bound(lines.begin(), lines.end(), lo); it != lines.end() && *it < hi; ++it)
      at.push_back((*it - a) / (b - a));
  };
  for (size_t k = 0; k < trim.loops.size(); ++k) {
    const auto& loop = trim.loops[k];
    for (size_t e = 0; e < loop.size(); ++e) {
      const glm::dvec2 a = loop[e], b = loop[(e + 1) % loop.size()];
      at.assign({0.0, 1.0});
      crossings(grid.u, a.x, b.x);
      crossings(grid.v, a.y, b.y);
      std::sort(at.begin(), at.end());
      keys.clear();
      glm::ivec2 prev(cell_index(grid.u, a.x), cell_index(grid.v, a.y));
      for (size_t s = 0; s < at.size(); ++s) {  // the pieces' middles, then the end b
        const glm::dvec2 q = s + 1 < at.size() ? a + (b - a) * (0.5 * (at[s] + at[s + 1])) : b;
        const glm::ivec2 c(cell_index(grid.u, q.x), cell_index(grid.v, q.y));
        for (const glm::ivec2 t : {c, prev, glm::ivec2(c.x, prev.y), glm::ivec2(prev.x, c.y)})
          keys.push_back(int64_t(t.y) * nu + t.x);
        prev = c;
      }
      std::sort(keys.begin(), keys.end());
      keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
      for (int64_t key : keys) cells_[key].emplace_back(int(k), int(e));
    }
  }
}

void TrimEdges::pieces(int i, int j, const glm::dvec3 corners[4], std::vector<TrimPiece>& out) const {
  if (trim_ == nullptr) return;
  // (s, t) in the unit cell -> the piece's triangle: (0, 1, 3) where s >= t, (0, 3, 2) where t >= s.
  for (const UnitPiece& pc : unit_pieces(i, j)) {
    const auto on = [&](glm::dvec2 st) {
      return pc.lower ? corners[0] + st.x * (corners[1] - corners[0]) + st.y * (corners[3] - corners[1])
                      : corners[0] + st.y * (corners[2] - corners[0]) + st.x * (corners[3] - corners[2]);
    };
    out.push_back({on(pc.st0), on(pc.st1), pc.uv0, pc.uv1, pc.lower ? 0 : 1});
  }
}

const std::vector<TrimEdges::UnitPiece>& TrimEdges::unit_pieces(int i, int j) const {
  const int64_t key = int64_t(j) * grid_->cells_u() + i;
  PieceCache& cache = *piece_cache_;
  {
    std::shared_lock lock(cache.mutex);
    const auto it = cache.cells.find(key);
    if (it != cache.cells.end()) return it->second;  // (a node's value never moves)
  }
  std::vector<UnitPiece> computed;
  compute_unit_pieces(i, j, computed);
  std::unique_lock lock(cache.mutex);
  return cache.cells.try_emplace(key, std::move(computed)).first->second;
}

void TrimEdges::compute_unit_pieces(int i, int j, std::vector<UnitPiece>& out) const {
  const auto it = cells_.find(int64_t(j) * grid_->cells_u() + i);
  if (it == cells_.end()) return;
  const double u0 = grid_->u[size_t(i)], u1 = grid_->u[size_t(i) + 1];
  const double v0 = grid_->v[size_t(j)], v1 = grid_->v[size_t(j) + 1];
  const std::vector<std::pair<int, int>>& edges = it->second;  // grouped by loop (the constructor's order)
  // The edges by the buckets of a B x B grid over the cell their boxes meet, so that an edge is cut
  // against the other loops' edges near it only (a planar face's cell may hold thousands of edges
  // of many loops); a crossing outside the cell or outside the edge cuts nothing it keeps.
  const int nb = std::clamp(int(std::sqrt(double(edges.size()) / 4.0)), 1, 32);
  const auto bucket_range = [&](glm::dvec2 p, glm::dvec2 q, int& bx0, int& bx1, int& by0, int& by1) {
    const double slack = 1e-9;
    const auto to = [&](double x, double lo, double hi) {
      return std::clamp(int(std::floor((x - lo) / (hi - lo) * nb)), 0, nb - 1);
    };
    bx0 = to(std::min(p.x, q.x) - slack * (u1 - u0), u0, u1), bx1 = to(std::max(p.x, q.x) + slack * (u1 - u0), u0, u1);
    by0 = to(std::min(p.y, q.y) - slack * (v1 - v0), v0, v1), by1 = to(std::max(p.y, q.y) + slack * (v1 - v0), v0, v1);
  };
  std::vector<std::vector<uint32_t>> buckets(size_t(nb) * size_t(nb));
  for (size_t n = 0; n < edges.size(); ++n) {
    const auto& loop = trim_->loops[size_t(edges[n].first)];
    int bx0, bx1, by0, by1;
    bucket_range(loop[size_t(edges[n].second)], loop[(size_t(edges[n].second) + 1) % loop.size()], bx0, bx1, by0, by1);
    for (int y = by0; y <= by1; ++y)
      for (int x = bx0; x <= bx1; ++x) buckets[size_t(y) * size_t(nb) + size_t(x)].push_back(uint32_t(n));
  }
  // Each loop's edges are one run of n (the grouping), and so one run of every bucket (which lists
  // n in increasing order): an edge skips its own loop's run by two binary searches (a loop of
  // 100,000 edges collapsed onto a line fills one column of buckets alone).
  std::vector<uint32_t> run_end(edges.size());
  for (size_t n = edges.size(); n-- > 0;)
    run_end[n] = n + 1 < edges.size() && edges[n + 1].first == edges[n].first ? run_end[n + 1] : uint32_t(n + 1);
  std::vector<uint32_t> seen(edges.size(), 0);  // the last edge n + 1 that tested edge n2
  uint32_t run_begin = 0;
  for (size_t n = 0; n < edges.size(); ++n) {
    if (n > 0 && edges[n].first != edges[n - 1].first) run_begin = uint32_t(n);
    const auto [k, e] = edges[n];
    const auto& loop = trim_->loops[size_t(k)];
    const glm::dvec2 a = loop[size_t(e)], b = loop[(size_t(e) + 1) % loop.size()];
    // The edge in unit-cell coordinates, clipped to [0, 1]^2 (Liang-Barsky).
    const glm::dvec2 sa((a.x - u0) / (u1 - u0), (a.y - v0) / (v1 - v0));
    const glm::dvec2 sd((b.x - u0) / (u1 - u0) - sa.x, (b.y - v0) / (v1 - v0) - sa.y);
    double l0 = 0.0, l1 = 1.0;
    if (!clip_to_square(sa, sd, 0.0, 1.0, l0, l1)) continue;
    // Cut where it crosses the diagonal s = t (each piece is straight on its triangle) and the
    // cell's edges of other loops (a hole reaching out of the outer loop; a loop is simple). Only
    // pieces with material beside them bound material, and the side is the same all along a piece:
    // tested at its middle (at a sharp corner's vertex both steps would fall outside).
    std::vector<double> cuts{l0, l1};
    const double denom = sd.x - sd.y;
    if (denom != 0.0) cuts.push_back((sa.y - sa.x) / denom);
    const glm::dvec2 ab = b - a;
    int bx0, bx1, by0, by1;
    bucket_range(a, b, bx0, bx1, by0, by1);
    const auto cut_by = [&](uint32_t n2) {
      if (seen[n2] == n + 1) return;
      seen[n2] = uint32_t(n + 1);
      const auto [k2, e2] = edges[n2];
      if (k2 == k) return;
      const auto& loop2 = trim_->loops[size_t(k2)];
      const glm::dvec2 c = loop2[size_t(e2)], cd = loop2[(size_t(e2) + 1) % loop2.size()] - c;
      const double det = ab.x * cd.y - ab.y * cd.x;
      if (det == 0.0) return;  // parallel
      const glm::dvec2 ac = c - a;
      const double l = (ac.x * cd.y - ac.y * cd.x) / det, mu = (ac.x * ab.y - ac.y * ab.x) / det;
      if (mu >= 0.0 && mu <= 1.0) cuts.push_back(l);
    };
    for (int y = by0; y <= by1; ++y)
      for (int x = bx0; x <= bx1; ++x) {
        const std::vector<uint32_t>& bucket = buckets[size_t(y) * size_t(nb) + size_t(x)];
        const auto own = std::lower_bound(bucket.begin(), bucket.end(), run_begin);
        const auto after = std::lower_bound(own, bucket.end(), run_end[n]);
        for (auto it = bucket.begin(); it != own; ++it) cut_by(*it);
        for (auto it = after; it != bucket.end(); ++it) cut_by(*it);
      }
    std::sort(cuts.begin(), cuts.end());
    const glm::dvec2 side = side_step_ * glm::normalize(glm::dvec2(a.y - b.y, b.x - a.x));
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double m0 = std::max(cuts[c], l0), m1 = std::min(cuts[c + 1], l1);
      if (!(m1 > m0)) continue;  // (an edge that only touches the cell: its neighbour holds it)
      const glm::dvec2 mid = a + 0.5 * (m0 + m1) * ab;
      if (!banded_.is_material(mid + side) && !banded_.is_material(mid - side)) continue;
      const glm::dvec2 st0 = sa + m0 * sd, st1 = sa + m1 * sd, st_mid = 0.5 * (st0 + st1);
      const auto uv = [&](glm::dvec2 st) { return glm::dvec2(u0 + st.x * (u1 - u0), v0 + st.y * (v1 - v0)); };
      out.push_back({st0, st1, uv(st0), uv(st1), st_mid.x >= st_mid.y});
    }
  }
}

void TrimEdges::segments(int i, int j, double margin, std::vector<glm::dvec4>& out) const {
  if (trim_ == nullptr) return;
  const auto it = cells_.find(int64_t(j) * grid_->cells_u() + i);
  if (it == cells_.end()) return;
  const double u0 = grid_->u[size_t(i)], u1 = grid_->u[size_t(i) + 1];
  const double v0 = grid_->v[size_t(j)], v1 = grid_->v[size_t(j) + 1];
  for (const auto& [k, e] : it->second) {
    const auto& loop = trim_->loops[size_t(k)];
    const glm::dvec2 a = loop[size_t(e)], b = loop[(size_t(e) + 1) % loop.size()];
    const glm::dvec2 sa((a.x - u0) / (u1 - u0), (a.y - v0) / (v1 - v0));
    const glm::dvec2 sd((b.x - u0) / (u1 - u0) - sa.x, (b.y - v0) / (v1 - v0) - sa.y);
    double l0 = 0.0, l1 = 1.0;
    if (!clip_to_square(sa, sd, -margin, 1.0 + margin, l0, l1)) continue;
    const glm::dvec2 p = sa + l0 * sd, q = sa + l1 * sd;
    out.emplace_back(p.x, p.y, q.x, q.y);
  }
}

std::vector<glm::ivec2> TrimEdges::cells() const {
  std::vector<glm::ivec2> out;
  out.reserve(cells_.size());
  const int64_t nu = grid_ == nullptr ? 1 : grid_->cells_u();
  for (const auto& [key, edges] : cells_) out.emplace_back(int(key % nu), int(key / nu));
  std::sort(out.begin(), out.end(), [](glm::ivec2 a, glm::ivec2 b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
  return out;
}

bool TrimEdges::closest(const glm::dvec3& p, int i, int j, const glm::dvec3 corners[4], TrimEdgeHit& best) const {
  std::vector<TrimPiece> found;
  pieces(i, j, corners, found);
  bool improved = false;
  for (const TrimPiece& pc : found) {
    const glm::dvec3 d = pc.b - pc.a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - pc.a, d) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 q = pc.a + t * d;
    const double dist = glm::length(q - p);
    if (dist >= best.distance) continue;
    best = {dist, q, pc.uv_at(t)};
    improved = true;
  }
  return improved;
}

}  // namespace queries
