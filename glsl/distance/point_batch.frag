// Batched point projection (beyond the paper): one fragment per query point descends the
// box pyramid of an atlas of evaluated faces (Krishnamurthy et al. §5.1 hierarchies, stored as mip
// levels of one texture; level 0 = the box of each cell's four samples, ungrown) depth first, the
// four children of a node visited nearest first (their point-box minimum distance, Eqs. 9-12), a
// node pruned when that distance exceeds the best triangle distance so far plus the float slack.
// At the cells the two triangles of the four samples (the split of queries/distance/cell_triangles.h);
// at a cell that a trim edge crosses, their material part (point_batch_trim.frag).
// Output per point: (best triangle distance, cell x, cell y, cells tested); (+inf, -1, -1, n) when
// no cell is material; the fourth channel is -1 - cells tested when the walk was cut short: after
// u_max_steps node expansions (a bound on one fragment's work on any GPU, whose watchdog ends a
// long draw), or when the renderer ended the loops itself (llvmpipe ends an invocation's loops after
// 65535 iterations in all). A point equidistant from a large part of the model (the centre of a
// sphere: every cell within the best distance) is such a walk; its answer is then not the nearest,
// and the CPU twin descends that point again. Every triangle lies in its cell's box, so the pruning never drops a closer
// triangle; the CPU twin is descend_cpu() in queries/distance/point_batch_descent.h.
#include "point_batch_triangle.frag"
#include "point_batch_trim.frag"

uniform sampler2D u_points;  // RGBA32F query points relative to u_origin, 16 per 4 x 4 tile, tiles row-major;
                             // w > 0: only a cell nearer than w is wanted (the descent's first best)
#ifdef ORIENTED
// Oriented boxes (queries/distance/point_batch_obb.cpp), all levels: (centre, e0), (axis a0, e1), (normal a2,
// e2), a1 = a2 x a0; e0 < 0: empty.
uniform sampler2D u_obb0;
uniform sampler2D u_obb1;
uniform sampler2D u_obb2;
#else
uniform sampler2D u_lo;  // RGBA32F box pyramid, all levels (empty box: lo = +inf, hi = -inf)
uniform sampler2D u_hi;
#endif
uniform sampler2D u_samples;  // RGBA32F atlas of samples (model coordinates)
uniform vec3 u_origin;
uniform int u_count;       // number of query points
uniform int u_width;       // width of u_points (a power of two)
uniform int u_top;         // the 1x1 level
uniform ivec2 u_size;      // size of level 0 (powers of two: level l is max(1, u_size >> l))
uniform float u_slack;     // relative float slack (times |q| + u_radius)
uniform float u_radius;    // half the diagonal of the model's box
uniform int u_two;         // 2: the end-of-walk probe loop runs twice unless the loop budget is spent
uniform int u_max_steps;   // node expansions before the walk is cut short (kWalkBudget)
uniform int u_trim_on;     // 1: the material part of the cells a trim edge crosses (point_batch_trim.frag)
out vec4 o_result;

const float kInf = 1.0 / 0.0;

#ifdef ORIENTED
float box_dist(vec3 q, ivec2 t, int level) {
  vec4 c = texelFetch(u_obb0, t, level);
  if (c.w < 0.0) return kInf;  // empty
  vec4 a = texelFetch(u_obb1, t, level), n = texelFetch(u_obb2, t, level);
  vec3 d = q - c.xyz;
  vec3 local = abs(vec3(dot(d, a.xyz), dot(d, cross(n.xyz, a.xyz)), dot(d, n.xyz)));
  return length(max(local - vec3(c.w, a.w, n.w), vec3(0.0)));
}
#else
float box_dist(vec3 q, ivec2 t, int level) {
  vec3 lo = texelFetch(u_lo, t, level).xyz, hi = texelFetch(u_hi, t, level).xyz;
  if (lo.x > hi.x) return kInf;  // empty (or +inf/-inf, never NaN)
  return length(max(max(lo - q, q - hi), vec3(0.0)));
}
#endif

void cswap(inout vec4 d, inout ivec4 k, int i, int j) {
  if (d[j] < d[i]) {
    float t = d[i];
    d[i] = d[j];
    d[j] = t;
    int u = k[i];
    k[i] = k[j];
    k[j] = u;
  }
}

