// One level of the simultaneous descent of two AABB hierarchies (Krishnamurthy et al. §5.1-5.2):
// output texel k is child pair (k & 15) of surviving pair (k >> 4): child (k & 3) of box A and child
// ((k >> 2) & 3) of box B (an object already at its leaves keeps its box: child 0 only). R and G are
// the minimum and maximum distance between the two boxes (Eqs. 13-20); the second target holds the
// child pair record (xa, ya, xb, yb) for the next level. Missing or empty children: (+inf, +inf).
// SAMPLE_UPPER (beyond the paper): G is also bounded by the distance of the two nodes' face samples
// (aabb_leaf.frag) plus their float budgets: two points of the faces, a tighter upper bound than the
// boxes' farthest points, and no less than the closest triangle pair's distance (samples are
// triangle corners), so the least upper bound U prunes more and keeps the same answer.
#include "lib_layout.glsl"
#include "lib_box.glsl"

uniform sampler2D u_pairs;  // RGBA32F records (xa, ya, xb, yb) of the surviving pairs, row-major
uniform int u_pair_count;
uniform int u_pair_offset;  // first pair of this chunk (a level too large for one target runs in chunks)
uniform sampler2D u_lo_a;   // the finer level of A (or A's leaves when it is there already)
uniform sampler2D u_hi_a;
uniform sampler2D u_lo_b;
uniform sampler2D u_hi_b;
uniform ivec2 u_descend;    // 1 when A (x) / B (y) goes one level down, 0 when it stays at its leaves
uniform int u_out_width;    // width of this pass's target
#ifdef SAMPLE_UPPER
uniform sampler2D u_sample_a;  // the face samples of A's and B's levels (w < 0: none)
uniform sampler2D u_sample_b;
#endif
layout(location = 0) out vec4 o_minmax;
layout(location = 1) out vec4 o_pair;

const float kInf = 1.0 / 0.0;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int k = g.y * u_out_width + g.x;
  int pair = (k >> 4) + u_pair_offset, ca = k & 3, cb = (k >> 2) & 3;
  o_minmax = vec4(kInf, kInf, 0.0, 0.0);
  o_pair = vec4(-1.0);
  if (pair >= u_pair_count || (u_descend.x == 0 && ca != 0) || (u_descend.y == 0 && cb != 0)) return;
  vec4 rec = texelFetch(u_pairs, layout_texel(pair, textureSize(u_pairs, 0).x), 0);
  ivec2 a = ivec2(rec.xy) * (1 + u_descend.x) + u_descend.x * ivec2(ca & 1, ca >> 1);
  ivec2 b = ivec2(rec.zw) * (1 + u_descend.y) + u_descend.y * ivec2(cb & 1, cb >> 1);
  if (any(greaterThanEqual(a, textureSize(u_lo_a, 0))) || any(greaterThanEqual(b, textureSize(u_lo_b, 0)))) return;
  vec3 lo1 = texelFetch(u_lo_a, a, 0).xyz, hi1 = texelFetch(u_hi_a, a, 0).xyz;
  vec3 lo2 = texelFetch(u_lo_b, b, 0).xyz, hi2 = texelFetch(u_hi_b, b, 0).xyz;
  if (any(greaterThan(lo1, hi1)) || any(greaterThan(lo2, hi2))) return;  // empty box
  o_minmax = vec4(box_box_minmax(lo1, hi1, lo2, hi2), 0.0, 0.0);  // Eqs. (13)-(20)
#ifdef SAMPLE_UPPER
  vec4 sa = texelFetch(u_sample_a, a, 0), sb = texelFetch(u_sample_b, b, 0);
  if (sa.w >= 0.0 && sb.w >= 0.0) {
    // The budgets, and the float rounding of the coordinates and of the distance (1e-6 relative).
    float slack = sa.w + sb.w + 1e-6 * (length(sa.xyz) + length(sb.xyz));
    o_minmax.y = min(o_minmax.y, distance(sa.xyz, sb.xyz) + slack);
  }
#endif
  o_pair = vec4(vec2(a), vec2(b));
}
