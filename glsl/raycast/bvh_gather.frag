// GPU BVH build, step 7: a table of 2^u_shift texels per leaf (the ray caster's patches: 16)
// permuted into key order: texel t of element k = texel t of element (index of key k).
#include "lib_layout.glsl"
#include "lib_bvh_keys.glsl"

uniform sampler2D u_src;
uniform int u_width;  // of the source and the output
uniform int u_shift;
out vec4 o_texel;

void main() {
  int e = layout_index(ivec2(gl_FragCoord.xy), u_width);
  int k = e >> u_shift;
  if (k >= u_n) {
    o_texel = vec4(0.0);
    return;
  }
  int src = (int(bvh_key(k).y) << u_shift) | (e & ((1 << u_shift) - 1));
  o_texel = texelFetch(u_src, pow2_texel(src, u_width), 0);
}
