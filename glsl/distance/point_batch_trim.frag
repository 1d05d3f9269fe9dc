// Trimmed cells of the batched point projection (Krishnamurthy et al. §5.3, beyond the paper's
// corner test), included by point_batch.frag: the distance from q to the material part of a cell's
// two triangles, so that the descent ends at the closest material point and not at a trimmed one.
// The closest material point of a triangle is its closest point when that is material, else a
// point of a trim-edge piece inside it (the distance is convex on a triangle); the cell's edges
// are its neighbours'. The CPU twin is BatchGeometry::trimmed_cell_distance (point_batch_cells.cpp),
// the per-cell data PointBatch::upload_trim_cells (point_batch_cells.cpp).
uniform sampler2D u_trim_cell;  // R32F per atlas texel: 0, or 1 + the index of its cell's header
uniform sampler2D u_trim_head;  // RGBA32F: (first segment, crossing segments, pieces, reference side)
uniform sampler2D u_trim_segs;  // RGBA32F: (s0, t0, s1, t1) in unit-cell coordinates
uniform int u_trim_width;       // width of u_trim_head and u_trim_segs

// The point of known side (is_material, in double on the CPU): away from the cell's corners,
// edges and diagonal, where trim edges often run.
const vec2 kTrimRef = vec2(0.3819660113, 0.6180339887);

vec4 trim_fetch(sampler2D t, int i) { return texelFetch(t, ivec2(i % u_trim_width, i / u_trim_width), 0); }

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Whether the segment from the reference point to x (unit-cell coordinates) crosses edge s. An
// edge's ends count half-open on the segment's line (> 0 or not), so a vertex shared by two edges
// of a loop counts once. x's side: the reference's, flipped at each crossing.
bool trim_crosses(vec2 x, vec4 s) {
  vec2 rx = x - kTrimRef;
  if ((cross2(rx, s.xy - kTrimRef) > 0.0) == (cross2(rx, s.zw - kTrimRef) > 0.0)) return false;
  vec2 e = s.zw - s.xy;
  return (cross2(e, kTrimRef - s.xy) > 0.0) != (cross2(e, x - s.xy) > 0.0);
}

// Barycentric weights of the closest point of triangle abc to p (the regions of
// point_batch_triangle.frag; queries/distance/point_distance.cpp closest_on_triangle).
vec3 triangle_weights(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return vec3(1.0, 0.0, 0.0);
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return vec3(0.0, 1.0, 0.0);
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 > d3) {
    float v = d1 / (d1 - d3);
    return vec3(1.0 - v, v, 0.0);
  }
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return vec3(0.0, 0.0, 1.0);
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 > d6) {
    float w = d2 / (d2 - d6);
    return vec3(1.0 - w, 0.0, w);
  }
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return vec3(0.0, 1.0 - w, w);
  }
  float denom = 1.0 / (va + vb + vc);
  float v = vb * denom, w = vc * denom;
  return vec3(1.0 - v - w, v, w);
}

float segment_dist2(vec3 p, vec3 a, vec3 b) {
  vec3 d = b - a;
  float l = dot(d, d);
  vec3 e = a + (l > 0.0 ? clamp(dot(p - a, d) / l, 0.0, 1.0) : 0.0) * d - p;
  return dot(e, e);
}

// (s, t) in the unit cell -> its triangle: (0, 1, 3) where s >= t, (0, 3, 2) where t > s (the split of
// queries/distance/cell_triangles.h, the CPU twins' too).
vec3 on_cell(vec2 st, bool lower, vec3 c0, vec3 c1, vec3 c2, vec3 c3) {
  return lower ? c0 + st.x * (c1 - c0) + st.y * (c3 - c1) : c0 + st.y * (c2 - c0) + st.x * (c3 - c2);
}

// Segment k of a cell's list: a crossing segment flips the sides m0, m1 of the two triangles'
// closest points x0, x1; a piece lowers d2 by its distance.
void trim_segment(int k, vec4 head, vec2 x0, vec2 x1, inout bool m0, inout bool m1, inout float d2, vec3 q, vec3 c0,
                  vec3 c1, vec3 c2, vec3 c3) {
  if (k >= int(head.y) + int(head.z)) return;
  vec4 s = trim_fetch(u_trim_segs, int(head.x) + k);
  if (k < int(head.y)) {
    m0 = m0 != trim_crosses(x0, s);
    m1 = m1 != trim_crosses(x1, s);
    return;
  }
  bool lower = s.x + s.z >= s.y + s.w;
  d2 = min(d2, segment_dist2(q, on_cell(s.xy, lower, c0, c1, c2, c3), on_cell(s.zw, lower, c0, c1, c2, c3)));
}

// Squared distance from q to the material part of the cell with corners c0..c3 (c_k at
// (u_{i + (k & 1)}, v_{j + (k >> 1)})); +inf when it holds no material. The triangles' closest
// points in unit-cell coordinates: (w1 + w2, w2) on (0, 1, 3), (w1, w1 + w2) on (0, 3, 2).
float trimmed_cell_dist2(vec3 q, vec3 c0, vec3 c1, vec3 c2, vec3 c3, int header) {
  vec4 head = trim_fetch(u_trim_head, header);
  vec3 w0 = triangle_weights(q, c0, c1, c3), w1 = triangle_weights(q, c0, c3, c2);
  vec2 x0 = vec2(w0.y + w0.z, w0.z), x1 = vec2(w1.y, w1.y + w1.z);
  bool m0 = head.w > 0.5, m1 = m0;
  float d2 = 1.0 / 0.0;
  // Eight segments an iteration: llvmpipe ends an invocation after 65535 loop iterations in all
  // (point_batch.frag), and cells of finely flattened trims hold dozens.
  for (int k = 0; k < int(head.y) + int(head.z); k += 8) {
    trim_segment(k, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 1, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 2, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 3, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 4, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 5, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 6, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
    trim_segment(k + 7, head, x0, x1, m0, m1, d2, q, c0, c1, c2, c3);
  }
  if (m0) d2 = min(d2, point_triangle_dist2(q, c0, c1, c3));
  if (m1) d2 = min(d2, point_triangle_dist2(q, c0, c3, c2));
  return d2;
}
