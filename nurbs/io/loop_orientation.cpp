#include "nurbs/io/loop_orientation.h"

#include "nurbs/io/curve_utils.h"

#include <algorithm>
#include <vector>

namespace nurbs::io {

double signed_area(const TrimLoop& loop, int samples_per_curve) {
  std::vector<glm::dvec2> pts;
  for (const Curve2& c : loop.curves) {
    if (c.points.empty() || c.knots.size() != c.points.size() + static_cast<size_t>(c.degree) + 1) continue;
    const int n = std::max(samples_per_curve, 2 * static_cast<int>(c.points.size()));
    const double a = c.knots[static_cast<size_t>(c.degree)];
    const double b = c.knots[c.points.size()];
    for (int i = 0; i < n; ++i) pts.push_back(curve_point(c, a + (b - a) * i / n));  // end = next curve's start
  }
  double area = 0.0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const glm::dvec2& p = pts[i];
    const glm::dvec2& q = pts[(i + 1) % pts.size()];
    area += p.x * q.y - q.x * p.y;
  }
  return 0.5 * area;
}

bool orient_loop(TrimLoop& loop) {
  const double area = signed_area(loop);
  if (area == 0.0 || (area > 0.0) == loop.outer) return false;
  std::reverse(loop.curves.begin(), loop.curves.end());
  for (Curve2& c : loop.curves) c = reversed(c);
  return true;
}

TrimLoop domain_loop(const Surface& s) {
  const double u0 = s.knots_u[static_cast<size_t>(s.degree_u)], u1 = s.knots_u[static_cast<size_t>(s.count_u)];
  const double v0 = s.knots_v[static_cast<size_t>(s.degree_v)], v1 = s.knots_v[static_cast<size_t>(s.count_v)];
  const glm::dvec2 corners[4] = {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
  TrimLoop loop;
  loop.outer = true;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 a = corners[i], b = corners[(i + 1) % 4];
    loop.curves.push_back(to_2d(line_segment({a, 0.0}, {b, 0.0})));
  }
  return loop;
}

}  // namespace nurbs::io
