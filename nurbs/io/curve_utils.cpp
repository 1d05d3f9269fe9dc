#include "nurbs/io/curve_utils.h"

#include <algorithm>
#include <vector>

namespace nurbs::io {

glm::dvec2 curve_point(const Curve2& c, double t) {
  const int p = c.degree;
  const int n = static_cast<int>(c.points.size());
  t = std::clamp(t, c.knots[static_cast<size_t>(p)], c.knots[static_cast<size_t>(n)]);
  // Span k with knots[k] <= t < knots[k+1], kept inside [p, n-1] so t = end uses the last span.
  int k = static_cast<int>(std::upper_bound(c.knots.begin(), c.knots.end(), t) - c.knots.begin()) - 1;
  k = std::clamp(k, p, n - 1);
  std::vector<glm::dvec3> d(static_cast<size_t>(p + 1));
  for (int j = 0; j <= p; ++j) {
    const size_t idx = static_cast<size_t>(k - p + j);
    const double w = c.weights.empty() ? 1.0 : c.weights[idx];
    d[static_cast<size_t>(j)] = glm::dvec3(c.points[idx] * w, w);
  }
  for (int r = 1; r <= p; ++r) {
    for (int j = p; j >= r; --j) {
      const double lo = c.knots[static_cast<size_t>(k - p + j)];
      const double hi = c.knots[static_cast<size_t>(k + 1 + j - r)];
      const double a = hi > lo ? (t - lo) / (hi - lo) : 0.0;
      d[static_cast<size_t>(j)] = (1.0 - a) * d[static_cast<size_t>(j - 1)] + a * d[static_cast<size_t>(j)];
    }
  }
  const glm::dvec3& h = d[static_cast<size_t>(p)];
  return glm::dvec2(h.x, h.y) / h.z;
}

Curve2 to_2d(const Curve3& c) {
  Curve2 r;
  r.degree = c.degree;
  r.knots = c.knots;
  r.weights = c.weights;
  r.points.reserve(c.points.size());
  for (const auto& q : c.points) r.points.emplace_back(q.x, q.y);
  return r;
}

Curve3 to_3d(const Curve2& c) {
  Curve3 r;
  r.degree = c.degree;
  r.knots = c.knots;
  r.weights = c.weights;
  r.points.reserve(c.points.size());
  for (const auto& q : c.points) r.points.emplace_back(q.x, q.y, 0.0);
  return r;
}

void transform_points(Curve3& c, const glm::dmat4& m) {
  for (auto& q : c.points) q = glm::dvec3(m * glm::dvec4(q, 1.0));
}

Curve3 line_segment(const glm::dvec3& a, const glm::dvec3& b) {
  Curve3 c;
  c.degree = 1;
  c.knots = {0.0, 0.0, 1.0, 1.0};
  c.points = {a, b};
  return c;
}

}  // namespace nurbs::io
