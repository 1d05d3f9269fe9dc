// Batched point projection (issue 8, beyond the paper): one fragment per query point descends the
// box pyramid of an atlas of evaluated faces (Krishnamurthy et al. §5.1 hierarchies, stored as mip
// levels of one texture; level 0 = the box of each cell's four samples, ungrown) depth first, the
// four children of a node visited nearest first (their point-box minimum distance, Eqs. 9-12), a
// node pruned when that distance exceeds the best triangle distance so far plus the float slack.
// At the cells the two triangles of the four samples (the diagonal of queries/point_distance.cpp).
// Output per point: (best triangle distance, cell x, cell y, cells tested); (+inf, -1, -1, n) when
// no cell is material; w = -1 if the stack overflowed (the caller then searches on the CPU). Every triangle lies in its cell's box, so the pruning never drops a closer
// triangle; the CPU twin is queries/point_batch.cpp descend().
#include "point_batch_triangle.frag"

uniform sampler2D u_points;  // RGBA32F query points relative to u_origin, row-major, width u_width
uniform sampler2D u_lo;      // RGBA32F box pyramid, all levels (empty box: lo = +inf, hi = -inf)
uniform sampler2D u_hi;
uniform sampler2D u_samples;  // RGBA32F atlas of samples (model coordinates)
uniform vec3 u_origin;
uniform int u_count;       // number of query points
uniform int u_width;       // width of u_points (a power of two)
uniform int u_top;         // the 1x1 level
uniform ivec2 u_size;      // size of level 0 (powers of two: level l is max(1, u_size >> l))
uniform float u_slack;     // relative float slack (times |q| + u_radius)
uniform float u_radius;    // half the diagonal of the model's box
out vec4 o_result;

const float kInf = 1.0 / 0.0;
const int kStack = 48;  // >= 3 (levels - 1) + 1 for 13 levels (a 4096^2 atlas)

float box_dist(vec3 q, ivec2 t, int level) {
  vec3 lo = texelFetch(u_lo, t, level).xyz, hi = texelFetch(u_hi, t, level).xyz;
  if (lo.x > hi.x) return kInf;  // empty (or +inf/-inf, never NaN)
  return length(max(max(lo - q, q - hi), vec3(0.0)));
}

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

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int index = g.y * u_width + g.x;
  if (index >= u_count) {
    o_result = vec4(kInf, -1.0, -1.0, 0.0);
    return;
  }
  vec3 q = texelFetch(u_points, g, 0).xyz;
  float slack = u_slack * (length(q) + u_radius);
  int st_node[kStack];  // level | x << 4 | y << 17
  float st_dist[kStack];
  int sp = 0;
  st_node[sp] = u_top;
  st_dist[sp++] = box_dist(q, ivec2(0), u_top);
  float best = kInf;
  ivec2 cell = ivec2(-1);
  int tested = 0;
  bool overflow = false;  // cannot happen within kStack (see above); reported, never silent
  while (sp > 0) {
    --sp;
    if (st_dist[sp] > best + slack) continue;
    int node = st_node[sp], level = node & 15;
    ivec2 base = 2 * ivec2((node >> 4) & 8191, node >> 17);
    // Not textureSize(u_lo, level - 1): llvmpipe answers a size query for the first fragment's lod
    // in every lane, and the lod differs between fragments here.
    ivec2 size = max(ivec2(1), u_size >> (level - 1));
    float d[4];
    for (int k = 0; k < 4; ++k) {
      ivec2 c = base + ivec2(k & 1, k >> 1);
      d[k] = (c.x < size.x && c.y < size.y) ? box_dist(q, c, level - 1) : kInf;
    }
    if (level == 1) {  // the children are cells: their triangles
      for (int k = 0; k < 4; ++k) {
        if (d[k] > best + slack) continue;
        ivec2 c = base + ivec2(k & 1, k >> 1);
        vec3 a = texelFetch(u_samples, c, 0).xyz - u_origin;
        vec3 b = texelFetch(u_samples, c + ivec2(1, 0), 0).xyz - u_origin;
        vec3 cc = texelFetch(u_samples, c + ivec2(0, 1), 0).xyz - u_origin;
        vec3 dd = texelFetch(u_samples, c + ivec2(1, 1), 0).xyz - u_origin;
        float t = sqrt(min(point_triangle_dist2(q, a, b, dd), point_triangle_dist2(q, a, dd, cc)));
        ++tested;
        if (t < best) {
          best = t;
          cell = c;
        }
      }
      continue;
    }
    // Children nearest first: a 4-sorting network on (distance, child), push the farthest first
    // (an insertion sort through dynamically indexed arrays gave wrong orders on llvmpipe).
    vec4 dv = vec4(d[0], d[1], d[2], d[3]);
    ivec4 order = ivec4(0, 1, 2, 3);
    cswap(dv, order, 0, 1);
    cswap(dv, order, 2, 3);
    cswap(dv, order, 0, 2);
    cswap(dv, order, 1, 3);
    cswap(dv, order, 1, 2);
    for (int i = 3; i >= 0; --i) {
      int k = order[i];
      if (d[k] > best + slack) continue;
      if (sp >= kStack) {
        overflow = true;
        continue;
      }
      ivec2 c = base + ivec2(k & 1, k >> 1);
      st_node[sp] = (level - 1) | (c.x << 4) | (c.y << 17);
      st_dist[sp++] = d[k];
    }
  }
  o_result = vec4(best, float(cell.x), float(cell.y), overflow ? -1.0 : float(tested));
}
