// Step 2 of the batched point projection: the GPU pass (PointBatch::descend_gpu,
// glsl/distance/point_batch.frag) and its twin in double (point_batch_descent.h), side by side.
#include "queries/distance/point_batch_descent.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <utility>

#include "queries/distance/point_batch.h"
#include "queries/distance/point_distance.h"
#include "queries/shaders.h"

namespace queries {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();

}  // namespace

std::vector<uint32_t> morton_order(std::span<const glm::dvec3> points, const glm::dvec3& centre, double half) {
  const auto spread = [](uint32_t v) {  // 10 bits -> every third of 30
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    return (v | (v << 2)) & 0x09249249u;
  };
  std::vector<std::pair<uint32_t, uint32_t>> keyed(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 t = glm::clamp((points[i] - centre) / (2.0 * std::max(half, 1e-300)) + 0.5, 0.0, 1.0);
    const glm::uvec3 c(t * 1023.0);
    keyed[i] = {spread(c.x) | (spread(c.y) << 1) | (spread(c.z) << 2), uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(points.size());
  for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

void build_cpu_pyramid(const BatchGeometry& g, size_t a, BatchAtlas& at) {
  if (!at.cpu_lo.empty()) return;
  const AtlasPlan& plan = g.m.atlases[a].plan;
  const int w = plan.width, h = plan.height, w0 = at.w0, h0 = at.h0;
  const glm::vec3 o(g.m.centre);
  // Level 0: aabb_leaf.frag (TRIM_CROSSED) in float (the same boxes, bit for bit), empty outside the
  // cells and in cells with no material sample that no trim edge crosses.
  std::vector<float> lo(size_t(w0) * size_t(h0) * 3, kInfF), hi(lo.size(), -kInfF);
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      if (!g.pyramid_cell(at, a, x, y)) continue;
      const auto at_texel = [&](int k) { return size_t(y + (k >> 1)) * size_t(w) + size_t(x + (k & 1)); };
      float* l = &lo[(size_t(y) * size_t(w0) + size_t(x)) * 3];
      float* u = &hi[(size_t(y) * size_t(w0) + size_t(x)) * 3];
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) {
          const float v = at.samples[4 * at_texel(k) + size_t(c)] - o[c];
          l[c] = std::min(l[c], v), u[c] = std::max(u[c], v);
        }
    }
  at.cpu_lo.push_back(std::move(lo));
  at.cpu_hi.push_back(std::move(hi));
  // Levels 1..: the 2x2 merge of aabb_merge.frag.
  for (int l = 1; l < at.levels; ++l) {
    const int fw = at.level_width(l - 1), fh = at.level_height(l - 1);
    const int lw = at.level_width(l), lh = at.level_height(l);
    std::vector<float> nlo(size_t(lw) * size_t(lh) * 3, kInfF), nhi(nlo.size(), -kInfF);
    for (int y = 0; y < lh; ++y)
      for (int x = 0; x < lw; ++x)
        for (int k = 0; k < 4; ++k) {
          const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
          if (cx >= fw || cy >= fh) continue;
          for (int c = 0; c < 3; ++c) {
            const size_t src = (size_t(cy) * size_t(fw) + size_t(cx)) * 3 + size_t(c);
            const size_t dst = (size_t(y) * size_t(lw) + size_t(x)) * 3 + size_t(c);
            nlo[dst] = std::min(nlo[dst], at.cpu_lo.back()[src]);
            nhi[dst] = std::max(nhi[dst], at.cpu_hi.back()[src]);
          }
        }
    at.cpu_lo.push_back(std::move(nlo));
    at.cpu_hi.push_back(std::move(nhi));
  }
}

BatchCell descend_cpu(const BatchGeometry& g, size_t a, const glm::dvec3& p, double within, bool trim_on_gpu) {
  const BatchAtlas& at = g.atlases[a];
  const glm::dvec3 q(glm::vec3(p - g.m.centre));           // the GPU's float point
  const double eps = kFloatSlack * (glm::length(q) + double(float(g.radius)));
  auto box = [&](int level, int x, int y) { return g.node_distance(at, q, level, x, y); };
  auto sample = [&](int x, int y) { return g.float_sample(at, a, x, y); };
  struct Node {
    int level, x, y;
    double d;
  };
  const int top = at.levels - 1;
  std::vector<Node> stack{{top, 0, 0, box(top, 0, 0)}};
  BatchCell best{within > 0.0 ? double(float(within)) : kInf, -1, -1, 0};  // the pass's float start
  while (!stack.empty()) {
    const Node n = stack.back();
    stack.pop_back();
    if (n.d > best.distance + eps) continue;
    const int cw = at.level_width(n.level - 1), ch = at.level_height(n.level - 1);
    double d[4];
    for (int k = 0; k < 4; ++k) {
      const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
      d[k] = cx < cw && cy < ch ? box(n.level - 1, cx, cy) : kInf;
    }
    if (n.level == 1) {  // the children are cells: their two triangles
      for (int k = 0; k < 4; ++k) {
        if (d[k] == kInf || d[k] > best.distance + eps) continue;  // empty cells too (point_batch.frag)
        const int cx = 2 * n.x + (k & 1), cy = 2 * n.y + (k >> 1);
        const glm::dvec3 s[4] = {sample(cx, cy), sample(cx + 1, cy), sample(cx, cy + 1), sample(cx + 1, cy + 1)};
        const float header = at.trim_cell[size_t(cy) * size_t(g.m.atlases[a].plan.width) + size_t(cx)];
        glm::dvec3 wts;
        double t = std::min(glm::length(closest_on_triangle(q, s[0], s[1], s[3], wts) - q),
                            glm::length(closest_on_triangle(q, s[0], s[3], s[2], wts) - q));
        if (trim_on_gpu && header > 0.0f && t < best.distance)  // no nearer
          t = g.trimmed_cell_distance(at, q, s, int(header) - 1);
        ++best.tested;
        if (t < best.distance) best.distance = t, best.x = cx, best.y = cy;
      }
      continue;
    }
    // The sorting network of point_batch.frag (same order on ties).
    int order[4] = {0, 1, 2, 3};
    double ds[4] = {d[0], d[1], d[2], d[3]};
    for (const auto& [i, j] : {std::pair{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}})
      if (ds[j] < ds[i]) std::swap(ds[i], ds[j]), std::swap(order[i], order[j]);
    for (int i = 3; i >= 0; --i)
      if (d[order[i]] < kInf && d[order[i]] <= best.distance + eps)
        stack.push_back({n.level - 1, 2 * n.x + (order[i] & 1), 2 * n.y + (order[i] >> 1), d[order[i]]});
  }
  return best;
}


std::vector<std::vector<BatchCell>> PointBatch::descend_gpu(std::span<const glm::dvec3> points,
                                                            std::span<const double> within) {
  std::vector<std::vector<BatchCell>> out(g_.atlases.size());
  if (points.empty()) return out;
  // Neighbouring fragments run in lockstep (SIMD lanes, warps), each as long as its slowest point:
  // points sorted along a Morton curve and laid out in 4 x 4 tiles keep the lanes' paths alike.
  const std::vector<uint32_t> order = morton_order(points, g_.m.centre, 2.0 * g_.radius);
  const int max_size = atlas_side(gpu_.info());
  int width = 4;
  while (width < max_size && int64_t(width) * width < int64_t(points.size())) width *= 2;
  const int64_t tiles_per_row = width / 4, tiles = (int64_t(points.size()) + 15) / 16;
  const int height = int(4 * ((tiles + tiles_per_row - 1) / tiles_per_row));
  if (height > max_size) throw std::length_error(fmt::format("PointBatch: {} points in one batch", points.size()));
  const auto texel_of = [&](size_t i) {  // slot i of the sorted points -> texel index
    const int64_t tile = int64_t(i >> 4), t = int64_t(i & 15);
    return size_t((4 * (tile / tiles_per_row) + (t >> 2)) * width + 4 * (tile % tiles_per_row) + (t & 3));
  };
  std::vector<float> q(size_t(width) * size_t(height) * 4, 0.0f);
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::vec3 d(points[order[i]] - g_.m.centre);
    std::copy_n(&d.x, 3, q.begin() + ptrdiff_t(4 * texel_of(i)));
    if (!within.empty()) q[4 * texel_of(i) + 3] = float(std::max(within[order[i]], 0.0));
  }
  gpgpu::PooledTexture pts = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  pts->upload(q);
  gpgpu::PooledTexture res = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  const bool oriented = g_.boxes == PointBoxes::Oriented;
  gpgpu::Program& prog =
      oriented ? queries::program(gpu_, "point_batch.frag", {{"ORIENTED", "1"}}) : queries::program(gpu_, "point_batch.frag");
  const glm::vec3 o(g_.m.centre);
  prog.set("u_origin", o.x, o.y, o.z);
  prog.set("u_count", int(points.size()));
  prog.set("u_width", width);
  prog.set("u_slack", float(kFloatSlack));
  prog.set("u_radius", float(g_.radius));
  prog.set("u_two", 2);
  prog.set("u_max_steps", kWalkBudget);
  prog.set("u_trim_width", kTrimTextureWidth);
  prog.set("u_trim_on", trim_on_gpu_ ? 1 : 0);
  for (size_t a = 0; a < g_.atlases.size(); ++a) {
    prog.set("u_top", g_.atlases[a].levels - 1);
    prog.set("u_size", g_.atlases[a].w0, g_.atlases[a].h0);
    Atlas& at = g_.atlases[a];
    ensure_uploaded(at, a);
    const gpgpu::Input in_aabb[] = {{"u_points", pts.get()},
                                    {"u_lo", &at.lo},
                                    {"u_hi", &at.hi},
                                    {"u_samples", &g_.m.atlases[a].points},
                                    {"u_trim_cell", &at.trim_cell_tex},
                                    {"u_trim_head", &at.trim_head_tex},
                                    {"u_trim_segs", &at.trim_segs_tex}};
    const gpgpu::Input in_obb[] = {{"u_points", pts.get()},
                                   {"u_obb0", &at.obb[0]},
                                   {"u_obb1", &at.obb[1]},
                                   {"u_obb2", &at.obb[2]},
                                   {"u_samples", &g_.m.atlases[a].points},
                                   {"u_trim_cell", &at.trim_cell_tex},
                                   {"u_trim_head", &at.trim_head_tex},
                                   {"u_trim_segs", &at.trim_segs_tex}};
    gpgpu::Texture* target[] = {res.get()};
    if (oriented)
      gpu_.run("point_batch", prog, in_obb, target);
    else
      gpu_.run("point_batch", prog, in_aabb, target);
    const std::vector<float> r = res->read();
    out[a].resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const float* v = &r[4 * texel_of(i)];
      const bool cut = v[3] < 0.0f;
      out[a][order[i]] = {double(v[0]), int(v[1]), int(v[2]), (long long)(cut ? -1.0f - v[3] : v[3]), cut};
    }
  }
  return out;
}

}  // namespace queries
