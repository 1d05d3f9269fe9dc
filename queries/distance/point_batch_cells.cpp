// The cells a trim edge crosses, in the batched point projection (point_batch.h; Krishnamurthy et
// al. §5.3 "discard the point and continue the search", on the GPU): their per-cell trim data for
// glsl/distance/point_batch_trim.frag, its CPU twin, and the closest material point of one cell in double.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <optional>
#include <stdexcept>

#include "nurbs/parallel.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/point_batch_finish.h"
#include "queries/distance/cell_triangles.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// glsl/distance/point_batch_trim.frag kTrimRef (as floats, so both sides use the same point).
const glm::dvec2 kTrimRef(double(0.3819660113f), double(0.6180339887f));
/// Segments are clipped to the cell grown by this much (unit-cell coordinates): a crossing of the
/// segment from the reference to a point of the cell lies inside it.
constexpr double kClipMargin = 1e-3;

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

/// The side of x from the cell's crossing segments: glsl/distance/point_batch_trim.frag trim_crosses over the
/// crossing segments as trimmed_cell_dist2 counts them, in double on the stored floats.
bool trim_material(glm::dvec2 x, const float* head, const std::vector<float>& segs) {
  bool m = head[3] > 0.5f;
  const glm::dvec2 rx = x - kTrimRef;
  for (int k = 0; k < int(head[1]); ++k) {
    const float* s = &segs[4 * (size_t(head[0]) + size_t(k))];
    const glm::dvec2 a(s[0], s[1]), b(s[2], s[3]);
    if ((cross2(rx, a - kTrimRef) > 0.0) == (cross2(rx, b - kTrimRef) > 0.0)) continue;
    if ((cross2(b - a, kTrimRef - a) > 0.0) != (cross2(b - a, x - a) > 0.0)) m = !m;
  }
  return m;
}

glm::dvec3 on_cell(glm::dvec2 st, bool lower, const glm::dvec3 c[4]) {
  return lower ? c[0] + st.x * (c[1] - c[0]) + st.y * (c[3] - c[1])
               : c[0] + st.y * (c[2] - c[0]) + st.x * (c[3] - c[2]);
}

/// The ends of a stored piece (s0, t0, s1, t1) on its triangle of the cell with corners c
/// (glsl/distance/point_batch_trim.frag trim_segment, a piece's part).
void piece_on_cell(const float* piece, const glm::dvec3 c[4], glm::dvec3& a, glm::dvec3& b) {
  const glm::dvec2 sa(piece[0], piece[1]), sb(piece[2], piece[3]);
  const bool lower = sa.x + sb.x >= sa.y + sb.y;
  a = on_cell(sa, lower, c), b = on_cell(sb, lower, c);
}

/// The side of the reference point of cell (i, j) of grid g, in double: the side the pass starts its
/// crossing count from, and the whole cell's when no edge crosses it.
bool reference_side(const TrimEdges& edges, const nurbs::ParamGrid& g, int i, int j) {
  const double u0 = g.u[size_t(i)], v0 = g.v[size_t(j)];
  return edges.is_material({u0 + kTrimRef.x * (g.u[size_t(i) + 1] - u0), v0 + kTrimRef.y * (g.v[size_t(j) + 1] - v0)});
}

/// Rows of `kTrimTextureWidth` RGBA texels holding `v` (padded with zeros).
gpgpu::Texture rows_texture(std::vector<float>& v) {
  const size_t texels = std::max<size_t>(v.size() / 4, 1);
  const int height = int((texels + kTrimTextureWidth - 1) / kTrimTextureWidth);
  v.resize(size_t(height) * kTrimTextureWidth * 4, 0.0f);
  gpgpu::Texture t(kTrimTextureWidth, height, gpgpu::Format::RGBA32F);
  t.upload(v);
  return t;
}

}  // namespace

