// Lemasson et al. §3.4 in float, included by raycast.frag: is a face point (u, v) material? The
// nearest cubic Bézier trim curve by three chords, three Newton steps of Eq. 5 for the projection,
// the side by a cross product, the dead-angle rules at junctions. CPU twin (double):
// nurbs/raycast/trim_test.cpp inside_trim (loops run with material on the left).
// u_faces: 2 texels per face: (first cubic, cubic count, 0, 0), (domain u min, max, v min, max).
// u_cubics: 3 texels per cubic: (p0, p1), (p2, p3) in (u, v), (next, prev, 0, 0) as global indices.
#include "lib_float.glsl"
#include "lib_layout.glsl"

uniform sampler2D u_faces;
uniform int u_faces_width;
uniform sampler2D u_cubics;
uniform int u_cubics_width;

struct Cubic {
  vec2 p0, p1, p2, p3;
};

vec4 cubic_texel(int i, int k) { return texelFetch(u_cubics, pow2_texel(3 * i + k, u_cubics_width), 0); }
Cubic load_cubic(int i) {
  vec4 a = cubic_texel(i, 0), b = cubic_texel(i, 1);
  return Cubic(a.xy, a.zw, b.xy, b.zw);
}

// Bernstein form, as the twin's cubic_point / cubic_d1 / cubic_d2.
vec2 cubic_point(Cubic c, float t) {
  float s = 1.0 - t;
  return s * s * s * c.p0 + 3.0 * s * s * t * c.p1 + 3.0 * s * t * t * c.p2 + t * t * t * c.p3;
}
vec2 cubic_d1(Cubic c, float t) {
  float s = 1.0 - t;
  return 3.0 * (s * s * (c.p1 - c.p0) + 2.0 * s * t * (c.p2 - c.p1) + t * t * (c.p3 - c.p2));
}
vec2 cubic_d2(Cubic c, float t) {
  return 6.0 * ((1.0 - t) * (c.p2 - 2.0 * c.p1 + c.p0) + t * (c.p3 - 2.0 * c.p2 + c.p1));
}
float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Chord q0 q1 (pieces k/3 .. (k+1)/3 of cubic i): keeps the nearest, t0 by linear interpolation.
void nearest_chord(vec2 p, vec2 q0, vec2 q1, int i, float k, inout float best_d2, inout int best, inout float t) {
  vec2 e = q1 - q0;
  float ee = dot(e, e);
  float lam = ee > 0.0 ? clamp(dot(p - q0, e) / ee, 0.0, 1.0) : 0.0;
  vec2 r = q0 + lam * e - p;
  if (dot(r, r) < best_d2) best_d2 = dot(r, r), best = i, t = (k + lam) / 3.0;
}

// Number of trim cubics of a face (0: untrimmed, no test).
int trim_count(int face) { return int(texelFetch(u_faces, pow2_texel(2 * face, u_faces_width), 0).y); }

// §3.4 on face `face` at p = (u, v). `pc` returns the trim point the answer came from (the
// projection, or p clamped to the domain), from which the caller measures how near the edge p is.
bool inside_trim(int face, vec2 p, out vec2 pc) {
  vec4 head = texelFetch(u_faces, pow2_texel(2 * face, u_faces_width), 0);
  vec4 dom = texelFetch(u_faces, pow2_texel(2 * face + 1, u_faces_width), 0);
  pc = clamp(p, dom.xz, dom.yw);
  if (p.x < dom.x || p.x > dom.y || p.y < dom.z || p.y > dom.w) return false;  // outside the domain
  int first = int(head.x), count = int(head.y), best = -1;
  float best_d2 = pos_inf(), t = 0.0;
  for (int i = first; i < first + count; ++i) {
    Cubic c = load_cubic(i);
    vec2 q1 = cubic_point(c, 1.0 / 3.0), q2 = cubic_point(c, 2.0 / 3.0);
    nearest_chord(p, c.p0, q1, i, 0.0, best_d2, best, t);
    nearest_chord(p, q1, q2, i, 1.0, best_d2, best, t);
    nearest_chord(p, q2, c.p3, i, 2.0, best_d2, best, t);
  }
  if (best < 0) return false;
  Cubic c = load_cubic(best);
  for (int it = 0; it < TRIM_ITERATIONS; ++it) {  // Eq. 5 (Schneider 1990); §3.4: 3 suffice
    vec2 r = cubic_point(c, t) - p, d1 = cubic_d1(c, t), d2 = cubic_d2(c, t);
    float den = dot(d1, d1) + dot(d2, r);
    if (!(abs(den) > 0.0)) break;
    t = clamp(t - dot(r, d1) / den, 0.0, 1.0);
  }
  pc = cubic_point(c, t);
  if (t <= 1e-9 || t >= 1.0 - 1e-9) {  // the projection sits on a junction: a possible dead angle
    vec4 link = cubic_texel(best, 2);  // (next, prev)
    Cubic a = c, b = c;
    if (t <= 1e-9)
      a = load_cubic(int(link.y));
    else
      b = load_cubic(int(link.x));
    vec2 ta = cubic_d1(a, 1.0), tb = cubic_d1(b, 0.0);
    bool la = cross2(ta, p - pc) > 0.0, lb = cross2(tb, p - pc) > 0.0;
    return cross2(ta, tb) > 0.0 ? (la && lb) : (la || lb);  // convex corner: both; concave: either
  }
  return cross2(pc - p, cubic_d1(c, t)) > 0.0;  // material on the left of the curve
}
