// GPU BVH build, step 5: node boxes without a bottom-up walk (no atomics in a fragment pass): a
// sparse table over the leaves in key order, T_L[k] = the box of leaves k .. k + 2^L - 1 (clamped
// at n - 1), built in log2(n) passes, and each node's box as the union of two overlapping table
// entries of its range [f, l]: T_L[f] and T_L[l - 2^L + 1], L = floor(log2(l - f + 1)). Equal to
// the CPU's bottom-up union (min and max are exact in float). STAGE 0: T_0 from the input boxes
// by the keys' index; STAGE 1: T_L from T_{L-1}; STAGE 2: the nodes whose range length has
// floor(log2) = u_level, the other fragments discarded (each node is written at one level).
// Outputs: box min, box max (RGBA32F, xyz).
#include "lib_layout.glsl"
#include "lib_bvh_keys.glsl"

uniform sampler2D u_min;  // STAGE 0: input boxes (input order); 1, 2: T_{L-1} or T_L (key order)
uniform sampler2D u_max;
uniform int u_src_width;
uniform int u_width;       // of the output
uniform int u_level;       // L
uniform sampler2D u_internal;  // STAGE 2: bvh_karras.frag's output
layout(location = 0) out vec4 o_min;
layout(location = 1) out vec4 o_max;

void fetch(int i, out vec4 lo, out vec4 hi) {
  ivec2 t = pow2_texel(i, u_src_width);
  lo = texelFetch(u_min, t, 0);
  hi = texelFetch(u_max, t, 0);
}

void main() {
  int i = layout_index(ivec2(gl_FragCoord.xy), u_width);
  vec4 a_lo, a_hi, b_lo, b_hi;
#if STAGE == 0
  fetch(int(bvh_key(min(i, u_n - 1)).y), a_lo, a_hi);
  b_lo = a_lo;
  b_hi = a_hi;
#elif STAGE == 1
  fetch(i, a_lo, a_hi);
  fetch(min(i + (1 << (u_level - 1)), u_n - 1), b_lo, b_hi);
#else
  int f, l;
  if (i >= u_n - 1) {
    f = l = i - (u_n - 1);
  } else {
    vec4 node = texelFetch(u_internal, pow2_texel(i, u_width), 0);
    f = int(node.z);
    l = int(node.w);
  }
  if (i >= 2 * u_n - 1 || findMSB(l - f + 1) != u_level) discard;
  fetch(f, a_lo, a_hi);
  fetch(l - (1 << u_level) + 1, b_lo, b_hi);
#endif
  o_min = min(a_lo, b_lo);
  o_max = max(a_hi, b_hi);
}
