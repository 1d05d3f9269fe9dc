// NURBS surface evaluation on a grid (Krishnamurthy et al. §2.2, their ref. [27]): texel (i, j) of
// the target (a tile of the grid) holds S(u_i, v_j), u_i and v_j read from parameter textures
// (normalised to the domain [0, 1]; knot-aligned, piecewise uniform: nurbs/distance/certified_grid.h).
// Control points arrive homogeneous, (w (P - origin), w), so float sums stay small; the origin is
// added back at the end. Outputs: o_point = (x, y, z, w) with w the rational denominator at
// (u_i, v_j); o_normal = unit normal (Su x Sv), (0, 0, 0) where it is undefined (poles).
#include "lib_bspline_basis.glsl"

uniform sampler2D u_knots_u;
uniform sampler2D u_knots_v;
uniform sampler2D u_ctrl;     // RGBA32F, point (i, j) at index j count_u + i (pow2_texel)
uniform sampler2D u_params_u; // R32F, samples x 1
uniform sampler2D u_params_v;
uniform ivec2 u_count;        // control points along u, v
uniform ivec2 u_degree;
uniform vec3 u_origin;
layout(location = 0) out vec4 o_point;
layout(location = 1) out vec4 o_normal;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  float u = texelFetch(u_params_u, ivec2(g.x, 0), 0).r;
  float v = texelFetch(u_params_v, ivec2(g.y, 0), 0).r;
  int width = textureSize(u_ctrl, 0).x;
  int p = u_degree.x, q = u_degree.y;
  int su = find_span(u_knots_u, u_count.x, p, u);
  int sv = find_span(u_knots_v, u_count.y, q, v);
  float Nu[MAX_DEGREE + 1], dNu[MAX_DEGREE + 1], Nv[MAX_DEGREE + 1], dNv[MAX_DEGREE + 1];
  basis_and_derivative(u_knots_u, su, u, p, Nu, dNu);
  basis_and_derivative(u_knots_v, sv, v, q, Nv, dNv);

  vec4 S = vec4(0.0), Su = vec4(0.0), Sv = vec4(0.0);
  for (int b = 0; b <= q; ++b) {
    vec4 row = vec4(0.0), row_du = vec4(0.0);
    for (int a = 0; a <= p; ++a) {
      vec4 pw = texelFetch(u_ctrl, pow2_texel((sv - q + b) * u_count.x + su - p + a, width), 0);
      row += Nu[a] * pw;
      row_du += dNu[a] * pw;
    }
    S += Nv[b] * row;
    Su += Nv[b] * row_du;
    Sv += dNv[b] * row;
  }
  vec3 P = S.xyz / S.w;
  vec3 du = (Su.xyz - Su.w * P) / S.w;  // quotient rule (A4.4, first order)
  vec3 dv = (Sv.xyz - Sv.w * P) / S.w;
  vec3 n = cross(du, dv);
  float len = length(n);
  o_point = vec4(P + u_origin, S.w);
  o_normal = vec4(len > 0.0 ? n / len : vec3(0.0), 0.0);
}
