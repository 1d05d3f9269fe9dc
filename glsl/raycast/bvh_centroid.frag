// GPU BVH build, step 0: leaf box centroids 0.5 (min + max) for the min / max reductions that
// give the Morton frame (gpgpu/reduce.h ignores NaN: padding is NaN).
#include "lib_layout.glsl"

uniform sampler2D u_box_min;
uniform sampler2D u_box_max;
uniform int u_width;
uniform int u_n;
out vec4 o_centroid;

void main() {
  ivec2 t = ivec2(gl_FragCoord.xy);
  if (layout_index(t, u_width) >= u_n) {
    o_centroid = vec4(uintBitsToFloat(0x7fc00000u));
    return;
  }
  o_centroid = vec4(0.5 * (texelFetch(u_box_min, t, 0).xyz + texelFetch(u_box_max, t, 0).xyz), 0.0);
}
