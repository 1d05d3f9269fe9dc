#include "nurbs/tessellation/tessellate.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/stopwatch.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/coherent_eval.h"
#include "nurbs/tessellation/half_edge_trim.h"
#include "nurbs/tessellation/rectangle_face.h"
#include "nurbs/tessellation/surface_cells.h"
#include "nurbs/tessellation/triangulate.h"
#include "nurbs/tessellation/watertight.h"
#include "nurbs/trim_loops.h"

namespace nurbs::tess {
namespace {

using Clock = std::chrono::steady_clock;
/// One face's mesh and figures, merged in face order afterwards.
struct FaceOut {
  FaceMesh mesh;
  TessellateStats stats;
  std::string failure;
};

TrimApproxOptions trim_options(const TessellateOptions& o) {
  TrimApproxOptions to;
  to.eps = o.mode == TessMode::Guaranteed ? o.loop_share * o.eps : o.eps;
  to.gamma = o.gamma;
  to.split = o.split;
  to.simplify = o.simplify;
  if (!o.thin_polylines) to.thinning = 0.0;
  to.edges = o.watertight;
  return to;
}

/// Positions of the boundary vertices on the loops' 3D polylines: a loop vertex keeps its xyz (the
/// same double values the neighbouring face holds after share_boundary_vertices), a point the
/// trimming inserted where a cell edge crosses a loop segment goes onto that segment's 3D chord, so
/// both faces' boundaries are the same polyline in space.
void boundary_positions(const std::vector<LoopPolyline>& loops, const FaceMesh& m, std::vector<glm::dvec3>& position) {
  for (size_t v = 0; v < m.uv.size(); ++v) {
    if (!m.trim_vertex[v]) continue;
    double best = 1e300;
    glm::dvec3 at = position[v];
    for (const LoopPolyline& l : loops)
      for (size_t i = 0; i < l.uv.size(); ++i) {
        const size_t j = (i + 1) % l.uv.size();
        const glm::dvec2 a = l.uv[i], ab = l.uv[j] - a;
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0 ? std::clamp(glm::dot(m.uv[v] - a, ab) / len2, 0.0, 1.0) : 0.0;
        const double d = glm::length(a + t * ab - m.uv[v]);
        if (d >= best) continue;
        best = d;
        at = t == 0.0 ? l.xyz[i] : t == 1.0 ? l.xyz[j] : glm::mix(l.xyz[i], l.xyz[j], t);
      }
    position[v] = at;
  }
}

/// §5's cell options of a face at `eps`: over the bounding box of its loops, clipped to the domain;
/// nullopt when the loops enclose no area there.
std::optional<CellOptions> cell_options(const TrimmedSurface& face, const std::vector<LoopPolyline>& loops,
                                        const TessellateOptions& o, double eps) {
  const bool guaranteed = o.mode == TessMode::Guaranteed;
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const LoopPolyline& l : loops)
    for (const glm::dvec2& p : l.uv) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const Interval du = surface_domain_u(face.surface), dv = surface_domain_v(face.surface);
  lo = glm::max(lo, glm::dvec2(du.min, dv.min));
  hi = glm::min(hi, glm::dvec2(du.max, dv.max));
  if (!(lo.x < hi.x && lo.y < hi.y)) return std::nullopt;
  CellOptions co;
  co.eps_surface = guaranteed ? (1.0 - o.loop_share) * eps : eps;
  co.error = guaranteed ? SurfaceError::Conservative : SurfaceError::Approximate;
  co.subdivision = o.subdivision;
  co.bound = o.cell_bound;
  co.domain_u = Interval{lo.x, hi.x};
  co.domain_v = Interval{lo.y, hi.y};
  co.bilinear_factor = guaranteed ? 2.0 : 1.0;
  return co;
}

double length2(const glm::dvec3& v) { return glm::dot(v, v); }

/// Watertight: a hole of three open edges this narrow, relative to eps, is a sliver the trimming
/// lost; close_t_junctions closes it (watertight.h) and the mesh's bound grows by its width.
constexpr double kSliverHole = 1e-3;

/// A triangle this flat in space is a sliver: its height under its longest edge, over that edge.
constexpr double kSliver = 1e-10;

double flatness(const std::vector<glm::dvec3>& p, const glm::ivec3& t) {
  const glm::dvec3 a = p[size_t(t.x)], b = p[size_t(t.y)], c = p[size_t(t.z)];
  const double longest = std::max({length2(b - a), length2(c - b), length2(a - c)});
  return longest > 0.0 ? glm::length(glm::cross(b - a, c - a)) / longest : 0.0;
}

/// Flips each sliver (three corners on a line in space, though not in (u, v): a planar face's
/// nearly collinear trim points) with the face's triangle across its longest edge, when the two new
/// triangles are proper and face the way the neighbour did: the corner opposite the long edge lies
/// on it, so they split the neighbour there. A sliver whose longest edge is the face's boundary is
/// dropped: the boundary then runs through its third corner, which lies on that edge (a watertight
/// mesh closes the junction this leaves with the next face). Returns the slivers flipped or dropped.
int flip_slivers(const std::vector<glm::dvec3>& p, std::vector<glm::ivec3>& tris) {
  std::unordered_map<uint64_t, size_t> by_edge;  // directed edge (a, b) -> triangle
  auto key = [](int a, int b) { return uint64_t(uint32_t(a)) << 32 | uint32_t(b); };
  for (size_t k = 0; k < tris.size(); ++k)
    for (int e = 0; e < 3; ++e) by_edge[key(tris[k][e], tris[k][(e + 1) % 3])] = k;
  int flipped = 0;
  for (size_t k = 0; k < tris.size(); ++k) {
    if (flatness(p, tris[k]) > kSliver) continue;
    const glm::ivec3 t = tris[k];
    int e = 0;  // the longest edge t[e] -> t[e + 1]
    double best = -1.0;
    for (int i = 0; i < 3; ++i) {
      const double l = length2(p[size_t(t[(i + 1) % 3])] - p[size_t(t[i])]);
      if (l > best) best = l, e = i;
    }
    const int a = t[e], b = t[(e + 1) % 3], c = t[(e + 2) % 3];
    const auto it = by_edge.find(key(b, a));
    if (it == by_edge.end()) {
      for (int i = 0; i < 3; ++i) by_edge.erase(key(t[i], t[(i + 1) % 3]));
      tris[k] = glm::ivec3(-1);
      ++flipped;
      continue;
    }
    if (it->second == k) continue;
    const glm::ivec3 n = tris[it->second];
    int d = -1;
    for (int i = 0; i < 3; ++i)
      if (n[i] != a && n[i] != b) d = n[i];
    if (d < 0 || d == c) continue;
    const glm::ivec3 x(c, a, d), y(c, d, b);
    const glm::dvec3 was = glm::cross(p[size_t(a)] - p[size_t(b)], p[size_t(d)] - p[size_t(b)]);
    auto facing = [&](const glm::ivec3& q) {
      return glm::dot(glm::cross(p[size_t(q.y)] - p[size_t(q.x)], p[size_t(q.z)] - p[size_t(q.x)]), was) > 0.0;
    };
    if (flatness(p, x) <= kSliver || flatness(p, y) <= kSliver || !facing(x) || !facing(y)) continue;
    const size_t m = it->second;
    for (const size_t q : {k, m})
      for (int i = 0; i < 3; ++i) by_edge.erase(key(tris[q][i], tris[q][(i + 1) % 3]));
    tris[k] = x, tris[m] = y;
    for (const size_t q : {k, m})
      for (int i = 0; i < 3; ++i) by_edge[key(tris[q][i], tris[q][(i + 1) % 3])] = q;
    ++flipped;
  }
  std::erase(tris, glm::ivec3(-1));
  return flipped;
}

FaceOut tessellate_face(const TrimmedSurface& face, const std::vector<LoopPolyline>& loops,
                        const TessellateOptions& o) {
  FaceOut out;
  const bool guaranteed = o.mode == TessMode::Guaranteed;
  for (const LoopPolyline& l : loops) out.stats.trim_edges += (long long)l.uv.size();

  // §5 cells over the bounding box of the loops (clipped to the domain by subdivide_surface).
  auto t = Clock::now();
  // A face whose loops all retrace themselves bounds no area (a degenerate face OpenCASCADE holds
  // valid): no triangles, and nothing missing.
  if (!loops.empty() &&
      std::all_of(loops.begin(), loops.end(), [](const LoopPolyline& l) { return encloses_nothing(l.uv); }))
    return out;
  const std::optional<CellOptions> co = cell_options(face, loops, o, o.eps);
  if (!co) {
    out.failure = "its trim loops enclose no area inside the surface's parameter domain";
    return out;
  }
  CellStats cs;
  CellOptions face_co = *co;
  face_co.max_nodes = o.max_face_nodes;
  const std::vector<Cell> cells = subdivide_surface(face.surface, face_co, &cs);
  out.stats.cells = cs.leaves;
  out.stats.cell_nodes = cs.nodes;
  out.stats.unconverged_cells = cs.unconverged;
  out.stats.seconds_surface = nurbs::seconds_since(t);
  if (guaranteed && cs.unconverged > 0)  // the mesh is still made, but not within eps
    out.failure = fmt::format(
        "the surface subdivision stopped at its limit ({} nodes, depth {}) with {} cells "
        "above eps; a larger eps",
        cs.nodes, cs.max_depth, cs.unconverged);

  // §6 trimming, §7 triangulation.
  t = Clock::now();
  const TrimmedPolygons polys = trim_cells(cells, loops);
  out.stats.seconds_trimming = nurbs::seconds_since(t);
  t = Clock::now();
  TriangulationStats ts;
  std::vector<glm::ivec3> tris = triangulate_polygons(polys, &ts);
  out.stats.degenerate_triangles = ts.degenerate_triangles;
  out.stats.seconds_triangulation = nurbs::seconds_since(t);
  if (tris.empty()) {
    out.failure = "trimming left no material polygon";
    return out;
  }

  // §8 evaluation of the vertices the triangles use, in the order of the polygons' vertices.
  t = Clock::now();
  std::vector<int> remap(polys.vertices.size(), -1);
  FaceMesh& m = out.mesh;
  for (glm::ivec3& tri : tris)
    for (int c = 0; c < 3; ++c) {
      int& r = remap[size_t(tri[c])];
      if (r < 0) {
        r = int(m.uv.size());
        m.uv.push_back(polys.vertices[size_t(tri[c])]);
        m.trim_vertex.push_back(polys.on_trim[size_t(tri[c])]);
      }
      tri[c] = r;
    }
  if (o.coherent_evaluation)
    evaluate_coherent(face.surface, m.uv, m.position, m.normal);
  else
    evaluate_direct(face.surface, m.uv, m.position, m.normal);
  if (o.watertight) boundary_positions(loops, m, m.position);
  // Triangles that collapse in space (two corners on a pole or a degenerate edge of the surface,
  // two trim vertices a rounding apart: within 1e-9 of this face's control box) cover nothing; they
  // are dropped and counted. Not within the file's resolution (TessellateOptions::weld): a cell
  // narrower than that (cells of a tube halved towards a knot line, 0.004 wide under a resolution of
  // 0.01) still covers a strip, and dropping its triangles would leave a slot in the mesh. Slivers
  // are flipped (flip_slivers).
  const double weld = 1e-9 * control_box(face.surface).diagonal();
  const size_t before = tris.size();
  std::erase_if(tris, [&](const glm::ivec3& t) {
    const glm::dvec3 a = m.position[size_t(t.x)], b = m.position[size_t(t.y)], c = m.position[size_t(t.z)];
    const double shortest = std::min({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const double scale = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    return shortest <= weld || glm::length(glm::cross(b - a, c - a)) <= 1e-12 * scale * scale;
  });
  out.stats.collapsed_triangles = (long long)(before - tris.size());
  out.stats.flipped_slivers = flip_slivers(m.position, tris);
  if (face.reversed) {
    for (glm::ivec3& tri : tris) std::swap(tri.y, tri.z);
    for (glm::dvec3& n : m.normal) n = -n;
  }
  m.triangles = std::move(tris);
  out.stats.seconds_evaluation = nurbs::seconds_since(t);
  out.stats.triangles = (long long)m.triangles.size();
  out.stats.vertices = (long long)m.uv.size();
  return out;
}

}  // namespace

TessellateResult tessellate(const std::vector<TrimmedSurface>& faces, const TessellateOptions& options,
                            const std::function<void(int, int)>& progress) {
  const auto start = Clock::now();
  std::vector<FaceOut> outs(faces.size());
  std::vector<std::vector<LoopPolyline>> loops(faces.size());
  std::vector<TrimApproxStats> trim_stats(faces.size());
  const TrimApproxOptions to = trim_options(options);
  // Runs body(f) for every face on the worker threads; a face that throws records its failure.
  auto for_faces = [&](const std::function<void(size_t)>& body) {
    parallel_for(faces.size(), options.threads, [&](size_t f, int) {
      if (!outs[f].failure.empty()) return;
      try {
        body(f);
      } catch (const std::exception& e) {
        outs[f] = FaceOut{};
        outs[f].failure = e.what();
      }
    });
  };
  // §4-§5: every face's loops first (the watertight step matches them across faces), then the rest.
  for_faces([&](size_t f) {
    TrimApproxOptions face_to = to;
    if (options.rectangle_faces && !options.watertight)
      if (const auto r = boundary_rectangle(faces[f]))
        face_to.outer_polyline = rectangle_polyline(faces[f].surface, *r);
    loops[f] = approximate_trim_loops(faces[f], face_to, &trim_stats[f]);
  });
  if (options.max_cells > 0) {
    // The work eps asks for, before it starts: each face's cells at 1024, 256 and 64 times eps (2 %
    // of the work) fit cells(eps) = F + A eps^-e, F the floor its knot spans impose and e in
    // [1/2, 1] (singly to doubly curved). Where the passes rise slower than e = 1/2 they are not yet
    // on the power law (the generated sphere: 16, 64 and 128 cells, then 6976 at eps), and e = 1,
    // the steepest, is taken.
    // Returns the estimate at eps and, from the same fit, the least eps whose estimate fits.
    auto estimate_at = [&](double eps) {
      const double scales[3] = {1024.0, 256.0, 64.0};
      std::vector<std::array<long long, 3>> counts(faces.size(), {0, 0, 0});
      for_faces([&](size_t f) {
        for (int k = 0; k < 3; ++k)
          if (auto co = cell_options(faces[f], loops[f], options, scales[k] * eps)) {
            co->max_nodes = int(std::min<long long>(2 * options.max_cells, 1LL << 22));
            CellStats cs;
            (void)subdivide_surface(faces[f].surface, *co, &cs);
            counts[f][size_t(k)] = cs.leaves;
          }
      });
      auto total = [&](double s) {  // the cells at eps x s (s in [1, 64])
        double sum = 0.0;
        for (const auto& [c1024, c256, c64] : counts) {
          const double rise = double(c64 - c256), before = double(c256 - c1024);
          const double measured = rise > 0.0 && before > 0.0 ? std::log(rise / before) / std::log(4.0) : 1.0;
          const double e = measured < 0.5 ? 1.0 : std::min(measured, 1.0);
          const double at64 = std::pow(64.0, -e), step = at64 * (1.0 - std::pow(4.0, -e));  // A at64 (1 - 4^-e) = rise
          const double a = rise > 0.0 ? rise / step : 0.0, floor = double(c64) - a * at64;
          sum += std::max(double(c64), floor + a * std::pow(s, -e));
        }
        return sum;
      };
      double lo = 1.0, hi = 64.0;
      for (int i = 0; i < 40; ++i) {
        const double mid = std::sqrt(lo * hi);
        (total(mid) > double(options.max_cells) ? lo : hi) = mid;
      }
      return std::pair{total(1.0), hi * eps};
    };
    const auto [estimate, least] = estimate_at(options.eps);
    if (estimate > double(options.max_cells)) {
      // The fit's least eps, checked by the same estimate there (its passes are coarser) and raised
      // until it fits: the eps named is one that the next run accepts.
      double fits = least;
      for (int i = 0; i < 12; ++i) {
        const auto [again, further] = estimate_at(fits);
        if (again <= double(options.max_cells)) break;
        fits = std::max(further, 1.25 * fits);
      }
      throw WorkLimitError(fmt::format("eps {:g} asks for about {:.3g} surface cells (from the cells at 64, 256 and "
                                       "1024 times eps), above the limit of {}; eps {:.2g} or more fits",
                                       options.eps, estimate, options.max_cells, fits),
                           (long long)estimate, fits);
    }
  }
  WatertightStats ws;
  if (options.watertight) {
    share_edge_polylines(faces, loops, to.eps, &ws);
    share_boundary_vertices(faces, loops, to.eps, &ws);
  }
  std::atomic<int> done{0};
  std::mutex report;
  for_faces([&](size_t f) {
    outs[f] = tessellate_face(faces[f], loops[f], options);
    outs[f].stats.trim = trim_stats[f];
    const int d = ++done;
    if (progress) {
      const std::lock_guard lock(report);
      progress(d, int(faces.size()));
    }
  });

  TessellateResult r;
  TriangleMesh& mesh = r.mesh;
  TessellateStats& s = r.stats;
  s.faces = int(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    FaceOut& o = outs[f];
    if (!o.failure.empty()) r.failures.push_back({int(f), o.failure});
    add(s.trim, o.stats.trim);
    s.cells += o.stats.cells;
    s.cell_nodes += o.stats.cell_nodes;
    s.unconverged_cells += o.stats.unconverged_cells;
    s.trim_edges += o.stats.trim_edges;
    s.degenerate_triangles += o.stats.degenerate_triangles;
    s.collapsed_triangles += o.stats.collapsed_triangles;
    s.flipped_slivers += o.stats.flipped_slivers;
    s.seconds_surface += o.stats.seconds_surface;
    s.seconds_trimming += o.stats.seconds_trimming;
    s.seconds_triangulation += o.stats.seconds_triangulation;
    s.seconds_evaluation += o.stats.seconds_evaluation;
    const int base = int(mesh.positions.size());
    const FaceMesh& m = o.mesh;
    mesh.positions.insert(mesh.positions.end(), m.position.begin(), m.position.end());
    mesh.normals.insert(mesh.normals.end(), m.normal.begin(), m.normal.end());
    mesh.uv.insert(mesh.uv.end(), m.uv.begin(), m.uv.end());
    mesh.vertex_face.insert(mesh.vertex_face.end(), m.uv.size(), int(f));
    for (const glm::ivec3& t : m.triangles) mesh.triangles.push_back(t + glm::ivec3(base));
    mesh.triangle_face.insert(mesh.triangle_face.end(), m.triangles.size(), int(f));
  }
  double size = 0.0;
  for (const TrimmedSurface& f : faces) size = std::max(size, control_box(f.surface).diagonal());
  r.weld_tolerance = std::max(1e-9 * size, options.weld);
  if (options.watertight) {
    close_t_junctions(mesh, r.weld_tolerance, &ws, kSliverHole * options.eps);
    s.edge_shared = ws.edge_shared;
    s.shared_vertices = ws.inserted + ws.merged;
    s.t_junction_splits = ws.splits;
    s.sliver_holes = ws.filled;
    r.fill_width = ws.fill_width;
  }
  s.failed_faces = int(r.failures.size());
  s.triangles = (long long)mesh.triangles.size();
  s.vertices = (long long)mesh.positions.size();
  s.seconds = nurbs::seconds_since(start);
  return r;
}

}  // namespace nurbs::tess
