// Non-uniform stream reduction, gather step: output element k descends the count pyramid from its
// 1x1 top to the k-th kept input texel (levels built by histopyramid_build.frag, u_num_levels of
// them, level 0 built from the predicate: channel 0 > 0, or with PREDICATE_CUT channel 0 <= u_cut).
// MAX_LEVELS (a define) is the most levels of any input
// the GPU can hold, so that one program serves every size; the samplers of levels past the top are
// bound to the top level and never read. Writes that texel's record and its row-major source index.
// Elements past u_count (padding of the output layout) get zeros and index 0xffffffff.
// The descent is unrolled by the preprocessor (STEP) so every sampler index is a constant: a loop
// over a sampler array is dynamic indexing, which llvmpipe runs several times slower.
#include "lib_keep.glsl"
#include "lib_layout.glsl"

uniform sampler2D u_pred;
uniform sampler2D u_records;
uniform usampler2D u_levels[MAX_LEVELS];
uniform ivec2 u_level_axis[MAX_LEVELS];  // axis level i was reduced along
uniform int u_num_levels;
uniform int u_out_width;
uniform uint u_count;
layout(location = 0) out vec4 o_record;
layout(location = 1) out uint o_index;

// One level down: among the (up to FANOUT) children of p along `axis`, find the one holding `rank`.
void step_counts(usampler2D child, ivec2 axis, inout ivec2 p, inout uint rank) {
  ivec2 size = textureSize(child, 0);
  ivec2 first = p * (ivec2(1) + (FANOUT - 1) * axis);
  for (int j = 0; j < FANOUT; ++j) {
    ivec2 c = first + j * axis;
    uint n = texelFetch(child, c, 0).r;
    if (rank < n || j == FANOUT - 1 || any(greaterThanEqual(c + axis, size))) {
      p = c;
      return;
    }
    rank -= n;
  }
}

// The last level down, onto the predicate.
void step_predicate(ivec2 axis, inout ivec2 p, inout uint rank) {
  ivec2 size = textureSize(u_pred, 0);
  ivec2 first = p * (ivec2(1) + (FANOUT - 1) * axis);
  for (int j = 0; j < FANOUT; ++j) {
    ivec2 c = first + j * axis;
    uint n = kept(texelFetch(u_pred, c, 0).r);
    if (rank < n || j == FANOUT - 1 || any(greaterThanEqual(c + axis, size))) {
      p = c;
      return;
    }
    rank -= n;
  }
}

#define STEP(i) \
  if (u_num_levels > i) step_counts(u_levels[i - 1], u_level_axis[i], p, rank);

void main() {
  uint k = uint(layout_index(ivec2(gl_FragCoord.xy), u_out_width));
  if (k >= u_count) {
    o_record = vec4(0.0);
    o_index = 0xffffffffu;
    return;
  }
  ivec2 p = ivec2(0);
  uint rank = k;
#if MAX_LEVELS > 16
#error at most 16 pyramid levels (a 65536^2 input)
#endif
#if MAX_LEVELS > 15
  STEP(15)
#endif
#if MAX_LEVELS > 14
  STEP(14)
#endif
#if MAX_LEVELS > 13
  STEP(13)
#endif
#if MAX_LEVELS > 12
  STEP(12)
#endif
#if MAX_LEVELS > 11
  STEP(11)
#endif
#if MAX_LEVELS > 10
  STEP(10)
#endif
#if MAX_LEVELS > 9
  STEP(9)
#endif
#if MAX_LEVELS > 8
  STEP(8)
#endif
#if MAX_LEVELS > 7
  STEP(7)
#endif
#if MAX_LEVELS > 6
  STEP(6)
#endif
#if MAX_LEVELS > 5
  STEP(5)
#endif
#if MAX_LEVELS > 4
  STEP(4)
#endif
#if MAX_LEVELS > 3
  STEP(3)
#endif
#if MAX_LEVELS > 2
  STEP(2)
#endif
#if MAX_LEVELS > 1
  STEP(1)
#endif
  step_predicate(u_level_axis[0], p, rank);
  o_record = texelFetch(u_records, p, 0);
  o_index = uint(layout_index(p, textureSize(u_pred, 0).x));
}
