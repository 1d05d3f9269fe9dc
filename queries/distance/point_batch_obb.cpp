// The oriented box pyramid of the batched point projection (point_batch.h, PointBoxes::Oriented;
// beyond the paper, whose §5.1 hierarchies hold axis-aligned boxes). Built on the CPU in double from
// the atlas's float samples, stored as floats, uploaded into three mip-mapped textures that
// glsl/distance/point_batch.frag (ORIENTED) reads; the twin (BatchGeometry::node_distance) reads the same floats.
//
// A node's box: centre c, orthonormal axes a0 (tangent), a1 = a2 x a0, a2 (normal), half extents
// e0, e1, e2. Level 0, a cell: a0 along the cell's mean u edge, a2 its mean normal, the extents those
// of its four samples (which span its two triangles). Level l > 0: the axes from the sums of the
// children's axes, the extents those of the children's box corners (a box holding them holds the
// children's boxes, so every triangle below). Containment is exact in double for the stored floats:
// the axes are rounded first, then the centre, and the extents are taken about the rounded centre
// along the rounded axes (for a child box: the reach of its corners, in closed form) and rounded up. What the pass adds
// in float (a1's cross product, the projections) is within the descent's float slack.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/parallel.h"
#include "queries/distance/point_batch.h"

namespace queries {
namespace {

struct Box {
  glm::dvec3 c{0.0}, a0{1, 0, 0}, a1{0, 1, 0}, a2{0, 0, 1}, e{-1.0};  // e.x < 0: empty
};

/// Axes from a tangent and a normal direction, rounded to float; the world axes when they are
/// degenerate (a collapsed cell, children whose normals cancel): the box is then axis-aligned.
void set_axes(Box& b, glm::dvec3 t, glm::dvec3 n) {
  const double nl = glm::length(n), t0 = glm::length(t);
  if (nl > 0.0 && std::isfinite(nl)) {
    n /= nl;
    t -= glm::dot(t, n) * n;
    const double tl = glm::length(t);
    if (tl > 1e-6 * t0 && tl > 0.0) {
      b.a0 = glm::dvec3(glm::vec3(t / tl));
      b.a2 = glm::dvec3(glm::vec3(n));
      b.a1 = glm::cross(b.a2, b.a0);
      return;
    }
  }
  b.a0 = {1, 0, 0}, b.a1 = {0, 1, 0}, b.a2 = {0, 0, 1};
}

/// The extents rounded up to floats.
void round_up(Box& b) {
  for (int k = 0; k < 3; ++k) {
    float f = float(b.e[k]);
    if (double(f) < b.e[k]) f = std::nextafter(f, HUGE_VALF);
    b.e[k] = f;
  }
}

/// Centre and extents of the points along b's axes (see the file comment).
template <class Points>
void fit(Box& b, const Points& points) {
  glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (const glm::dvec3& p : points) {
    const glm::dvec3 l(glm::dot(p, b.a0), glm::dot(p, b.a1), glm::dot(p, b.a2));
    lo = glm::min(lo, l), hi = glm::max(hi, l);
  }
  const glm::dvec3 mid = 0.5 * (lo + hi);
  b.c = glm::dvec3(glm::vec3(mid.x * b.a0 + mid.y * b.a1 + mid.z * b.a2));
  b.e = glm::dvec3(0.0);
  for (const glm::dvec3& p : points) {
    const glm::dvec3 d = p - b.c;
    b.e = glm::max(b.e,
                   glm::dvec3(std::abs(glm::dot(d, b.a0)), std::abs(glm::dot(d, b.a1)), std::abs(glm::dot(d, b.a2))));
  }
  round_up(b);
}

/// The same for the boxes `children` (non-empty): the largest |a_i . (x - c)| over a child box is
/// |a_i . (c_child - c)| + sum_k |a_i . a_k,child| e_k,child, which its corners reach.
void fit_boxes(Box& b, const Box* children[], int count) {
  const glm::dvec3 axes[3] = {b.a0, b.a1, b.a2};
  auto reach = [&](const Box& c, int i) {  // half width of child c along axis i
    return std::abs(glm::dot(axes[i], c.a0)) * c.e.x + std::abs(glm::dot(axes[i], c.a1)) * c.e.y +
           std::abs(glm::dot(axes[i], c.a2)) * c.e.z;
  };
  glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (int j = 0; j < count; ++j)
    for (int i = 0; i < 3; ++i) {
      const double m = glm::dot(axes[i], children[j]->c), r = reach(*children[j], i);
      lo[i] = std::min(lo[i], m - r), hi[i] = std::max(hi[i], m + r);
    }
  const glm::dvec3 mid = 0.5 * (lo + hi);
  b.c = glm::dvec3(glm::vec3(mid.x * b.a0 + mid.y * b.a1 + mid.z * b.a2));
  b.e = glm::dvec3(0.0);
  for (int j = 0; j < count; ++j)
    for (int i = 0; i < 3; ++i)
      b.e[i] = std::max(b.e[i], std::abs(glm::dot(axes[i], children[j]->c - b.c)) + reach(*children[j], i));
  round_up(b);
}

/// Box i of a level stored as three RGBA float arrays ((c, e0), (a0, e1), (a2, e2)): the floats
/// are the box's values (set_axes and fit round them), so storing and loading loses nothing and
/// no level is kept in double (a 4096 x 1024 level of Box would take 500 MB).
void store(const Box& b, std::array<std::vector<float>, 3>& out, size_t i) {
  const glm::dvec3 first[3] = {b.c, b.a0, b.a2};
  for (size_t k = 0; k < 3; ++k) {
    float* texel = &out[k][4 * i];
    for (int c = 0; c < 3; ++c) texel[c] = float(first[k][c]);
    texel[3] = float(b.e[int(k)]);
  }
}

Box load(const std::array<std::vector<float>, 3>& in, size_t i) {
  Box b;
  const float *c = &in[0][4 * i], *t = &in[1][4 * i], *n = &in[2][4 * i];
  b.c = {c[0], c[1], c[2]}, b.a0 = {t[0], t[1], t[2]}, b.a2 = {n[0], n[1], n[2]};
  b.a1 = glm::cross(b.a2, b.a0);
  b.e = {c[3], t[3], n[3]};
  return b;
}

}  // namespace

/// Texture k of a sparse level expanded to its n texels: the stored boxes, every other texel an
/// empty Box (what the GPU pass reads).
std::vector<float> BatchAtlas::expand_level(const ObbLevel& level, int k, size_t n) {
  const Box none;
  std::array<std::vector<float>, 3> one;
  for (auto& v : one) v.resize(4);
  store(none, one, 0);
  std::vector<float> out(4 * n);
  for (size_t i = 0; i < n; ++i) std::copy_n(one[size_t(k)].begin(), 4, out.begin() + ptrdiff_t(4 * i));
  for (size_t b = 0; b < level.texels.size(); ++b)
    std::copy_n(level.boxes[size_t(k)].begin() + ptrdiff_t(4 * b), 4,
                out.begin() + ptrdiff_t(4 * size_t(level.texels[b])));
  return out;
}

void PointBatch::build_oriented_pyramid(Atlas& at, size_t a) {
  const int w = g_.m.atlases[a].plan.width, levels = at.levels;
  auto sample = [&](int x, int y) { return g_.float_sample(at, a, x, y); };
  at.cpu_obb.assign(size_t(levels), {});
  // A level's boxes come share by share (rows of texels, ascending), each share's (texel, box) in
  // texel order; joined in share order the texels ascend.
  struct Share {
    std::vector<uint32_t> texels;
    std::array<std::vector<float>, 3> boxes;
    void add(uint32_t texel, const Box& b) {
      texels.push_back(texel);
      for (auto& v : boxes) v.resize(v.size() + 4);
      store(b, boxes, texels.size() - 1);
    }
  };
  const auto join = [&](int l, std::vector<Share>& shares) {
    Atlas::ObbLevel& out = at.cpu_obb[size_t(l)];
    out.index.assign(size_t(at.level_width(l)) * size_t(at.level_height(l)), -1);
    for (Share& sh : shares) {
      for (const uint32_t t : sh.texels) out.index[t] = int32_t(out.texels.size()), out.texels.push_back(t);
      for (size_t k = 0; k < 3; ++k) out.boxes[k].insert(out.boxes[k].end(), sh.boxes[k].begin(), sh.boxes[k].end());
      sh = {};
    }
  };
  const int h = g_.m.atlases[a].plan.height;  // cells lie inside the plan (level 0 is padded)
  std::vector<Share> shares(nurbs::share_count(size_t(h), 16));
  nurbs::for_shares(size_t(h), shares.size(), [&](size_t s, size_t y0, size_t y1) {
    std::vector<glm::dvec3> hull;
    for (int y = int(y0); y < int(y1); ++y)
      for (int x = 0; x + 1 < w; ++x) {
        if (!g_.pyramid_cell(at, a, x, y)) continue;
        const glm::dvec3 p[4] = {sample(x, y), sample(x + 1, y), sample(x, y + 1), sample(x + 1, y + 1)};
        // A cell a trim edge crosses: the box of its material part only (the pass's distance there
        // is to that part), so a point near the trimmed-away rest does not descend into it.
        g_.material_points(at, a, x, y, p, hull);
        if (hull.empty()) continue;
        Box b;
        const glm::dvec3 du = (p[1] - p[0]) + (p[3] - p[2]), dv = (p[2] - p[0]) + (p[3] - p[1]);
        set_axes(b, du, glm::cross(du, dv));
        fit(b, hull);
        shares[s].add(uint32_t(size_t(y) * size_t(at.w0) + size_t(x)), b);
      }
  });
  join(0, shares);
  for (int l = 1; l < levels; ++l) {
    const int fw = at.level_width(l - 1), lw = at.level_width(l);
    const Atlas::ObbLevel& fine = at.cpu_obb[size_t(l - 1)];
    // The parents of the finer level's boxes, ascending (rows of two fine rows each).
    std::vector<uint32_t> parents;
    for (const uint32_t t : fine.texels) {
      const uint32_t x = t % uint32_t(fw), y = t / uint32_t(fw);
      parents.push_back((y / 2) * uint32_t(lw) + x / 2);
    }
    std::sort(parents.begin(), parents.end());
    parents.erase(std::unique(parents.begin(), parents.end()), parents.end());
    shares.assign(nurbs::share_count(parents.size(), 256), {});
    nurbs::for_shares(parents.size(), shares.size(), [&](size_t s, size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        const int x = int(parents[i] % uint32_t(lw)), y = int(parents[i] / uint32_t(lw));
        glm::dvec3 t(0.0), n(0.0);
        Box kids[4];
        const Box* children[4];
        int count = 0;
        for (int k = 0; k < 4; ++k) {
          const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
          if (cx >= fw || cy >= at.level_height(l - 1)) continue;
          const int32_t j = fine.index[size_t(cy) * size_t(fw) + size_t(cx)];
          if (j < 0) continue;
          kids[count] = load(fine.boxes, size_t(j));
          if (kids[count].e.x < 0.0) continue;
          t += kids[count].a0, n += kids[count].a2;
          children[count] = &kids[count];
          ++count;
        }
        if (count == 0) continue;
        Box b;
        set_axes(b, t, n);
        fit_boxes(b, children, count);
        shares[s].add(parents[i], b);
      }
    });
    join(l, shares);
  }
}

void BatchAtlas::upload_oriented_pyramid() {
  for (int k = 0; k < 3; ++k) obb[size_t(k)] = gpgpu::Texture(w0, h0, gpgpu::Format::RGBA32F, levels);
  for (int l = 0; l < levels; ++l)
    for (int k = 0; k < 3; ++k) {
      std::vector<float> level = expand_level(cpu_obb[size_t(l)], k, size_t(level_width(l)) * size_t(level_height(l)));
      obb[size_t(k)].upload_level(l, level);
    }
}

std::vector<float> PointBatch::oriented_level(size_t a, int level, int k) const {
  const Atlas& at = g_.atlases[a];
  return BatchAtlas::expand_level(at.cpu_obb[size_t(level)], k, size_t(at.level_width(level)) * size_t(at.level_height(level)));
}

}  // namespace queries