// No stack array (dynamically indexed arrays are slow on llvmpipe): per level j, 8 bits of `pend`
// hold the siblings still to visit at that level, nearest first (count in bits 0-1, then 2-bit
// child indices); bit j of `busy` says some are left. Ancestors are the current texel >> k.
uint get_pend(uvec4 p, int j) { return (p[j >> 2] >> uint(8 * (j & 3))) & 255u; }
void set_pend(inout uvec4 p, inout uint busy, int j, uint v) {
  uint sh = uint(8 * (j & 3));
  p[j >> 2] = (p[j >> 2] & ~(255u << sh)) | (v << sh);
  busy = (v & 3u) != 0u ? busy | (1u << uint(j)) : busy & ~(1u << uint(j));
}

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int index = (((g.y >> 2) * (u_width >> 2) + (g.x >> 2)) << 4) + ((g.y & 3) << 2) + (g.x & 3);
  if (index >= u_count) {
    o_result = vec4(kInf, -1.0, -1.0, 0.0);
    return;
  }
  vec4 point = texelFetch(u_points, g, 0);
  vec3 q = point.xyz;
  float slack = u_slack * (length(q) + u_radius);
  // Pruned: beyond best + slack, and always an empty box (+inf; while best is +inf too, inf > inf
  // is false and an empty cell's "triangles" would join samples of two slots).
  const float kMaxFloat = 3.402823e38;
  float best = point.w > 0.0 ? point.w : kInf;
  ivec2 cell = ivec2(-1);
  int tested = 0;
  int level = u_top;
  ivec2 xy = ivec2(0);
  uvec4 pend = uvec4(0u);
  uint busy = 0u;
  bool done = box_dist(q, xy, level) == kInf;
  int steps = 0;
  while (!done) {
    if (++steps > u_max_steps) break;
    // Expand the node (level, xy): its four children's boxes.
    ivec2 base = 2 * xy;
    // Not textureSize(u_lo, level - 1): llvmpipe answers a size query for the first fragment's lod
    // in every lane, and the lod differs between fragments here.
    ivec2 size = max(ivec2(1), u_size >> (level - 1));
    vec4 dv;
    for (int k = 0; k < 4; ++k) {
      ivec2 c = base + ivec2(k & 1, k >> 1);
      dv[k] = (c.x < size.x && c.y < size.y) ? box_dist(q, c, level - 1) : kInf;
    }
    if (level == 1) {  // the children are cells: their triangles
      for (int k = 0; k < 4; ++k) {
        if (!(dv[k] <= min(best + slack, kMaxFloat))) continue;
        ivec2 c = base + ivec2(k & 1, k >> 1);
        vec3 a = texelFetch(u_samples, c, 0).xyz - u_origin;
        vec3 b = texelFetch(u_samples, c + ivec2(1, 0), 0).xyz - u_origin;
        vec3 cc = texelFetch(u_samples, c + ivec2(0, 1), 0).xyz - u_origin;
        vec3 dd = texelFetch(u_samples, c + ivec2(1, 1), 0).xyz - u_origin;
        float t = sqrt(min(point_triangle_dist2(q, a, b, dd), point_triangle_dist2(q, a, dd, cc)));
        float header = texelFetch(u_trim_cell, c, 0).r;  // a trim edge crosses the cell: its material part,
        if (u_trim_on != 0 && header > 0.0 && t < best) t = sqrt(trimmed_cell_dist2(q, a, b, cc, dd, int(header) - 1));
        ++tested;
        if (t < best) {
          best = t;
          cell = c;
        }
      }
    } else {
      // Children nearest first (a sorting network; an insertion sort through dynamically indexed
      // arrays gave wrong orders on llvmpipe): go to the nearest, keep the others within reach.
      ivec4 order = ivec4(0, 1, 2, 3);
      cswap(dv, order, 0, 1);
      cswap(dv, order, 2, 3);
      cswap(dv, order, 0, 2);
      cswap(dv, order, 1, 3);
      cswap(dv, order, 1, 2);
      float reach = min(best + slack, kMaxFloat);
      if (dv[0] <= reach) {
        uint n = uint(dv[1] <= reach) + uint(dv[2] <= reach) + uint(dv[3] <= reach);  // sorted: a prefix
        set_pend(pend, busy, level - 1, n | uint(order[1] << 2) | uint(order[2] << 4) | uint(order[3] << 6));
        xy = base + ivec2(order[0] & 1, order[0] >> 1);
        --level;
        continue;
      }
    }
    // Back up to the nearest sibling left at the lowest level; pruned ones end their level (the
    // rest are farther).
    while (true) {
      uint m = busy & ~((1u << uint(level)) - 1u);
      if (m == 0u) {
        done = true;
        break;
      }
      int j = findLSB(m);
      uint v = get_pend(pend, j);
      int k = int((v >> 2) & 3u);
      set_pend(pend, busy, j, ((v & 3u) - 1u) | ((v >> 4) << 2));
      xy = 2 * (xy >> (j + 1 - level)) + ivec2(k & 1, k >> 1);
      level = j;
      if (box_dist(q, xy, level) <= min(best + slack, kMaxFloat)) break;
      set_pend(pend, busy, j, 0u);
    }
  }
  // A forced loop exit: the compiler may take done as true after the loop (it exits no other way),
  // so a probe loop with a uniform count tells: it runs 0 times once the budget is spent (as in
  // raycast.frag).
  int probe = 0;
  for (int i = 0; i < u_two; ++i) ++probe;
  bool cut = !done || steps > u_max_steps || probe != 2;
  o_result = vec4(best, float(cell.x), float(cell.y), cut ? -1.0 - float(tested) : float(tested));
}