void PointBatch::upload_trim_cells(Atlas& at, size_t a) {
  const AtlasPlan& plan = g_.m.atlases[a].plan;
  at.trim_cell.assign(size_t(plan.width) * size_t(plan.height), 0.0f);
  at.trim_head.clear(), at.trim_segs.clear();
  // Per slot on the hardware threads, then appended in slot order.
  struct Part {
    std::vector<float> head, segs;
    std::vector<size_t> texels;
  };
  std::vector<Part> parts(plan.slots.size());
  nurbs::for_shares(plan.slots.size(), nurbs::share_count(plan.slots.size(), 1), [&](size_t, size_t s0, size_t s1) {
    std::vector<glm::dvec4> crossing;
    std::vector<TrimPiece> pieces;
    const glm::dvec3 corners[4]{};  // pieces are stored by their parameters only
    for (size_t s = s0; s < s1; ++s) {
      const AtlasSlot& sl = plan.slots[s];
      const TrimEdges& edges = g_.trim_edges[size_t(sl.face)];
      if (g_.m.faces[size_t(sl.face)].loops.empty()) continue;
      const nurbs::ParamGrid& g = g_.m.grids[size_t(sl.face)].grid;
      Part& part = parts[s];
      // The cells an edge crosses, and the other cells of the pyramid that may be trimmed (a
      // trimmed corner sample, or crossed by PreparedModel's conservative count): those hold no
      // segments, and the reference's side is the whole cell's.
      std::vector<glm::ivec2> cells = edges.cells();
      std::vector<char> listed(size_t(g.cells_u()) * size_t(g.cells_v()), 0);
      for (const glm::ivec2 c : cells) listed[size_t(c.y) * size_t(g.cells_u()) + size_t(c.x)] = 1;
      for (int j = 0; j < g.cells_v(); ++j)
        for (int i = 0; i < g.cells_u(); ++i) {
          const int x = sl.x + i, y = sl.y + j;
          if (listed[size_t(j) * size_t(g.cells_u()) + size_t(i)] || !g_.pyramid_cell(at, a, x, y)) continue;
          bool all_material = at.crossed[size_t(y) * size_t(plan.width) + size_t(x)] < 0.5f;
          for (int k = 0; k < 4; ++k)
            all_material =
                all_material && at.mask[size_t(y + (k >> 1)) * size_t(plan.width) + size_t(x + (k & 1))] > 0.5f;
          if (!all_material) cells.emplace_back(i, j);
        }
      for (const glm::ivec2 c : cells) {
        crossing.clear(), pieces.clear();
        edges.segments(c.x, c.y, kClipMargin, crossing);
        edges.pieces(c.x, c.y, corners, pieces);
        const double u0 = g.u[size_t(c.x)], du = g.u[size_t(c.x) + 1] - u0;
        const double v0 = g.v[size_t(c.y)], dv = g.v[size_t(c.y) + 1] - v0;
        const bool ref = reference_side(edges, g, c.x, c.y);
        part.texels.push_back(size_t(sl.y + c.y) * size_t(plan.width) + size_t(sl.x + c.x));
        part.head.insert(part.head.end(), {float(part.segs.size() / 4), float(crossing.size()), float(pieces.size()),
                                           ref ? 1.0f : 0.0f});
        for (const glm::dvec4& e : crossing)
          part.segs.insert(part.segs.end(), {float(e.x), float(e.y), float(e.z), float(e.w)});
        for (const TrimPiece& pc : pieces)
          part.segs.insert(part.segs.end(), {float((pc.uv_a.x - u0) / du), float((pc.uv_a.y - v0) / dv),
                                             float((pc.uv_b.x - u0) / du), float((pc.uv_b.y - v0) / dv)});
      }
    }
  });
  for (Part& part : parts) {
    const float first = float(at.trim_segs.size() / 4);
    for (size_t k = 0; k < part.texels.size(); ++k) {
      at.trim_cell[part.texels[k]] = float(at.trim_head.size() / 4 + 1);
      part.head[4 * k] += first;
      at.trim_head.insert(at.trim_head.end(), part.head.begin() + ptrdiff_t(4 * k),
                          part.head.begin() + ptrdiff_t(4 * k + 4));
    }
    at.trim_segs.insert(at.trim_segs.end(), part.segs.begin(), part.segs.end());
    part = {};
  }
  // Indices travel as floats: exact below 2^24.
  if (at.trim_head.size() / 4 >= (size_t(1) << 24) || at.trim_segs.size() / 4 >= (size_t(1) << 24))
    throw std::length_error(fmt::format("PointBatch: {} trimmed cells, {} trim segments in one atlas (at most 2^24)",
                                        at.trim_head.size() / 4, at.trim_segs.size() / 4));
}

void BatchAtlas::upload_trim_textures(const AtlasPlan& plan) {
  trim_cell_tex = gpgpu::Texture(plan.width, plan.height, gpgpu::Format::R32F);
  trim_cell_tex.upload(trim_cell);
  trim_head_tex = rows_texture(trim_head);
  trim_segs_tex = rows_texture(trim_segs);
}

