// Non-uniform stream reduction, gather step: output element k descends the count pyramid from its
// 1x1 top to the k-th kept input texel (levels built by histopyramid_build.frag, NUM_LEVELS of them,
// level 0 built from the predicate). Writes that texel's record and its row-major source index.
// Elements past u_count (padding of the output layout) get zeros and index 0xffffffff.
#include "lib_layout.glsl"

uniform sampler2D u_pred;
uniform sampler2D u_records;
uniform usampler2D u_levels[NUM_LEVELS];
uniform ivec2 u_level_axis[NUM_LEVELS];   // axis level i was reduced along
uniform ivec2 u_pred_size;
uniform int u_out_width;
uniform uint u_count;
layout(location = 0) out vec4 o_record;
layout(location = 1) out uint o_index;

uint count_at(int level, ivec2 t) {
  // level -1 is the predicate itself
  if (level < 0) return texelFetch(u_pred, t, 0).r > 0.0 ? 1u : 0u;
  return texelFetch(u_levels[level], t, 0).r;
}

ivec2 level_size(int level) { return level < 0 ? u_pred_size : textureSize(u_levels[level], 0); }

void main() {
  uint k = uint(layout_index(ivec2(gl_FragCoord.xy), u_out_width));
  if (k >= u_count) {
    o_record = vec4(0.0);
    o_index = 0xffffffffu;
    return;
  }
  ivec2 p = ivec2(0);
  uint rank = k;
  for (int i = NUM_LEVELS - 1; i >= 0; --i) {
    ivec2 axis = u_level_axis[i];
    ivec2 child_size = level_size(i - 1);
    ivec2 first = p * (ivec2(1) + 3 * axis);
    for (int j = 0; j < 4; ++j) {
      ivec2 c = first + j * axis;
      uint n = count_at(i - 1, c);
      if (rank < n || j == 3 || any(greaterThanEqual(c + axis, child_size))) {
        p = c;
        break;
      }
      rank -= n;
    }
  }
  o_record = texelFetch(u_records, p, 0);
  o_index = uint(layout_index(p, u_pred_size.x));
}
