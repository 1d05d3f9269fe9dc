#include "nurbs/io/curve_utils.h"

namespace nurbs::io {

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
