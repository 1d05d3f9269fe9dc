// GPU BVH build, step 3: Karras (HPG 2012) §4, every internal node i in [0, n - 2] independently,
// one fragment each: direction of its key range, the other end j by an exponential then a binary
// search on delta, the split gamma by a binary search, children gamma and gamma + 1 (leaf k is
// node n - 1 + k). Output (left, right, first, last) with [first, last] = the node's key range;
// fragments past the internal nodes write (-1, -1, -1, -1). CPU twin: build_bvh_codes
// (nurbs/raycast/morton_bvh.cpp), the same loop.
#include "lib_layout.glsl"
#include "lib_bvh_keys.glsl"

uniform int u_width;  // of the output
out vec4 o_node;

void main() {
  int i = layout_index(ivec2(gl_FragCoord.xy), u_width);
  if (i >= u_n - 1) {
    o_node = vec4(-1.0);
    return;
  }
  int d = bvh_delta(i, i + 1) - bvh_delta(i, i - 1) >= 0 ? 1 : -1;
  int dmin = bvh_delta(i, i - d);
  int lmax = 2;
  while (bvh_delta(i, i + lmax * d) > dmin) lmax *= 2;
  int l = 0;
  for (int t = lmax / 2; t >= 1; t /= 2)
    if (bvh_delta(i, i + (l + t) * d) > dmin) l += t;
  int j = i + l * d;
  int dnode = bvh_delta(i, j);
  int s = 0;
  for (int div = 2;; div *= 2) {
    int t = (l + div - 1) / div;
    if (bvh_delta(i, i + (s + t) * d) > dnode) s += t;
    if (t <= 1) break;
  }
  int gamma = i + s * d + min(d, 0);
  int left = min(i, j) == gamma ? u_n - 1 + gamma : gamma;
  int right = max(i, j) == gamma + 1 ? u_n + gamma : gamma + 1;
  o_node = vec4(float(left), float(right), float(min(i, j)), float(max(i, j)));
}
