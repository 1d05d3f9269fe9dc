// Batched surface evaluation: the grids of many faces packed into one atlas and evaluated
// in one pass, as surface_eval_tabulated.frag does for one face. Texel (x, y) belongs to the face
// slot u_slot_of[x, y] (-1: no face); its slot record gives the grid's corner in the atlas, where
// its basis tables and control points start in the shared arrays, and its origin.
#include "lib_layout.glsl"

uniform sampler2D u_slot_of;  // R32F, atlas size: slot index or -1
uniform sampler2D u_slots;    // RGBA32F array, 4 records per slot (queries/distance/face_atlas.cpp)
uniform sampler2D u_basis;    // RGBA32F array: (N, dN/dt, span, 0), u tables then v tables per slot
uniform sampler2D u_ctrl;     // RGBA32F array: homogeneous control points of every slot
layout(location = 0) out vec4 o_point;

vec4 record(int slot, int k) {
  return texelFetch(u_slots, pow2_texel(4 * slot + k, textureSize(u_slots, 0).x), 0);
}
vec4 array_at(sampler2D a, int i) { return texelFetch(a, pow2_texel(i, textureSize(a, 0).x), 0); }

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int slot = int(texelFetch(u_slot_of, g, 0).r);
  if (slot < 0) {
    o_point = vec4(0.0);
    return;
  }
  vec4 r0 = record(slot, 0), r1 = record(slot, 1), r2 = record(slot, 2), r3 = record(slot, 3);
  int i = g.x - int(r0.x), j = g.y - int(r0.y);
  int base_u = int(r0.z), base_v = int(r0.w), ctrl = int(r1.x), count_u = int(r1.y);
  int p = int(r1.z), q = int(r1.w), W = int(r2.w), H = int(r3.x);
  int su = int(array_at(u_basis, base_u + i).z);
  int sv = int(array_at(u_basis, base_v + j).z);
  vec4 S = vec4(0.0);
  for (int b = 0; b <= q; ++b) {
    float nv = array_at(u_basis, base_v + b * H + j).x;
    vec4 row = vec4(0.0);
    for (int a = 0; a <= p; ++a) {
      float nu = array_at(u_basis, base_u + a * W + i).x;
      row += nu * array_at(u_ctrl, ctrl + (sv - q + b) * count_u + su - p + a);
    }
    S += nv * row;
  }
  o_point = vec4(S.xyz / S.w + r2.xyz, S.w);
}
