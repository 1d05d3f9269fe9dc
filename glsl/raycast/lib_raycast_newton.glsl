// Lemasson et al. §3.3 in float, included by raycast.frag: the initial
// values from the control polyhedron and the fixed-count Newton iteration (Eqs. 2-4) with its three
// outcomes. CPU twin (double): nurbs/raycast/ray_patch.cpp initial_guesses and newton_patch.
#include "lib_float.glsl"
#include "lib_raycast_patch.glsl"
// Möller-Trumbore in the ray's frame, where the ray is the z axis: the barycentrics b of v1, v2 are
// those of the origin in the triangle's x, y, and t interpolates z. The slack (a few float ulp of
// 1) keeps a crossing on a shared triangle edge found by one of the two triangles.
bool ray_triangle(vec3 v0, vec3 v1, vec3 v2, out float t, out vec2 b) {
  vec2 e1 = v1.xy - v0.xy, e2 = v2.xy - v0.xy;
  float det = e1.x * e2.y - e1.y * e2.x;
  t = 0.0;
  b = vec2(0.0);
  if (det == 0.0) return false;  // the ray is parallel to the triangle
  b = vec2(e2.x * v0.y - e2.y * v0.x, e1.y * v0.x - e1.x * v0.y) / det;
  t = v0.z + b.x * (v1.z - v0.z) + b.y * (v2.z - v0.z);
  return b.x >= -1e-6 && b.y >= -1e-6 && b.x + b.y <= 1.0 + 1e-6;
}

// The 4 nearest distinct starts so far, sorted by t (xyzw): a sorted insertion through constant
// component indices. Empty slots have t = +inf and a start far from [0, 1]^2.
struct Starts {
  vec4 t, s, u;  // crossing distance, start s, start t
};
void cswap_start(inout Starts q, int i, int j) {
  if (q.t[j] < q.t[i]) {
    vec3 a = vec3(q.t[i], q.s[i], q.u[i]);
    q.t[i] = q.t[j], q.s[i] = q.s[j], q.u[i] = q.u[j];
    q.t[j] = a.x, q.s[j] = a.y, q.u[j] = a.z;
  }
}
void add_start(inout Starts q, float t, vec2 st) {
  st = clamp(st, 0.0, 1.0);
  vec4 ds = q.s - st.x, du = q.u - st.y;
  if (any(lessThan(ds * ds + du * du, vec4(1e-12))) || !(t < q.t.w)) return;  // a shared edge's twin
  q.t.w = t, q.s.w = st.x, q.u.w = st.y;
  cswap_start(q, 2, 3);
  cswap_start(q, 1, 2);
  cswap_start(q, 0, 1);
}
// Cell (i, j) = ij of the control net as two triangles; local (a, b) -> ((i + a)/3, (j + b)/3).
void cell_starts(vec3 p00, vec3 p10, vec3 p01, vec3 p11, vec2 ij, inout Starts q) {
  float t;
  vec2 b;
  if (ray_triangle(p00, p10, p11, t, b)) add_start(q, t, (ij + vec2(b.x + b.y, b.y)) / 3.0);
  if (ray_triangle(p00, p11, p01, t, b)) add_start(q, t, (ij + vec2(b.x, b.x + b.y)) / 3.0);
}
// §3.3 initial values: the ray against the control polyhedron, nearest crossings first.
Starts initial_guesses(Patch P) {
  Starts q;
  q.t = vec4(pos_inf());
  q.s = q.u = vec4(1e9);
  cell_starts(P.r0[0], P.r0[1], P.r1[0], P.r1[1], vec2(0, 0), q);
  cell_starts(P.r0[1], P.r0[2], P.r1[1], P.r1[2], vec2(1, 0), q);
  cell_starts(P.r0[2], P.r0[3], P.r1[2], P.r1[3], vec2(2, 0), q);
  cell_starts(P.r1[0], P.r1[1], P.r2[0], P.r2[1], vec2(0, 1), q);
  cell_starts(P.r1[1], P.r1[2], P.r2[1], P.r2[2], vec2(1, 1), q);
  cell_starts(P.r1[2], P.r1[3], P.r2[2], P.r2[3], vec2(2, 1), q);
  cell_starts(P.r2[0], P.r2[1], P.r3[0], P.r3[1], vec2(0, 2), q);
  cell_starts(P.r2[1], P.r2[2], P.r3[1], P.r3[2], vec2(1, 2), q);
  cell_starts(P.r2[2], P.r2[3], P.r3[2], P.r3[3], vec2(2, 2), q);
  if (q.t.x == pos_inf()) q.t.x = 0.0, q.s.x = 0.5, q.u.x = 0.5;  // fallback: the patch centre
  return q;
}

uniform float u_scale;        // Newton on (U, V) = u_scale (s, t): §3.3's 1e4
uniform float u_residual;     // ε of §3.3 relative to the patch diagonal (1e-7)
uniform float u_edge_margin;  // (s, t) slack outside [0, 1]^2 (1e-7), plus a float part, see newton_patch

struct NewtonHit {
  bool converged;  // outcome (3) of §3.3; (1) and (2) are both false here
  vec2 st;
  float t;
  PatchPoint e;  // at st in the ray's frame, for the trim test's margin
};

// Eq. 3 from `start` with the Jacobian of Eq. 4 wrt (U, V), NEWTON_ITERATIONS steps (fewer when J is
// singular), then the outcome. Float cannot reach the twin's 1e-7 diag residual on patches small
// against the scene, so |R| <= max(u_residual diag, eps3) counts as converged, and the (s, t)
// margin grows by eps3 / |S_s| (eps3 / |S_t|): the parameter shift of a float-sized point error.
NewtonHit newton_patch(Patch P, float eps3, vec2 start) {
  float scale = u_scale;
  vec2 x = scale * start;
  mat3x2 e = evaluate_residual(P, start);
  for (int it = 0; it < NEWTON_ITERATIONS; ++it) {        // the same count on every thread: §3.3's 7
    vec2 ru = e[1] / scale, rv = e[2] / scale, r = e[0];  // Eq. 4's columns wrt U and V
    float det = ru.x * rv.y - rv.x * ru.y;
    if (!(abs(det) > 1e-14 * (abs(ru.x * rv.y) + abs(rv.x * ru.y))) || is_nan_bits(det) || abs(det) == pos_inf()) break;
    x = clamp(x - vec2(rv.y * r.x - rv.x * r.y, ru.x * r.y - ru.y * r.x) / det, -scale, 2.0 * scale);
    e = evaluate_residual(P, x / scale);
  }
  NewtonHit h;
  h.st = x / scale;
  h.e = evaluate_patch(P, h.st);
  h.t = h.e.s.z;
  vec2 m = u_edge_margin + min(vec2(eps3) / vec2(length(h.e.ss), length(h.e.st)), vec2(1e-2));
  h.converged = length(e[0]) <= max(u_residual * P.diag, eps3) && all(greaterThanEqual(h.st, -m)) &&
                all(lessThanEqual(h.st, 1.0 + m));
  return h;
}
