// One level of an AABB hierarchy (Krishnamurthy et al. §5.1, stored mip-style): the box of the 2x2
// children (2x, 2y) .. (2x+1, 2y+1) of the finer level; children outside it are empty.
// SAMPLE_UPPER (beyond the paper, aabb_leaf.frag): the node's face sample is its first child's that has one.
uniform sampler2D u_lo;  // finer level
uniform sampler2D u_hi;
layout(location = 0) out vec4 o_lo;
layout(location = 1) out vec4 o_hi;
#ifdef SAMPLE_UPPER
uniform sampler2D u_sample;
layout(location = 2) out vec4 o_sample;
#endif

const float kInf = 1.0 / 0.0;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_lo, 0);
  vec3 lo = vec3(kInf), hi = vec3(-kInf);
#ifdef SAMPLE_UPPER
  o_sample = vec4(0.0, 0.0, 0.0, -1.0);
#endif
  for (int k = 0; k < 4; ++k) {
    ivec2 c = 2 * g + ivec2(k & 1, k >> 1);
    if (c.x >= size.x || c.y >= size.y) continue;
    lo = min(lo, texelFetch(u_lo, c, 0).xyz);
    hi = max(hi, texelFetch(u_hi, c, 0).xyz);
#ifdef SAMPLE_UPPER
    vec4 s = texelFetch(u_sample, c, 0);
    if (o_sample.w < 0.0 && s.w >= 0.0) o_sample = s;
#endif
  }
  o_lo = vec4(lo, 0.0);
  o_hi = vec4(hi, 0.0);
}
