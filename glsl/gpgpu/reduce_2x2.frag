// Standard reduction (Krishnamurthy et al. §1.1): one log-n step. Each output texel combines the
// 2x2 block of input texels below it, channel by channel, with the operation in u_ops:
// 0 = min, 1 = max, 2 = sum. Texels outside the input (odd sizes) count as the neutral element.
// Beyond the paper, BLOCK = 4 or 8 combines BLOCK^2 texels per pass (gpgpu/reduce.h): half or a
// third of the passes, each costing its fixed overhead on llvmpipe; the block is BLOCK x BLOCK, or a
// row (a column) of BLOCK^2 texels where the input is one texel high (wide), as u_block says.
// NaN policy: min and max ignore NaN entries (an all-NaN block gives the neutral +inf / -inf);
// sums propagate NaN, so a NaN in the data is visible in the result.
#include "lib_float.glsl"

uniform sampler2D u_src;
uniform ivec2 u_src_size;
uniform ivec4 u_ops;
out vec4 o_value;

float neutral(int op) { return op == 0 ? pos_inf() : (op == 1 ? -pos_inf() : 0.0); }

float combine(int op, float acc, float v) {
  if (op == 2) return acc + v;
  if (is_nan_bits(v)) return acc;
  return op == 0 ? min(acc, v) : max(acc, v);
}

#ifndef BLOCK
#define BLOCK 2
#endif
#if BLOCK > 2
uniform ivec2 u_block;  // the block's shape: (BLOCK, BLOCK), (BLOCK^2, 1) or (1, BLOCK^2)
#endif

void main() {
#if BLOCK > 2
  ivec2 shape = u_block;
#else
  ivec2 shape = ivec2(2);
#endif
  ivec2 base = ivec2(gl_FragCoord.xy) * shape;
  vec4 acc = vec4(neutral(u_ops.x), neutral(u_ops.y), neutral(u_ops.z), neutral(u_ops.w));
  for (int k = 0; k < BLOCK * BLOCK; ++k) {  // row by row through the block
    ivec2 t = base + ivec2(k % shape.x, k / shape.x);
    if (t.x >= u_src_size.x || t.y >= u_src_size.y) continue;
    vec4 v = texelFetch(u_src, t, 0);
    acc = vec4(combine(u_ops.x, acc.x, v.x), combine(u_ops.y, acc.y, v.y),
               combine(u_ops.z, acc.z, v.z), combine(u_ops.w, acc.w, v.w));
  }
  o_value = acc;
}
