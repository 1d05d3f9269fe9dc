// Non-uniform stream reduction, build step (Krishnamurthy et al. §1.1; a HistoPyramid laid out
// row-major so that compaction preserves element order). Each output texel counts the elements
// kept in the FANOUT input texels along u_axis ((1,0): along a row, (0,1): along the column);
// FANOUT is 4, or 16 for half the passes (gpgpu/compact.h).
// FROM_PREDICATE: the input is the predicate texture (kept where channel 0 > 0; NaN is not kept;
// with PREDICATE_CUT, kept where channel 0 <= u_cut: compact_at_most); otherwise it is the
// previous R32UI count level.
uniform ivec2 u_src_size;
uniform ivec2 u_axis;
#if FROM_PREDICATE
#include "lib_keep.glsl"
uniform sampler2D u_src;
#else
uniform usampler2D u_src;
#endif
out uint o_count;

void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * (ivec2(1) + (FANOUT - 1) * u_axis);
  uint count = 0u;
  for (int k = 0; k < FANOUT; ++k) {
    ivec2 t = base + k * u_axis;
    if (t.x >= u_src_size.x || t.y >= u_src_size.y) break;
#if FROM_PREDICATE
    count += kept(texelFetch(u_src, t, 0).r);
#else
    count += texelFetch(u_src, t, 0).r;
#endif
  }
  o_count = count;
}
