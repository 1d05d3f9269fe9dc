// Argmin reduction step: like reduce_2x2.frag with min, but carrying where the minimum is.
// Output texel = (value, x, y, 0) with (x, y) the source texel (exact in float below 2^24).
// FIRST_PASS reads channel u_channel of the source data; later passes read (value, x, y).
// Ties go to the smallest row-major index (y, then x), so the result equals the CPU twin's.
// NaN entries never win; a block without valid entries gives (+inf, -1, -1).
#include "lib_float.glsl"

uniform sampler2D u_src;
uniform ivec2 u_src_size;
uniform int u_channel;
out vec4 o_value;

bool better(vec3 a, vec3 b) {
  if (b.y < 0.0) return true;
  if (a.x != b.x) return a.x < b.x;
  return a.z < b.z || (a.z == b.z && a.y < b.y);
}

void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * 2;
  vec3 best = vec3(pos_inf(), -1.0, -1.0);
  for (int dy = 0; dy < 2; ++dy) {
    for (int dx = 0; dx < 2; ++dx) {
      ivec2 t = base + ivec2(dx, dy);
      if (t.x >= u_src_size.x || t.y >= u_src_size.y) continue;
#if FIRST_PASS
      float v = texelFetch(u_src, t, 0)[u_channel];
      if (is_nan_bits(v)) continue;
      vec3 cand = vec3(v, float(t.x), float(t.y));
#else
      vec3 cand = texelFetch(u_src, t, 0).xyz;
      if (cand.y < 0.0) continue;
#endif
      if (better(cand, best)) best = cand;
    }
  }
  o_value = vec4(best, 0.0);
}
