// GPU BVH build, step 4: the parent of every node (2n - 1 of them), gathered rather than scattered.
// A node with key range [a, b] is its parent's left child when the parent's split is at b, i.e.
// when delta(b, b + 1) > delta(a - 1, a) (Apetrei, "Fast and simple agglomerative LBVH
// construction", 2014); the parent's range then reaches from a to the last key b' sharing
// delta(b, b + 1) bits with key a (an exponential and a binary search, delta(a, j) falls with j),
// and the mirror case. Karras' parent is indexed by one end of its range: node a' (the left end)
// when its range is exactly the parent's, else the right end. Output (parent, sibling, is left,
// 0); the root (node 0) gets (-1, -1, 0, 0).
#include "lib_layout.glsl"
#include "lib_bvh_keys.glsl"

uniform sampler2D u_internal;  // bvh_karras.frag's output: (left, right, first, last)
uniform int u_width;           // of the node arrays
out vec4 o_parent;

vec4 internal(int i) { return texelFetch(u_internal, pow2_texel(i, u_width), 0); }

ivec2 node_range(int c) {
  if (c >= u_n - 1) return ivec2(c - (u_n - 1));
  return ivec2(internal(c).zw);
}

void main() {
  int c = layout_index(ivec2(gl_FragCoord.xy), u_width);
  if (c == 0 || c >= 2 * u_n - 1) {
    o_parent = vec4(-1.0, -1.0, 0.0, 0.0);
    return;
  }
  ivec2 r = node_range(c);
  int a = r.x, b = r.y;
  bool is_left = b != u_n - 1 && (a == 0 || bvh_delta(b, b + 1) > bvh_delta(a - 1, a));
  int parent;
  if (is_left) {
    int p = bvh_delta(b, b + 1);
    int step = 1;
    while (bvh_delta(a, b + 2 * step) >= p) step *= 2;
    int l = step;  // delta(a, b + step) >= p > delta(a, b + 2 step)
    for (int t = step / 2; t >= 1; t /= 2)
      if (bvh_delta(a, b + l + t) >= p) l += t;
    int end = b + l;
    parent = node_range(a) == ivec2(a, end) ? a : end;
  } else {
    int p = bvh_delta(a - 1, a);
    int step = 1;
    while (bvh_delta(b, a - 2 * step) >= p) step *= 2;
    int l = step;
    for (int t = step / 2; t >= 1; t /= 2)
      if (bvh_delta(b, a - l - t) >= p) l += t;
    int start = a - l;
    parent = node_range(start) == ivec2(start, b) ? start : b;
  }
  vec4 pn = internal(parent);
  o_parent = vec4(float(parent), is_left ? pn.y : pn.x, is_left ? 1.0 : 0.0, 0.0);
}
