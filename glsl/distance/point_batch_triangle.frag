// Squared distance from p to triangle abc: the regions of Ericson, "Real-Time Collision Detection"
// §5.1.5 (as queries/distance/point_distance.cpp closest_on_triangle), included by point_batch.frag. In the
// edge and face regions the distance is taken to the edge's line (|ab x ap| / |ab|) or the plane
// (ap . n / |n|), not to a rebuilt closest point: in float that keeps its error a few ulp of the
// coordinates' size, where rebuilding the point from barycentric weights loses more on thin triangles.
float line_dist2(vec3 ap, vec3 ab) {
  vec3 c = cross(ab, ap);
  return dot(c, c) / dot(ab, ab);
}

float point_triangle_dist2(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return dot(ap, ap);
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return dot(bp, bp);
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 > d3) return line_dist2(ap, ab);
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return dot(cp, cp);
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 > d6) return line_dist2(ap, ac);
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) return line_dist2(bp, c - b);
  vec3 n = cross(ab, ac);
  float h = dot(ap, n);
  return h * h / dot(n, n);
}
