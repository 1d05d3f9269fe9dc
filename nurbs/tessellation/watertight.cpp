#include "nurbs/tessellation/watertight.h"

#include "nurbs/median_tree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <iterator>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "nurbs/tessellation/douglas_peucker.h"
#include "nurbs/tessellation/mesh_topology.h"

namespace nurbs::tess {
namespace {

using Clock = std::chrono::steady_clock;
using Segment = std::array<glm::dvec3, 2>;

/// Segments in 3D on the shared median tree (nurbs/median_tree.h); near() visits every segment
/// within r of a point, with its distance and foot (the closest one alone would be the point's own edge).
class SegmentTree {
 public:
  explicit SegmentTree(std::vector<Segment> segments)
      : segs_(std::move(segments)),
        tree_(
            int(segs_.size()),
            [&](int s, auto add) {
              for (const glm::dvec3& v : segs_[size_t(s)]) add(v);
            },
            [&](int s, int axis) { return segs_[size_t(s)][0][axis] + segs_[size_t(s)][1][axis]; }) {}
  /// Calls visit(segment index, distance, foot parameter t in [0, 1]) for each segment within r of p.
  template <class Visit>
  void near(const glm::dvec3& p, double r, Visit&& visit) const {
    if (tree_.nodes.empty()) return;
    int stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const MedianTree::Node& n = tree_.nodes[size_t(stack[--top])];
      if (glm::length(glm::max(glm::max(n.lo - p, p - n.hi), glm::dvec3(0.0))) > r) continue;
      if (n.left >= 0) {
        stack[top++] = n.left;
        stack[top++] = n.right;
        continue;
      }
      for (int k = n.first; k < n.first + n.count; ++k) {
        const Segment& s = segs_[size_t(tree_.order[size_t(k)])];
        const glm::dvec3 ab = s[1] - s[0];
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0 ? std::clamp(glm::dot(p - s[0], ab) / len2, 0.0, 1.0) : 0.0;
        const double d = glm::length(s[0] + t * ab - p);
        if (d <= r) visit(tree_.order[size_t(k)], d, t);
      }
    }
  }

