// Triangle-triangle distance in double (the CPU end of the clearance query, clearance.h): the
// minimum over the six vertex-triangle and nine edge-edge closest pairs, which is the distance of
// two disjoint triangles; when an edge of one crosses the other, the distance is 0 there.
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "queries/distance/clearance.h"
#include "queries/distance/point_distance.h"

namespace queries {

// Ericson, "Real-Time Collision Detection", §5.1.9.
double segment_distance(glm::dvec3 p1, glm::dvec3 q1, glm::dvec3 p2, glm::dvec3 q2, double& s, double& t) {
  const glm::dvec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
  if (a <= 1e-300 && e <= 1e-300) {
    s = t = 0;
  } else if (a <= 1e-300) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = glm::dot(d1, r);
    if (e <= 1e-300) {
      t = 0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = glm::dot(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return glm::length((p1 + s * d1) - (p2 + t * d2));
}

namespace {

/// Where segment pq crosses triangle abc (Möller-Trumbore), as the segment parameter; false if not.
bool segment_hits_triangle(glm::dvec3 p, glm::dvec3 q, const glm::dvec3 tri[3], double& at, glm::dvec3& w) {
  const glm::dvec3 d = q - p, e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
  const glm::dvec3 h = glm::cross(d, e2);
  const double det = glm::dot(e1, h);
  // Parallel to the plane or in it: no crossing. |det| <= |d| |e1| |e2|, and in the plane rounding
  // leaves it near 1e-16 of that, with u, v and the crossing meaningless (a segment 333 away taken
  // to cross); the closest pairs of ends and edges give the distance then, 0 where they meet.
  if (!(std::abs(det) > 1e-12 * glm::length(d) * glm::length(e1) * glm::length(e2))) return false;
  const glm::dvec3 sv = p - tri[0];
  const double u = glm::dot(sv, h) / det;
  if (u < 0 || u > 1) return false;
  const glm::dvec3 qv = glm::cross(sv, e1);
  const double v = glm::dot(d, qv) / det;
  if (v < 0 || u + v > 1) return false;
  at = glm::dot(e2, qv) / det;
  w = {1 - u - v, u, v};
  return at >= 0 && at <= 1;
}

/// Whether the points s[0..2] lie strictly on one side of the plane of triangle o, beyond the
/// rounding of the test (a degenerate o has no plane: false).
bool strictly_one_side(const glm::dvec3 s[3], const glm::dvec3 o[3]) {
  const glm::dvec3 n = glm::cross(o[1] - o[0], o[2] - o[0]);
  double d[3], far = 0.0;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 r = s[k] - o[0];
    d[k] = glm::dot(n, r);
    far = std::max(far, glm::dot(r, r));
  }
  const double margin = 1e-12 * std::sqrt(glm::dot(n, n) * far);  // |n| |r| bounds each |d|
  return margin > 0.0 &&
         ((d[0] > margin && d[1] > margin && d[2] > margin) || (d[0] < -margin && d[1] < -margin && d[2] < -margin));
}

}  // namespace

double segment_triangle_distance(glm::dvec3 p, glm::dvec3 q, const glm::dvec3 tri[3], double& s, glm::dvec3& w) {
  // Crossing: 0 there. Else the closest pair has an end of the segment or an edge of the triangle.
  if (segment_hits_triangle(p, q, tri, s, w)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (int end = 0; end < 2; ++end) {
    glm::dvec3 wt;
    const glm::dvec3 x = end == 0 ? p : q;
    const double d = glm::length(closest_on_triangle(x, tri[0], tri[1], tri[2], wt) - x);
    if (d < best) best = d, s = double(end), w = wt;
  }
  for (int k = 0; k < 3; ++k) {
    double a, b;
    const double d = segment_distance(p, q, tri[k], tri[(k + 1) % 3], a, b);
    if (d < best) {
      best = d, s = a;
      w = glm::dvec3(0.0);
      w[k] = 1.0 - b;
      w[(k + 1) % 3] = b;
    }
  }
  return best;
}

double triangle_distance(const glm::dvec3 a[3], const glm::dvec3 b[3], glm::dvec3& pa, glm::dvec3& pb, glm::dvec3& wa,
                         glm::dvec3& wb) {
  double best = std::numeric_limits<double>::infinity();
  auto unit = [](int k) { return glm::dvec3(k == 0, k == 1, k == 2); };
  for (int side = 0; side < 2; ++side) {
    const glm::dvec3* s = side == 0 ? a : b;
    const glm::dvec3* o = side == 0 ? b : a;
    // No edge of s can cross o when all of s lies strictly on one side of o's plane.
    const bool apart = strictly_one_side(s, o);
    for (int k = 0; k < 3; ++k) {
      // An edge of one crossing the other: distance 0 at the crossing.
      double at;
      glm::dvec3 w;
      if (!apart && segment_hits_triangle(s[k], s[(k + 1) % 3], o, at, w)) {
        const glm::dvec3 x = s[k] + at * (s[(k + 1) % 3] - s[k]);
        const glm::dvec3 ws = (1 - at) * unit(k) + at * unit((k + 1) % 3);
        pa = pb = x;
        wa = side == 0 ? ws : w;
        wb = side == 0 ? w : ws;
        return 0.0;
      }
      // Vertex k of one to the other triangle.
      const glm::dvec3 q = closest_on_triangle(s[k], o[0], o[1], o[2], w);
      const double dist = glm::length(q - s[k]);
      if (dist < best) {
        best = dist;
        pa = side == 0 ? s[k] : q;
        pb = side == 0 ? q : s[k];
        wa = side == 0 ? unit(k) : w;
        wb = side == 0 ? w : unit(k);
      }
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s, t;
      const double dist = segment_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], s, t);
      if (dist < best) {
        best = dist;
        pa = a[i] + s * (a[(i + 1) % 3] - a[i]);
        pb = b[j] + t * (b[(j + 1) % 3] - b[j]);
        wa = (1 - s) * unit(i) + s * unit((i + 1) % 3);
        wb = (1 - t) * unit(j) + t * unit((j + 1) % 3);
      }
    }
  return best;
}

}  // namespace queries
