// Pass 2 of the two-pass (tabulated) surface evaluation: texel (i, j) combines the tabulated
// basis functions of column i and row j (computed in double on the CPU: queries/distance/surface_grid.cpp,
// basis_table) with the homogeneous control points.
// Same outputs as surface_eval.frag. Control points: an array of power-of-two width (pow2_texel).
#include "lib_layout.glsl"

uniform sampler2D u_basis_u;  // samples_u x (p + 1)
uniform sampler2D u_basis_v;  // samples_v x (q + 1)
uniform sampler2D u_ctrl;     // RGBA32F (w (P - origin), w), point (i, j) at index j count_u + i
uniform int u_count_u;        // control points along u
uniform ivec2 u_degree;
uniform vec3 u_origin;
layout(location = 0) out vec4 o_point;
layout(location = 1) out vec4 o_normal;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int p = u_degree.x, q = u_degree.y, width = textureSize(u_ctrl, 0).x;
  int su = int(texelFetch(u_basis_u, ivec2(g.x, 0), 0).z);
  int sv = int(texelFetch(u_basis_v, ivec2(g.y, 0), 0).z);
  vec4 S = vec4(0.0), Su = vec4(0.0), Sv = vec4(0.0);
  for (int b = 0; b <= q; ++b) {
    vec2 nv = texelFetch(u_basis_v, ivec2(g.y, b), 0).xy;
    vec4 row = vec4(0.0), row_du = vec4(0.0);
    for (int a = 0; a <= p; ++a) {
      vec2 nu = texelFetch(u_basis_u, ivec2(g.x, a), 0).xy;
      vec4 pw = texelFetch(u_ctrl, pow2_texel((sv - q + b) * u_count_u + su - p + a, width), 0);
      row += nu.x * pw;
      row_du += nu.y * pw;
    }
    S += nv.x * row;
    Su += nv.x * row_du;
    Sv += nv.y * row;
  }
  vec3 P = S.xyz / S.w;
  vec3 du = (Su.xyz - Su.w * P) / S.w;
  vec3 dv = (Sv.xyz - Sv.w * P) / S.w;
  vec3 n = cross(du, dv);
  float len = length(n);
  o_point = vec4(P + u_origin, S.w);
  o_normal = vec4(len > 0.0 ? n / len : vec3(0.0), 0.0);
}
