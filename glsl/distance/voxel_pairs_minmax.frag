// Voxel pairs of the object first stage of Krishnamurthy et al. §5.4: row y of this tile is
// occupied voxel u_offset.y + y of object A, column x is voxel u_offset.x + x of object B. R = the
// minimum distance of the two voxel boxes (a lower bound for every pair), G = their maximum distance,
// an upper bound only when both voxels hold surface material (witness flag in lo.w), +inf otherwise.
#include "lib_layout.glsl"
#include "lib_box.glsl"

uniform sampler2D u_lo_a;  // RGBA32F per occupied voxel of A (layout_pow2): box min, w = witness
uniform sampler2D u_hi_a;  // box max
uniform sampler2D u_lo_b;  // the same for B, refitted under its motion
uniform sampler2D u_hi_b;
uniform ivec2 u_offset;    // first voxel of B (x) and of A (y) in this tile
out vec4 o_minmax;

const float kInf = 1.0 / 0.0;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  ivec2 ta = pow2_texel(u_offset.y + g.y, textureSize(u_lo_a, 0).x);
  ivec2 tb = pow2_texel(u_offset.x + g.x, textureSize(u_lo_b, 0).x);
  vec4 lo1 = texelFetch(u_lo_a, ta, 0), lo2 = texelFetch(u_lo_b, tb, 0);
  vec2 d = box_box_minmax(lo1.xyz, texelFetch(u_hi_a, ta, 0).xyz, lo2.xyz, texelFetch(u_hi_b, tb, 0).xyz);
  o_minmax = vec4(d.x, lo1.w > 0.5 && lo2.w > 0.5 ? d.y : kInf, 0.0, 0.0);
}
