/// \file triangulate_monotone.cpp
/// §7 of Balázs, Guthe and Klein (2004) for non-convex polygons: the O(n log n) triangulation of
/// Garey, Johnson, Preparata and Tarjan (1978). A plane sweep from top to bottom adds diagonals at
/// split and merge vertices so that every piece is y-monotone; each piece is then triangulated in
/// linear time with a stack of reflex vertices.
#include <algorithm>
#include <iterator>
#include <set>

#include "nurbs/tessellation/triangulate.h"
#include "nurbs/tessellation/triangulate_detail.h"

namespace nurbs::tess {
namespace {

using detail::above;
using detail::ccw;

enum class Kind { Start, End, Split, Merge, Regular };

bool angle_less(glm::dvec2 p, glm::dvec2 q) {
  const bool hp = p.y < 0.0 || (p.y == 0.0 && p.x < 0.0), hq = q.y < 0.0 || (q.y == 0.0 && q.x < 0.0);
  if (hp != hq) return !hp;
  return p.x * q.y - p.y * q.x > 0.0;
}

/// Diagonals (local index pairs) that split the polygon P into y-monotone pieces.
std::vector<std::pair<int, int>> monotone_diagonals(const std::vector<glm::dvec2>& P) {
  const int n = static_cast<int>(P.size());
  auto prev = [&](int i) { return (i + n - 1) % n; };
  auto next = [&](int i) { return (i + 1) % n; };
  std::vector<Kind> kind(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const glm::dvec2 p = P[static_cast<std::size_t>(prev(i))], v = P[static_cast<std::size_t>(i)],
                     q = P[static_cast<std::size_t>(next(i))];
    const bool convex = detail::orient_sign(p, v, q) > 0;  // unknown sign: treated as reflex
    if (above(v, p) && above(v, q))
      kind[static_cast<std::size_t>(i)] = convex ? Kind::Start : Kind::Split;
    else if (above(p, v) && above(q, v))
      kind[static_cast<std::size_t>(i)] = convex ? Kind::End : Kind::Merge;
    else
      kind[static_cast<std::size_t>(i)] = Kind::Regular;
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return above(P[static_cast<std::size_t>(a)], P[static_cast<std::size_t>(b)]); });
  // Sweep status: edges e_i = (i, i + 1) with the interior on their right, ordered left to right at
  // the sweep line (a balanced tree: O(log n) per event). Edges of a simple polygon do not cross, so
  // the order found at insertion stays valid; erasing goes through the stored iterator. Key -1 stands
  // for the current event vertex itself.
  std::vector<int> helper(static_cast<std::size_t>(n), -1);
  glm::dvec2 sweep{0.0};
  auto x_at = [&](int e) {
    if (e < 0) return sweep.x;
    const glm::dvec2 a = P[static_cast<std::size_t>(e)], b = P[static_cast<std::size_t>(next(e))];
    if (sweep.y == a.y) return a.y == b.y ? std::max(a.x, b.x) : a.x;
    if (sweep.y == b.y) return b.x;
    return a.x + (sweep.y - a.y) * (b.x - a.x) / (b.y - a.y);
  };
  auto less = [&](int e, int f) {
    const double xe = x_at(e), xf = x_at(f);
    if (xe != xf) return xe < xf;
    if (e < 0 || f < 0) return false;
    // Two edges through the event vertex (only a new edge meeting an old one there): the one going
    // further left below the sweep line is left.
    const glm::dvec2 de = P[static_cast<std::size_t>(next(e))] - P[static_cast<std::size_t>(e)],
                     df = P[static_cast<std::size_t>(next(f))] - P[static_cast<std::size_t>(f)];
    return de.x * df.y - de.y * df.x > 0.0;
  };
  std::set<int, decltype(less)> active(less);
  std::vector<std::set<int, decltype(less)>::iterator> where(static_cast<std::size_t>(n), active.end());
  std::vector<std::pair<int, int>> diag;
  auto insert = [&](int e) { where[static_cast<std::size_t>(e)] = active.insert(e).first; };
  auto left_of = [&](int) {
    if (active.empty()) return -1;
    auto it = active.upper_bound(-1);
    if (it == active.begin()) return *it;  // rounding put every edge to the right: take the nearest
    return *std::prev(it);
  };
  auto erase = [&](int e) {
    auto& it = where[static_cast<std::size_t>(e)];
    if (it != active.end()) active.erase(it), it = active.end();
  };
  auto fix_up = [&](int v, int e) {  // diagonal to a merge vertex that is helper of e
    const int h = helper[static_cast<std::size_t>(e)];
    if (h >= 0 && kind[static_cast<std::size_t>(h)] == Kind::Merge) diag.emplace_back(v, h);
  };
  for (int v : order) {
    sweep = P[static_cast<std::size_t>(v)];
    const int ep = prev(v);
    switch (kind[static_cast<std::size_t>(v)]) {
      case Kind::Start:
        insert(v), helper[static_cast<std::size_t>(v)] = v;
        break;
      case Kind::End:
        fix_up(v, ep), erase(ep);
        break;
      case Kind::Split: {
        const int e = left_of(v);
        if (e >= 0) diag.emplace_back(v, helper[static_cast<std::size_t>(e)]), helper[static_cast<std::size_t>(e)] = v;
        insert(v), helper[static_cast<std::size_t>(v)] = v;
        break;
      }
      case Kind::Merge: {
        fix_up(v, ep), erase(ep);
        const int e = left_of(v);
        if (e >= 0) fix_up(v, e), helper[static_cast<std::size_t>(e)] = v;
        break;
      }
      case Kind::Regular:
        if (above(P[static_cast<std::size_t>(ep)], P[static_cast<std::size_t>(v)])) {  // left chain: interior right
          fix_up(v, ep), erase(ep);
          insert(v), helper[static_cast<std::size_t>(v)] = v;
        } else {
          const int e = left_of(v);
          if (e >= 0) fix_up(v, e), helper[static_cast<std::size_t>(e)] = v;
        }
        break;
    }
  }
  return diag;
}

/// Pieces of P cut along `diag`: faces traced with leftmost turns over the polygon edges (forward)
/// and the diagonals (both ways).
std::vector<std::vector<int>> pieces(const std::vector<glm::dvec2>& P, const std::vector<std::pair<int, int>>& diag) {
  const int n = static_cast<int>(P.size());
  std::vector<std::vector<int>> nb(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) nb[static_cast<std::size_t>(i)] = {(i + 1) % n, (i + n - 1) % n};
  for (auto [a, b] : diag)
    if (a != b) nb[static_cast<std::size_t>(a)].push_back(b), nb[static_cast<std::size_t>(b)].push_back(a);
  for (int i = 0; i < n; ++i)
    std::sort(nb[static_cast<std::size_t>(i)].begin(), nb[static_cast<std::size_t>(i)].end(), [&](int p, int q) {
      return angle_less(P[static_cast<std::size_t>(p)] - P[static_cast<std::size_t>(i)],
                        P[static_cast<std::size_t>(q)] - P[static_cast<std::size_t>(i)]);
    });
  std::vector<std::pair<int, int>> todo;
  for (int i = 0; i < n; ++i) todo.emplace_back(i, (i + 1) % n);
  for (auto [a, b] : diag) todo.emplace_back(a, b), todo.emplace_back(b, a);
  std::sort(todo.begin(), todo.end());
  std::vector<bool> used(todo.size(), false);
  auto index = [&](int a, int b) {
    auto it = std::lower_bound(todo.begin(), todo.end(), std::make_pair(a, b));
    return static_cast<std::size_t>(it - todo.begin());
  };
  std::vector<std::vector<int>> out;
  for (std::size_t s = 0; s < todo.size(); ++s) {
    if (used[s]) continue;
    std::vector<int> face;
    int u = todo[s].first, v = todo[s].second;
    for (int guard = 0; guard <= 2 * static_cast<int>(todo.size()); ++guard) {
      const std::size_t k = index(u, v);
      if (k >= used.size() || todo[k] != std::make_pair(u, v) || used[k]) break;
      used[k] = true;
      face.push_back(u);
      const auto& l = nb[static_cast<std::size_t>(v)];
      const auto it = std::find(l.begin(), l.end(), u);
      const std::size_t i = static_cast<std::size_t>(it - l.begin());
      u = v, v = l[(i + l.size() - 1) % l.size()];
    }
    if (face.size() >= 3) out.push_back(std::move(face));
  }
  return out;
}

/// Linear-time triangulation of a y-monotone counter-clockwise piece (local indices into P).
void triangulate_monotone(const std::vector<glm::dvec2>& P, const std::vector<int>& piece, const std::vector<int>& ids,
                          const std::vector<glm::dvec2>& vertices, std::vector<glm::ivec3>& out,
                          TriangulationStats* stats) {
  const std::size_t m = piece.size();
  auto pt = [&](int local) { return P[static_cast<std::size_t>(local)]; };
  std::size_t top = 0, bottom = 0;
  for (std::size_t i = 1; i < m; ++i) {
    if (above(pt(piece[i]), pt(piece[top]))) top = i;
    if (above(pt(piece[bottom]), pt(piece[i]))) bottom = i;
  }
  std::vector<int> left(P.size(), 0);  // 1: left chain (from top forward to bottom)
  for (std::size_t i = top; i != bottom; i = (i + 1) % m) left[static_cast<std::size_t>(piece[i])] = 1;
  std::vector<int> u(piece);
  std::sort(u.begin(), u.end(), [&](int a, int b) { return above(pt(a), pt(b)); });
  auto tri = [&](int a, int b, int c) {
    detail::emit_triangle(vertices, ids[static_cast<std::size_t>(a)], ids[static_cast<std::size_t>(b)],
                          ids[static_cast<std::size_t>(c)], out, stats);
  };
  std::vector<int> st{u[0], u[1]};
  for (std::size_t j = 2; j + 1 < m; ++j) {
    const int v = u[j];
    if (left[static_cast<std::size_t>(v)] != left[static_cast<std::size_t>(st.back())]) {
      // v and the stack on opposite chains; st[i] is above st[i + 1].
      for (std::size_t i = 0; i + 1 < st.size(); ++i)
        left[static_cast<std::size_t>(v)] ? tri(v, st[i + 1], st[i]) : tri(v, st[i], st[i + 1]);
      st = {u[j - 1], v};
    } else {
      int last = st.back();
      st.pop_back();
      while (!st.empty()) {
        const int o = left[static_cast<std::size_t>(v)] ? detail::orient_sign(pt(st.back()), pt(last), pt(v))
                                                        : detail::orient_sign(pt(v), pt(last), pt(st.back()));
        if (o <= 0) break;  // not inside (or collinear, or too thin to tell: a zero-area triangle)
        left[static_cast<std::size_t>(v)] ? tri(st.back(), last, v) : tri(v, last, st.back());
        last = st.back();
        st.pop_back();
      }
      st.push_back(last), st.push_back(v);
    }
  }
  for (std::size_t i = 0; i + 1 < st.size(); ++i)  // the stack's lower vertex tells its chain
    left[static_cast<std::size_t>(st[i + 1])] ? tri(u[m - 1], st[i], st[i + 1]) : tri(u[m - 1], st[i + 1], st[i]);
}

}  // namespace

void triangulate_nonconvex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon,
                           std::vector<glm::ivec3>& out, TriangulationStats* stats) {
  if (polygon.size() < 3) return;
  if (stats) ++stats->nonconvex_polygons;
  std::vector<glm::dvec2> P;
  for (int id : polygon) P.push_back(vertices[static_cast<std::size_t>(id)]);
  const std::size_t first = out.size();
  const auto parts = pieces(P, monotone_diagonals(P));
  for (const auto& piece : parts) {
    if (stats) ++stats->monotone_pieces;
    triangulate_monotone(P, piece, polygon, vertices, out, stats);
  }
  detail::remove_degenerate(vertices, out, first, stats);
}

}  // namespace nurbs::tess
