// GPU BVH build, step 1 (Lemasson et al. §3.2; queries/raycast/bvh_gpu.h): the 30-bit Morton code of each
// leaf box's centroid in the box of the centroids, one fragment per element of the padded array
// (a power of two for the bitonic sort). Output (code >> 15, code & 32767, index, 0); padding gets
// the key 2^30 | index, after every real one. Float steps as the CPU twin's (morton_keys_float):
// centroid 0.5 (lo + hi), (c - u_lo) * u_inv_ext * 1024, floor, clamp to [0, 1023].
#include "lib_layout.glsl"

uniform sampler2D u_box_min;  // leaf boxes (RGBA32F, xyz), input order, u_width-wide pow2 layout
uniform sampler2D u_box_max;
uniform int u_width;  // of the boxes and of the output
uniform int u_n;
uniform vec3 u_lo;       // least centroid
uniform vec3 u_inv_ext;  // 1 / (largest - least centroid), per axis
out vec4 o_key;

uint expand_bits(uint x) {  // the low 10 bits of x to every third bit (Karras' expandBits)
  x = (x * 0x00010001u) & 0xFF0000FFu;
  x = (x * 0x00000101u) & 0x0F00F00Fu;
  x = (x * 0x00000011u) & 0xC30C30C3u;
  x = (x * 0x00000005u) & 0x49249249u;
  return x;
}

void main() {
  int i = layout_index(ivec2(gl_FragCoord.xy), u_width);
  if (i >= u_n) {
    o_key = vec4(32768.0, 0.0, float(i), 0.0);
    return;
  }
  ivec2 t = pow2_texel(i, u_width);
  vec3 c = 0.5 * (texelFetch(u_box_min, t, 0).xyz + texelFetch(u_box_max, t, 0).xyz);
  vec3 q = clamp(floor((c - u_lo) * u_inv_ext * 1024.0), 0.0, 1023.0);
  uint code = (expand_bits(uint(q.x)) << 2) | (expand_bits(uint(q.y)) << 1) | expand_bits(uint(q.z));
  o_key = vec4(float(code >> 15), float(code & 32767u), float(i), 0.0);
}
