// GPU BVH build, step 2: one compare-exchange step (k, j) of a bitonic sort network over the keys
// of bvh_morton.frag (lexicographic on x, y, z; all keys differ by their index), log2(N) (log2(N)
// + 1) / 2 passes for N elements, ping-pong. Element i meets i ^ j; blocks of size k with bit k of
// i clear sort ascending, the others descending, and the last block (k = N) ascending.
#include "lib_layout.glsl"

uniform sampler2D u_src;
uniform int u_width;
uniform int u_k;
uniform int u_j;
out vec4 o_key;

bool key_less(vec4 a, vec4 b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

void main() {
  int i = layout_index(ivec2(gl_FragCoord.xy), u_width);
  int partner = i ^ u_j;
  vec4 a = texelFetch(u_src, pow2_texel(i, u_width), 0);
  vec4 b = texelFetch(u_src, pow2_texel(partner, u_width), 0);
  bool ascending = (i & u_k) == 0;
  bool keep_min = ascending == (i < partner);
  bool a_first = key_less(a, b);
  o_key = (keep_min == a_first) ? a : b;
}