 private:
  std::vector<Segment> segs_;
  MedianTree tree_;
};

/// Union-find whose root is the smallest member (ids are numbered by face, loop, index).
struct Groups {
  std::vector<int> parent;
  explicit Groups(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

struct Insertion {
  int loop, segment;
  double t;
  int source;  ///< global id of the vertex inserted
  glm::dvec2 uv;
  double s;  ///< parameter of uv's projection on the uv chord
};

/// uv of the point p on face surface s near the chord ua-ub at 3D foot parameter t (watertight.h).
glm::dvec2 insertion_uv(const Surface& surface, const glm::dvec3& p, glm::dvec2 ua, glm::dvec2 ub, double t,
                        double* s) {
  const glm::dvec2 chord = ub - ua, start = ua + t * chord;
  const double len2 = glm::dot(chord, chord);
  *s = t;
  if (!(len2 > 0)) return start;
  const glm::dvec2 q = project_point(surface, p, start, 4);
  const double along = glm::dot(q - ua, chord) / len2;
  const double across = std::abs(chord.x * (q.y - ua.y) - chord.y * (q.x - ua.x)) / len2;  // / chord length^2
  if (!(along > 0.0 && along < 1.0 && across <= 0.25)) return start;  // Newton left the chord: keep the lerp
  *s = along;
  return q;
}

/// An undirected edge of welded ids: min << 32 | max.
uint64_t edge_key(int a, int b) { return uint64_t(uint32_t(std::min(a, b))) << 32 | uint32_t(std::max(a, b)); }

/// An edge of welded ids (edge_key) within one face.
struct FaceEdge {
  int face;
  uint64_t edge;
  bool operator==(const FaceEdge&) const = default;
};
struct FaceEdgeHash {
  size_t operator()(const FaceEdge& k) const {
    return std::hash<uint64_t>()(k.edge * 31u + uint64_t(uint32_t(k.face)));
  }
};

/// A vertex of another part of the mesh lying inside an open edge.
struct Split {
  int edge;  ///< 0..2 within its triangle
  double t;
  int point;  ///< welded vertex id
};

/// A loop's run of consecutive segments along one B-rep edge: vertices first .. first + count.
struct Stretch {
  int face, loop, first, count;
};

/// The loop turned so that vertex 0 starts a run of one edge (nothing to do when the whole loop is
/// one edge, or carries no edges).
void start_at_edge_change(LoopPolyline& loop) {
  const size_t n = loop.uv.size();
  if (loop.edge.size() != n || n < 2) return;
  size_t s = 0;
  while (s < n && loop.edge[s] == loop.edge[(s + n - 1) % n]) ++s;
  if (s == 0 || s == n) return;
  std::rotate(loop.uv.begin(), loop.uv.begin() + long(s), loop.uv.end());
  std::rotate(loop.xyz.begin(), loop.xyz.begin() + long(s), loop.xyz.end());
  std::rotate(loop.edge.begin(), loop.edge.begin() + long(s), loop.edge.end());
}

/// Vertex k of a stretch (the loop closes: vertex n is vertex 0).
const glm::dvec3& stretch_xyz(const LoopPolyline& loop, const Stretch& s, int k) {
  return loop.xyz[size_t(s.first + k) % loop.xyz.size()];
}

/// Cumulative 3D arc length along a stretch's vertices, from 0.
std::vector<double> arc_lengths(const LoopPolyline& loop, const Stretch& s) {
  std::vector<double> arc{0.0};
  for (int k = 1; k <= s.count; ++k)
    arc.push_back(arc.back() + glm::length(stretch_xyz(loop, s, k) - stretch_xyz(loop, s, k - 1)));
  return arc;
}

/// The point at arc-length fraction f of a stretch, with the segment j it lies on and t along it.
glm::dvec3 at_fraction(const LoopPolyline& loop, const Stretch& s, const std::vector<double>& arc, double f, int* j,
                       double* t) {
  const double want = std::clamp(f, 0.0, 1.0) * arc.back();
  int k = int(std::upper_bound(arc.begin(), arc.end(), want) - arc.begin()) - 1;
  k = std::clamp(k, 0, s.count - 1);
  const double len = arc[size_t(k) + 1] - arc[size_t(k)];
  const double u = len > 0.0 ? std::clamp((want - arc[size_t(k)]) / len, 0.0, 1.0) : 0.0;
  if (j) *j = k;
  if (t) *t = u;
  return glm::mix(stretch_xyz(loop, s, k), stretch_xyz(loop, s, k + 1), u);
}

/// The sliver holes of close_t_junctions (watertight.h): returns the triangles added and the
/// largest height of one. `id`: welded ids of the mesh's vertices.
std::pair<int, double> fill_sliver_holes(TriangleMesh& mesh, const std::vector<int>& id, double fill_width) {
  if (!(fill_width > 0.0)) return {0, 0.0};
  std::unordered_map<uint64_t, int> uses;
  for (const glm::ivec3& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++uses[edge_key(id[size_t(t[e])], id[size_t(t[(e + 1) % 3])])];
  struct Open {
    int a, b;    ///< welded ids, in the direction the triangle uses the edge
    int va, vb;  ///< the triangle's own vertices
    int face;
  };
  std::vector<Open> open;
  std::unordered_map<int, std::vector<int>> from;  // welded id -> open edges leaving it
  for (size_t k = 0; k < mesh.triangles.size(); ++k)
    for (int e = 0; e < 3; ++e) {
      const int va = mesh.triangles[k][e], vb = mesh.triangles[k][(e + 1) % 3];
      const int a = id[size_t(va)], b = id[size_t(vb)];
      if (uses[edge_key(a, b)] != 1) continue;
      from[a].push_back(int(open.size()));
      open.push_back({a, b, va, vb, mesh.triangle_face.empty() ? 0 : mesh.triangle_face[k]});
    }
  int filled = 0;
  double widest = 0.0;
  std::vector<bool> closed(open.size(), false);
  for (int i = 0; i < int(open.size()); ++i)
    for (int j : from[open[size_t(i)].b])
      for (int k : from[open[size_t(j)].b]) {
        const Open &x = open[size_t(i)], &y = open[size_t(j)], &z = open[size_t(k)];
        if (z.b != x.a || y.b == x.a || i > j || i > k) continue;  // each hole once, from its first edge
        if (closed[size_t(i)] || closed[size_t(j)] || closed[size_t(k)]) continue;
        const glm::dvec3 pa = mesh.positions[size_t(x.va)], pb = mesh.positions[size_t(y.va)],
                         pc = mesh.positions[size_t(z.va)];
        const double longest = std::max({glm::length(pb - pa), glm::length(pc - pb), glm::length(pa - pc)});
        const double height = longest > 0 ? glm::length(glm::cross(pb - pa, pc - pa)) / longest : 0.0;
        if (height > fill_width) continue;
        // The face holding two of the edges gives all three corners.
        int a, b, c, face;
        if (y.face == z.face)
          face = y.face, a = z.vb, b = y.va, c = y.vb;
        else if (x.face == y.face)
          face = x.face, a = x.va, b = x.vb, c = y.vb;
        else if (x.face == z.face)
          face = x.face, a = x.va, b = x.vb, c = z.va;
        else
          continue;
        mesh.triangles.emplace_back(a, c, b);
        closed[size_t(i)] = closed[size_t(j)] = closed[size_t(k)] = true;
        if (!mesh.triangle_face.empty()) mesh.triangle_face.push_back(face);
        ++filled;
        widest = std::max(widest, height);
      }
  return {filled, widest};
}

}  // namespace

int share_edge_polylines(const std::vector<TrimmedSurface>& faces, std::vector<std::vector<LoopPolyline>>& loops,
                         double tolerance, WatertightStats* stats) {
  if (faces.size() != loops.size()) throw std::invalid_argument("share_edge_polylines: one loop list per face");
  const auto start = Clock::now();
  std::unordered_map<int, std::vector<Stretch>> by_edge;
  for (size_t f = 0; f < loops.size(); ++f)
    for (size_t l = 0; l < loops[f].size(); ++l) {
      LoopPolyline& loop = loops[f][l];
      start_at_edge_change(loop);
      const int n = int(loop.uv.size());
      if (loop.edge.size() != size_t(n) || n < 2) continue;
      for (int i = 0; i < n;) {
        int j = i + 1;
        while (j < n && loop.edge[size_t(j)] == loop.edge[size_t(i)]) ++j;
        if (loop.edge[size_t(i)] >= 0) by_edge[loop.edge[size_t(i)]].push_back({int(f), int(l), i, j - i});
        i = j;
      }
    }
  // Per slave loop, its stretches' new interior vertices (read from the loops as they are).
  struct Replace {
    Stretch stretch;
    std::vector<glm::dvec3> xyz;
    std::vector<glm::dvec2> uv;
    int edge;
  };
  std::vector<Replace> replaced;
  for (auto& [edge, list] : by_edge) {
    if (list.size() != 2) continue;  // an edge of one face (a border), or of more (not a manifold edge)
    const bool first_master = list[0].count >= list[1].count;
    const Stretch& m = list[first_master ? 0 : 1];
    const Stretch& s = list[first_master ? 1 : 0];
    const LoopPolyline& ml = loops[size_t(m.face)][size_t(m.loop)];
    const LoopPolyline& sl = loops[size_t(s.face)][size_t(s.loop)];
    const std::vector<double> ma = arc_lengths(ml, m), sa = arc_lengths(sl, s);
    if (!(ma.back() > 0.0) || !(sa.back() > 0.0)) continue;
    // The two faces' polylines run along the edge the same way or opposite ways: the way whose
    // points a third and two thirds along lie nearer. Each lies within its loop tolerance of its
    // face's edge, and the two edges within both faces' gaps: a pair farther apart is not the same
    // curve (the reader's topology is then not trusted), and is left to the vertex matching.
    const double reach = tolerance + faces[size_t(m.face)].edge_gap + faces[size_t(s.face)].edge_gap;
    auto off = [&](bool reverse) {
      double worst = 0.0;
      for (const double f : {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0})
        worst = std::max(worst, glm::length(at_fraction(sl, s, sa, f, nullptr, nullptr) -
                                            at_fraction(ml, m, ma, reverse ? 1.0 - f : f, nullptr, nullptr)));
      return worst;
    };
    const double forward = off(false), backward = off(true);
    const bool reverse = backward < forward;
    if (!(std::min(forward, backward) <= 2.0 * reach)) continue;
    Replace r{s, {}, {}, edge};
    const Surface& surface = faces[size_t(s.face)].surface;
    bool monotone = true, along_chain = true;
    double taken_f = 0.0;
    double last = -1.0;
    std::vector<glm::dvec2> lerp;
    for (int k = 1; k < m.count; ++k) {
      const int mk = reverse ? m.count - k : k;
      const glm::dvec3 p = stretch_xyz(ml, m, mk);
      const double f = reverse ? 1.0 - ma[size_t(mk)] / ma.back() : ma[size_t(mk)] / ma.back();
      // A master vertex repeated (a segment of no length), or within the tolerance of a stretch end,
      // is not taken: the slave's loop would get a segment of (almost) no length.
      if (!(f > taken_f && f < 1.0)) continue;
      // The corner's own (share_boundary_vertices makes corners one): within the tolerance of a
      // stretch end, or a tenth of the stretch's length on an edge shorter than that (a pin tip's
      // circle below the tolerance keeps its points, both faces alike).
      const double corner = std::min(tolerance, 0.1 * sa.back());
      if (glm::length(p - stretch_xyz(sl, s, 0)) <= corner || glm::length(p - stretch_xyz(sl, s, s.count)) <= corner)
        continue;
      taken_f = f;
      int j = 0;
      double t = 0.0;
      at_fraction(sl, s, sa, f, &j, &t);
      const glm::dvec2 ua = sl.uv[size_t(s.first + j) % sl.uv.size()];
      const glm::dvec2 ub = sl.uv[size_t(s.first + j + 1) % sl.uv.size()];
      // The taken point lies along the slave's own chain (near its segment at that arc fraction):
      // else the two stretches are not one curve run alike (the pair is left as it is).
      double gap = 1e300;
      for (int q = std::max(0, j - 2); q <= std::min(s.count - 1, j + 2); ++q)
        gap = std::min(gap, segment_distance(p, stretch_xyz(sl, s, q), stretch_xyz(sl, s, q + 1)));
      along_chain = along_chain && gap <= reach;
      double along = t;
      r.uv.push_back(insertion_uv(surface, p, ua, ub, t, &along));
      lerp.push_back(glm::mix(ua, ub, t));
      monotone = monotone && j + along > last;
      last = j + along;
      r.xyz.push_back(p);
    }
    if (!monotone) r.uv = lerp;  // Newton's points must keep their order along the chain
    // Each taken point stays within reach of its own face where its uv puts it (the mesh's bound
    // allows a boundary vertex that move, model_mesh.h), else the pair is left as it is.
    bool near = along_chain;
    for (size_t k = 0; k < r.xyz.size() && near; ++k)
      near = glm::length(surface_point(surface, r.uv[k].x, r.uv[k].y) - r.xyz[k]) <= reach;
    if (near) replaced.push_back(std::move(r));
  }
  // Each slave loop rebuilt: its stretches' interiors replaced, the rest kept (stretches in order).
  std::sort(replaced.begin(), replaced.end(), [](const Replace& a, const Replace& b) {
    return std::tie(a.stretch.face, a.stretch.loop, a.stretch.first) <
           std::tie(b.stretch.face, b.stretch.loop, b.stretch.first);
  });
  std::vector<bool> touched(loops.size(), false);
  int shared = 0;
  for (size_t i = 0; i < replaced.size();) {
    const int f = replaced[i].stretch.face, l = replaced[i].stretch.loop;
    LoopPolyline& loop = loops[size_t(f)][size_t(l)];
    const int n = int(loop.uv.size());
    LoopPolyline out;
    out.outer = loop.outer;
    int v = 0;
    for (; i < replaced.size() && replaced[i].stretch.face == f && replaced[i].stretch.loop == l; ++i) {
      const Replace& r = replaced[i];
      for (; v <= r.stretch.first; ++v) {  // up to and with the stretch's first vertex
        out.uv.push_back(loop.uv[size_t(v)]), out.xyz.push_back(loop.xyz[size_t(v)]);
        out.edge.push_back(loop.edge[size_t(v)]);
      }
      for (size_t k = 0; k < r.xyz.size(); ++k)
        out.uv.push_back(r.uv[k]), out.xyz.push_back(r.xyz[k]), out.edge.push_back(r.edge);
      v = r.stretch.first + r.stretch.count;  // the stretch's last vertex starts the next run
      shared += int(r.xyz.size());
    }
    for (; v < n; ++v) {
      out.uv.push_back(loop.uv[size_t(v)]), out.xyz.push_back(loop.xyz[size_t(v)]);
      out.edge.push_back(loop.edge[size_t(v)]);
    }
    loop = std::move(out);
    touched[size_t(f)] = true;
  }
  if (stats) {
    stats->edge_shared += shared;
    stats->faces_touched += int(std::count(touched.begin(), touched.end(), true));
    stats->seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }
  return shared;
}

int share_boundary_vertices(const std::vector<TrimmedSurface>& faces, std::vector<std::vector<LoopPolyline>>& loops,
                            double tolerance, WatertightStats* stats) {
  if (faces.size() != loops.size()) throw std::invalid_argument("share_boundary_vertices: one loop list per face");
  const auto start = Clock::now();
  // Global vertex ids in (face, loop, index) order, and the segments longer than the tolerance.
  std::vector<std::vector<int>> base(loops.size());
  std::vector<std::array<int, 3>> ref;  // global id -> (face, loop, index)
  std::vector<Segment> segments;
  std::vector<int> segment_vertex;  // segment -> global id of its first vertex
  std::vector<int> edge_of;         // global id -> B-rep edge of the segment after it (-1 unknown)
  for (size_t f = 0; f < loops.size(); ++f)
    for (size_t l = 0; l < loops[f].size(); ++l) {
      base[f].push_back(int(ref.size()));
      const LoopPolyline& loop = loops[f][l];
      const auto& xyz = loop.xyz;
      for (size_t i = 0; i < xyz.size(); ++i) {
        const glm::dvec3 a = xyz[i], b = xyz[(i + 1) % xyz.size()];
        // Without the file's edges, a segment shorter than the tolerance is skipped (a degenerate
        // edge at a pole); with them only a degenerate one is (a fillet's arc narrower than the
        // tolerance is still an edge its neighbours share).
        const bool known = loop.edge.size() == xyz.size() && loop.edge[i] >= 0;
        if (glm::length(b - a) > (known ? 1e-6 : 1.0) * tolerance)
          segments.push_back({a, b}), segment_vertex.push_back(int(ref.size()));
        ref.push_back({int(f), int(l), int(i)});
        edge_of.push_back(loop.edge.size() == xyz.size() ? loop.edge[i] : -1);
      }
    }
  const SegmentTree tree(segments);
  auto next_id = [&](int id) {  // the vertex after `id` in its loop
    const auto [f, l, i] = ref[size_t(id)];
    return base[size_t(f)][size_t(l)] + (i + 1) % int(loops[size_t(f)][size_t(l)].xyz.size());
  };
  auto xyz_of = [&](int id) -> glm::dvec3& {
    const auto [f, l, i] = ref[size_t(id)];
    return loops[size_t(f)][size_t(l)].xyz[size_t(i)];
  };

  std::vector<glm::dvec2> period;  // domain size: a seam joins points this far apart in uv
  for (const TrimmedSurface& face : faces)
    period.emplace_back(surface_domain_u(face.surface).max - surface_domain_u(face.surface).min,
                        surface_domain_v(face.surface).max - surface_domain_v(face.surface).min);
  // Matches against the loops as given: the nearest segment of every other face.
  Groups groups(ref.size());
  std::vector<std::vector<Insertion>> insertions(loops.size());
  struct Best {
    int face, segment;
    double d, t, within;  ///< within: the distance to which the two faces' vertices are one point
    glm::dvec2 foot;      ///< on the face's (u, v): the two sides of its seam are two matches
  };
  // Across a B-rep edge whose faces' file edges lie off their surfaces (TrimmedSurface::edge_gap),
  // the two loops lie up to both gaps apart: vertices of the same edge match that far.
  const double largest_gap = largest_edge_gap(faces);
  std::vector<Best> best;
  for (int v = 0; v < int(ref.size()); ++v) {
    const glm::dvec3 p = xyz_of(v);
    const auto [f, lf, vf] = ref[size_t(v)];
    const glm::dvec2 uv = loops[size_t(f)][size_t(lf)].uv[size_t(vf)];
    // The B-rep edges of the vertex's two segments: with the file's topology, a vertex goes only onto
    // segments of those edges (a sliver face's two sides may lie within the tolerance of each other).
    // One known edge is enough: the other, a curve the reader added to close a gap, ends at the
    // known edge's end, a corner of that edge's faces, not a point of any other edge.
    const int size = int(loops[size_t(f)][size_t(lf)].uv.size());
    const int out_edge = edge_of[size_t(v)], in_edge = edge_of[size_t(v - vf + (vf + size - 1) % size)];
    best.clear();
    tree.near(p, tolerance + 2.0 * largest_gap, [&](int s, double d, double t) {
      const int e = edge_of[size_t(segment_vertex[size_t(s)])];
      if (e >= 0 && (in_edge >= 0 || out_edge >= 0) && e != in_edge && e != out_edge) return;
      const auto [g, l, i] = ref[size_t(segment_vertex[size_t(s)])];
      const bool same_edge = e >= 0 && (e == in_edge || e == out_edge);
      const double within =
          tolerance + (same_edge ? faces[size_t(f)].edge_gap + faces[size_t(g)].edge_gap : 0.0);
      if (d > within) return;
      const LoopPolyline& loop = loops[size_t(g)][size_t(l)];
      const glm::dvec2 foot = glm::mix(loop.uv[size_t(i)], loop.uv[(size_t(i) + 1) % loop.uv.size()], t);
      const auto across_seam = [&](glm::dvec2 a, glm::dvec2 b) {
        return std::abs(a.x - b.x) > 0.5 * period[size_t(g)].x || std::abs(a.y - b.y) > 0.5 * period[size_t(g)].y;
      };
      // The same face: only across its seam, never its own neighbouring edges.
      if (g == f && !across_seam(foot, uv)) return;
      // The nearest segment of each face, on each side of its seam (feet a whole domain apart along
      // one parameter at the same other one: both sides take the vertex; a sliver's two sides, also
      // far apart in (u, v), are not a domain apart at one parameter, and keep one match).
      const glm::dvec2 domain = period[size_t(g)];
      const auto seam_sides = [&](glm::dvec2 a, glm::dvec2 b) {
        const glm::dvec2 gap = glm::abs(a - b);
        return (gap.x >= (1 - 1e-3) * domain.x && gap.y <= 1e-3 * domain.y) ||
               (gap.y >= (1 - 1e-3) * domain.y && gap.x <= 1e-3 * domain.x);
      };
      auto it = std::find_if(best.begin(), best.end(),
                             [&](const Best& b) { return b.face == g && !seam_sides(b.foot, foot); });
      if (it == best.end())
        best.push_back({g, s, d, t, within, foot});
      else if (d < it->d)
        *it = {g, s, d, t, within, foot};
    });
    for (const Best& b : best) {
      const int a = segment_vertex[size_t(b.segment)], c = next_id(a);
      const double da = glm::length(p - xyz_of(a)), dc = glm::length(p - xyz_of(c));
      if (std::min(da, dc) <= b.within) {
        groups.unite(v, da <= dc ? a : c);
        continue;
      }
      const auto [g, l, i] = ref[size_t(a)];
      const LoopPolyline& loop = loops[size_t(g)][size_t(l)];
      Insertion ins{l, i, b.t, v, {}, 0.0};
      ins.uv = insertion_uv(faces[size_t(g)].surface, p, loop.uv[size_t(i)], loop.uv[(size_t(i) + 1) % loop.uv.size()],
                            b.t, &ins.s);
      insertions[size_t(g)].push_back(ins);
    }
  }

  // Merged groups take the xyz of their first member.
  int merged = 0, inserted = 0;
  std::vector<bool> touched(loops.size(), false);
  for (int v = 0; v < int(ref.size()); ++v) {
    const int r = groups.find(v);
    if (r == v) continue;
    ++merged;
    xyz_of(v) = xyz_of(r);
    touched[size_t(ref[size_t(v)][0])] = true;
    touched[size_t(ref[size_t(r)][0])] = true;
  }

  // Insertions, per loop, sorted along each segment by t (points read from a copy: loops change).
  std::vector<glm::dvec3> point(ref.size());
  for (int v = 0; v < int(ref.size()); ++v) point[size_t(v)] = xyz_of(v);
  for (size_t g = 0; g < loops.size(); ++g) {
    auto& list = insertions[g];
    if (list.empty()) continue;
    std::sort(list.begin(), list.end(), [](const Insertion& x, const Insertion& y) {
      return std::tie(x.loop, x.segment, x.t, x.source) < std::tie(y.loop, y.segment, y.t, y.source);
    });
    for (size_t l = 0; l < loops[g].size(); ++l) {
      LoopPolyline& loop = loops[g][l];
      const int n = int(loop.uv.size());
      LoopPolyline out;
      out.outer = loop.outer;
      const bool edges = loop.edge.size() == size_t(n);
      auto it =
          std::lower_bound(list.begin(), list.end(), int(l), [](const Insertion& x, int k) { return x.loop < k; });
      for (int i = 0; i < n; ++i) {
        out.uv.push_back(loop.uv[size_t(i)]);
        out.xyz.push_back(loop.xyz[size_t(i)]);
        if (edges) out.edge.push_back(loop.edge[size_t(i)]);
        const int a = groups.find(base[g][l] + i), c = groups.find(base[g][l] + (i + 1) % n);
        auto end = it;
        while (end != list.end() && end->loop == int(l) && end->segment == i) ++end;
        // Newton's uv must keep the order of t along the chord, else all of them take the lerp.
        bool monotone = true;
        for (auto k = it; k != end; ++k) monotone = monotone && (k == it || std::prev(k)->s < k->s);
        std::vector<int> roots;
        for (; it != end; ++it) {
          const int r = groups.find(it->source);
          if (r == a || r == c || std::find(roots.begin(), roots.end(), r) != roots.end()) continue;
          roots.push_back(r);
          const glm::dvec2 ua = loop.uv[size_t(i)], ub = loop.uv[size_t((i + 1) % n)];
          out.uv.push_back(monotone ? it->uv : ua + it->t * (ub - ua));
          out.xyz.push_back(point[size_t(r)]);
          if (edges) out.edge.push_back(loop.edge[size_t(i)]);
          ++inserted;
          touched[g] = true;
        }
      }
      loop = std::move(out);
    }
  }
  if (stats) {
    stats->inserted += inserted;
    stats->merged += merged;
    stats->faces_touched += int(std::count(touched.begin(), touched.end(), true));
    stats->seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }
  return inserted + merged;
}

int close_t_junctions(TriangleMesh& mesh, double weld_tolerance, WatertightStats* stats, double fill_width) {
  const auto start = Clock::now();
  std::vector<int> id = weld_vertices(mesh.positions, weld_tolerance);
  // Triangles with two corners welded together cover nothing, and their two remaining edges are
  // the same edge: counted twice, it would look closed and hide a junction on it. Removed.
  size_t kept = 0;
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    const glm::ivec3 t = mesh.triangles[k];
    const int a = id[size_t(t.x)], b = id[size_t(t.y)], c = id[size_t(t.z)];
    if (a == b || b == c || c == a) continue;
    mesh.triangles[kept] = t;
    if (!mesh.triangle_face.empty()) mesh.triangle_face[kept] = mesh.triangle_face[k];
    ++kept;
  }
  const int collapsed = int(mesh.triangles.size() - kept);
  mesh.triangles.resize(kept);
  if (!mesh.triangle_face.empty()) mesh.triangle_face.resize(kept);
  int splits = 0;
  // New vertices are copies of welded points, so one pass finds every junction; the second pass
  // only confirms (and catches a point that lay on an edge's two sides, split in the first pass).
  for (int pass = 0; pass < 2; ++pass) {
    std::unordered_map<uint64_t, int> uses;
    for (const glm::ivec3& t : mesh.triangles)
      for (int e = 0; e < 3; ++e) {
        const int a = id[size_t(t[e])], b = id[size_t(t[(e + 1) % 3])];
        if (a != b) ++uses[edge_key(a, b)];
      }
    // Uses per face: an edge on its face's boundary may be used by more faces than two where
    // bodies touch (a face of each body along one line), and a junction on it is closed all the same.
    std::unordered_map<FaceEdge, int, FaceEdgeHash> face_uses;
    auto face_of = [&](int k) { return mesh.triangle_face.empty() ? 0 : mesh.triangle_face[size_t(k)]; };
    for (int k = 0; k < int(mesh.triangles.size()); ++k)
      for (int e = 0; e < 3; ++e) {
        const int a = id[size_t(mesh.triangles[size_t(k)][e])], b = id[size_t(mesh.triangles[size_t(k)][(e + 1) % 3])];
        if (a != b) ++face_uses[{face_of(k), edge_key(a, b)}];
      }
    std::vector<Segment> open;                 // the faces' boundary edges
    std::vector<std::array<int, 2>> open_ref;  // (triangle, edge)
    std::vector<int> points;                   // welded ids on open edges
    for (int k = 0; k < int(mesh.triangles.size()); ++k)
      for (int e = 0; e < 3; ++e) {
        const int a = id[size_t(mesh.triangles[size_t(k)][e])], b = id[size_t(mesh.triangles[size_t(k)][(e + 1) % 3])];
        if (a == b || face_uses[{face_of(k), edge_key(a, b)}] != 1) continue;
        open.push_back({mesh.positions[size_t(a)], mesh.positions[size_t(b)]});
        open_ref.push_back({k, e});
        if (uses[edge_key(a, b)] == 1) points.push_back(a), points.push_back(b);
      }
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    const SegmentTree tree(open);
    std::unordered_map<int, std::vector<Split>> found;  // triangle -> its splits
    for (int w : points) {
      const glm::dvec3 p = mesh.positions[size_t(w)];
      tree.near(p, weld_tolerance, [&](int s, double, double t) {
        const auto [k, e] = open_ref[size_t(s)];
        const glm::ivec3 tri = mesh.triangles[size_t(k)];
        if (w == id[size_t(tri[0])] || w == id[size_t(tri[1])] || w == id[size_t(tri[2])]) return;
        if (glm::length(p - open[size_t(s)][0]) <= weld_tolerance ||
            glm::length(p - open[size_t(s)][1]) <= weld_tolerance)
          return;
        found[k].push_back({e, t, w});
      });
    }
    if (found.empty()) break;
    std::vector<int> order;  // deterministic: triangles in index order
    for (const auto& [k, list] : found) order.push_back(k);
    std::sort(order.begin(), order.end());
    for (int k : order) {
      std::vector<Split>& list = found[k];
      std::sort(list.begin(), list.end(), [](const Split& x, const Split& y) {
        return std::tie(x.edge, x.t, x.point) < std::tie(y.edge, y.t, y.point);
      });
      const glm::ivec3 original = mesh.triangles[size_t(k)];
      std::vector<glm::ivec3> pieces{original};
      for (size_t first = 0; first < list.size();) {
        size_t last = first;
        while (last < list.size() && list[last].edge == list[first].edge) ++last;
        const int a = original[list[first].edge], b = original[(list[first].edge + 1) % 3];
        // The piece that still holds the directed edge a -> b; fan it from its third corner.
        size_t j = 0;
        int le = 0;
        for (; j < pieces.size(); ++j) {
          for (le = 0; le < 3 && !(pieces[j][le] == a && pieces[j][(le + 1) % 3] == b); ++le) {
          }
          if (le < 3) break;
        }
        if (j == pieces.size()) {  // cannot happen: fans keep the triangle's other directed edges
          first = last;
          continue;
        }
        const int c = pieces[j][(le + 2) % 3];
        std::vector<int> chain{a};
        for (size_t m = first; m < last; ++m) {
          const double t = list[m].t;
          const int v = int(mesh.positions.size());
          mesh.positions.push_back(mesh.positions[size_t(list[m].point)]);
          if (!mesh.uv.empty()) mesh.uv.push_back(glm::mix(mesh.uv[size_t(a)], mesh.uv[size_t(b)], t));
          if (!mesh.normals.empty()) {
            const glm::dvec3 n = glm::mix(mesh.normals[size_t(a)], mesh.normals[size_t(b)], t);
            mesh.normals.push_back(glm::length(n) > 0 ? glm::normalize(n) : mesh.normals[size_t(a)]);
          }
          if (!mesh.vertex_face.empty()) mesh.vertex_face.push_back(mesh.vertex_face[size_t(a)]);
          if (!mesh.colors.empty()) mesh.colors.push_back(glm::mix(mesh.colors[size_t(a)], mesh.colors[size_t(b)], t));
          id.push_back(list[m].point);
          chain.push_back(v);
        }
        chain.push_back(b);
        pieces[j] = glm::ivec3(chain[0], chain[1], c);
        for (size_t m = 1; m + 1 < chain.size(); ++m) pieces.emplace_back(chain[m], chain[m + 1], c);
        splits += int(last - first);
        first = last;
      }
      mesh.triangles[size_t(k)] = pieces[0];
      for (size_t j = 1; j < pieces.size(); ++j) {
        mesh.triangles.push_back(pieces[j]);
        if (!mesh.triangle_face.empty()) mesh.triangle_face.push_back(mesh.triangle_face[size_t(k)]);
      }
    }
  }
  const auto [filled, widest] = fill_sliver_holes(mesh, id, fill_width);
  if (stats) {
    stats->splits += splits;
    stats->collapsed += collapsed;
    stats->filled += filled;
    stats->fill_width = std::max(stats->fill_width, widest);
    stats->seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }
  return splits;
}

}  // namespace nurbs::tess