double BatchGeometry::trimmed_cell_distance(const BatchAtlas& at, const glm::dvec3& q, const glm::dvec3 c[4],
                                         int header) const {
  const float* head = &at.trim_head[4 * size_t(header)];
  double best = kInf;
  glm::dvec3 w;
  // The cell's triangles (cell_triangles.h): on triangle 0, (s, t) = (w1 + w2, w2); on 1, (w1, w1 + w2).
  constexpr auto& T = kCellTriangle;
  const glm::dvec3 p0 = closest_on_triangle(q, c[T[0][0]], c[T[0][1]], c[T[0][2]], w);
  const double d0 = glm::length(p0 - q);
  if (trim_material({w.y + w.z, w.z}, head, at.trim_segs)) best = d0;
  const glm::dvec3 p1 = closest_on_triangle(q, c[T[1][0]], c[T[1][1]], c[T[1][2]], w);
  const double d1 = glm::length(p1 - q);
  if (trim_material({w.y, w.y + w.z}, head, at.trim_segs)) best = std::min(best, d1);
  // A piece lies on its triangle, no nearer than the triangle's closest point: the pieces of a
  // triangle as near as `best` or farther cannot lower it (the pass reads them all).
  const bool skip0 = d0 >= best, skip1 = d1 >= best;
  if (skip0 && skip1) return best;
  const size_t first = size_t(head[0]) + size_t(head[1]);
  for (size_t k = 0; k < size_t(head[2]); ++k) {
    const float* piece = &at.trim_segs[4 * (first + k)];
    if (piece[0] + piece[2] >= piece[1] + piece[3] ? skip0 : skip1) continue;  // (piece_on_cell's triangle)
    glm::dvec3 a, b;
    piece_on_cell(piece, c, a, b);
    const glm::dvec3 d = b - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(q - a, d) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(a + t * d - q));
  }
  return best;
}

void BatchGeometry::material_points(const BatchAtlas& at, size_t a, int x, int y, const glm::dvec3 corners[4],
                                 std::vector<glm::dvec3>& out) const {
  out.clear();
  const float header = at.trim_cell[size_t(y) * size_t(m.atlases[a].plan.width) + size_t(x)];
  if (!(header > 0.0f)) {
    out.assign(corners, corners + 4);
    return;
  }
  const float* head = &at.trim_head[4 * size_t(header - 1.0f)];
  const AtlasPlan& plan = m.atlases[a].plan;  // (at is not in atlases yet while the pyramid is built)
  const AtlasSlot& sl = plan.slots[size_t(at.slot_of[size_t(y) * size_t(plan.width) + size_t(x)])];
  const FaceCell c{sl.face, x - sl.x, y - sl.y};
  const nurbs::ParamGrid& g = m.grids[size_t(c.face)].grid;
  const TrimEdges& edges = trim_edges[size_t(c.face)];
  for (int k = 0; k < 4; ++k) {
    const bool material = head[1] == 0.0f && head[2] == 0.0f  // no edge: the reference's side throughout
                              ? head[3] > 0.5f
                              : edges.is_material({g.u[size_t(c.i + (k & 1))], g.v[size_t(c.j + (k >> 1))]});
    if (material) out.push_back(corners[k]);
  }
  const size_t first = size_t(head[0]) + size_t(head[1]);
  for (size_t k = 0; k < size_t(head[2]); ++k) {
    glm::dvec3 pa, pb;
    piece_on_cell(&at.trim_segs[4 * (first + k)], corners, pa, pb);
    out.push_back(pa), out.push_back(pb);
  }
}

PointDistance BatchFinish::material_cell(const glm::dvec3& p, size_t a, int x, int y) const {
  PointDistance best;
  best.distance = kInf;
  glm::dvec3 corners[4];
  const FaceCell c = g_.cell_corners(a, x, y, corners);
  // A cell no edge crosses is material throughout or not at all (as the pass takes it): its
  // boundary points too, where is_material's half-open rule may say trimmed (an edge of the loop
  // on the cell's side, a loop touching it at a vertex).
  const TrimEdges& edges = g_.trim_edges[size_t(c.face)];
  std::optional<bool> uniform;
  if (!g_.m.faces[size_t(c.face)].loops.empty() && !edges.crossed(c.i, c.j))
    uniform = reference_side(edges, g_.m.grids[size_t(c.face)].grid, c.i, c.j);
  int triangle = -1;  // the material triangle point's triangle, -1: none
  for (int t = 0; t < 2; ++t) {
    const PointDistance rt = cell_result(p, a, x, y, false, t);
    if (rt.distance < best.distance && (uniform ? *uniform : material(rt))) best = rt, triangle = t;
  }
  TrimEdgeHit h{best.distance};
  if (!edges.closest(p, c.i, c.j, corners, h)) {
    if (triangle < 0) return PointDistance{};
    return cell_result(p, a, x, y, true, triangle);
  }
  best.distance = h.distance, best.point = h.point, best.uv = h.uv, best.face = c.face;
  best.found = true;
  best.on_trim_edge = true;
  best.bound = g_.model_bound + 2.0 * g_.slack(p);
  best.point_bound = std::sqrt(4 * best.bound * best.distance + best.bound * best.bound);
  return best;
}

}  // namespace queries
