// Lemasson et al. §3.3 in float, included by raycast.frag: a ray as two planes (Eq. 2), a bicubic
// Bézier patch read from its texture and its de Casteljau evaluation (Eq. 1 with S_s, S_t for Eq. 4).
// CPU twin (double): nurbs/raycast/ray_patch.cpp ray_planes, bicubic_patches.cpp evaluate_patch.
#include "lib_layout.glsl"

// u_patches: 16 texels per patch (power-of-two width >= 16, so a patch is one row): texel 16 k + 4 j + i
// holds p[4 j + i] (i along s, j along t) relative to the scene centre; the w channels carry the
// patch's data: texel 0 the face, 1 the control box diagonal, 2-5 range_u.min/max, range_v.min/max.
uniform sampler2D u_patches;
uniform int u_patches_width;

// A ray relative to the scene centre and its frame (n1, n2, d): N1, N2 of the two planes of Eq. 2
// (as ray_planes) and the direction. Patches are moved into this frame once per patch test, where
// a point's x, y are the two rows of R (Eq. 2: N . (S - o) = N . S + d) and z its t along the ray,
// so Newton evaluates R and the Jacobian of Eq. 4 by de Casteljau on x, y alone (R is linear in
// the control points). eps3: the float noise floor of a point on the ray (u_ulps ulp of |o| + the
// scene radius), the residual float can reach.
struct RayF {
  vec3 o, d;
  mat3 to_ray;  // rows n1, n2, d
  float eps3;
};

RayF make_ray(vec3 o, vec3 d, float eps3) {
  RayF r;
  r.o = o;
  r.d = d;
  vec3 a = abs(d), axis = vec3(0.0);  // the coordinate axis least aligned with d
  if (a.x <= a.y && a.x <= a.z)
    axis.x = 1.0;
  else if (a.y <= a.z)
    axis.y = 1.0;
  else
    axis.z = 1.0;
  vec3 n1 = normalize(cross(d, axis));
  r.to_ray = transpose(mat3(n1, cross(d, n1), d));
  r.eps3 = eps3;
  return r;
}

// Rows of control points in named matrices (no dynamically indexed arrays: see point_batch.frag).
struct Patch {
  mat4x3 r0, r1, r2, r3;  // row j: columns p[4 j + 0 .. 3], in the ray's frame
  int face;
  float diag;
  vec4 range;  // range_u.min, range_u.max, range_v.min, range_v.max
};

vec4 patch_texel(ivec2 b, int i) { return texelFetch(u_patches, b + ivec2(i, 0), 0); }
vec3 in_frame(RayF r, vec4 p) { return r.to_ray * (p.xyz - r.o); }

Patch load_patch(int k, RayF r) {
  ivec2 b = pow2_texel(16 * k, u_patches_width);
  vec4 a0 = patch_texel(b, 0), a1 = patch_texel(b, 1), a2 = patch_texel(b, 2), a3 = patch_texel(b, 3);
  vec4 a4 = patch_texel(b, 4), a5 = patch_texel(b, 5);
  Patch P;
  P.r0 = mat4x3(in_frame(r, a0), in_frame(r, a1), in_frame(r, a2), in_frame(r, a3));
  P.r1 = mat4x3(in_frame(r, a4), in_frame(r, a5), in_frame(r, patch_texel(b, 6)), in_frame(r, patch_texel(b, 7)));
  P.r2 = mat4x3(in_frame(r, patch_texel(b, 8)), in_frame(r, patch_texel(b, 9)), in_frame(r, patch_texel(b, 10)),
                in_frame(r, patch_texel(b, 11)));
  P.r3 = mat4x3(in_frame(r, patch_texel(b, 12)), in_frame(r, patch_texel(b, 13)), in_frame(r, patch_texel(b, 14)),
                in_frame(r, patch_texel(b, 15)));
  P.face = int(a0.w);
  P.diag = a1.w;
  P.range = vec4(a2.w, a3.w, a4.w, a5.w);
  return P;
}

vec3 lerp3(vec3 a, vec3 b, float t) { return a + (b - a) * t; }  // as the twin's lerp (not mix)
vec2 lerp2(vec2 a, vec2 b, float t) { return a + (b - a) * t; }

// de Casteljau on a cubic (§3.3: chosen over the Bernstein sums for float): point and derivative.
void casteljau3(vec3 q0, vec3 q1, vec3 q2, vec3 q3, float t, out vec3 p, out vec3 dp) {
  vec3 a = lerp3(q0, q1, t), b = lerp3(q1, q2, t), c = lerp3(q2, q3, t);
  vec3 d = lerp3(a, b, t), e = lerp3(b, c, t);
  p = lerp3(d, e, t);
  dp = 3.0 * (e - d);
}
void casteljau2(vec2 q0, vec2 q1, vec2 q2, vec2 q3, float t, out vec2 p, out vec2 dp) {
  vec2 a = lerp2(q0, q1, t), b = lerp2(q1, q2, t), c = lerp2(q2, q3, t);
  vec2 d = lerp2(a, b, t), e = lerp2(b, c, t);
  p = lerp2(d, e, t);
  dp = 3.0 * (e - d);
}

struct PatchPoint {
  vec3 s, ss, st;  // S, dS/ds, dS/dt (in the ray's frame)
};

// As evaluate_patch: rows along s, then the column along t.
PatchPoint evaluate_patch(Patch P, vec2 st) {
  vec3 q0, q1, q2, q3, d0, d1, d2, d3, unused;
  casteljau3(P.r0[0], P.r0[1], P.r0[2], P.r0[3], st.x, q0, d0);
  casteljau3(P.r1[0], P.r1[1], P.r1[2], P.r1[3], st.x, q1, d1);
  casteljau3(P.r2[0], P.r2[1], P.r2[2], P.r2[3], st.x, q2, d2);
  casteljau3(P.r3[0], P.r3[1], P.r3[2], P.r3[3], st.x, q3, d3);
  PatchPoint e;
  casteljau3(q0, q1, q2, q3, st.y, e.s, e.st);
  casteljau3(d0, d1, d2, d3, st.y, e.ss, unused);
  return e;
}

// The same on x, y: R (Eq. 2) and its partials wrt s, t (Eq. 4), as a mat3x2 (R, R_s, R_t).
mat3x2 evaluate_residual(Patch P, vec2 st) {
  vec2 q0, q1, q2, q3, d0, d1, d2, d3, e, es, et, unused;
  casteljau2(P.r0[0].xy, P.r0[1].xy, P.r0[2].xy, P.r0[3].xy, st.x, q0, d0);
  casteljau2(P.r1[0].xy, P.r1[1].xy, P.r1[2].xy, P.r1[3].xy, st.x, q1, d1);
  casteljau2(P.r2[0].xy, P.r2[1].xy, P.r2[2].xy, P.r2[3].xy, st.x, q2, d2);
  casteljau2(P.r3[0].xy, P.r3[1].xy, P.r3[2].xy, P.r3[3].xy, st.x, q3, d3);
  casteljau2(q0, q1, q2, q3, st.y, e, et);
  casteljau2(d0, d1, d2, d3, st.y, es, unused);
  return mat3x2(e, es, et);
}
