#include "nurbs/project_curve.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <vector>

#include "nurbs/curve_eval.h"
#include "nurbs/surface_eval.h"

namespace nurbs {
namespace {

glm::dvec2 clamp_to_domain(const Surface& s, glm::dvec2 uv) {
  const Interval u = surface_domain_u(s), v = surface_domain_v(s);
  return {std::clamp(uv.x, u.min, u.max), std::clamp(uv.y, v.min, v.max)};
}

struct Sample {
  double t;
  glm::dvec2 uv;
};

}  // namespace

glm::dvec2 closest_parameter(const Surface& s, glm::dvec3 p, glm::dvec2 start) {
  glm::dvec2 uv = clamp_to_domain(s, start);
  // Converged once a step is below 1e-13 of the domain: rounding keeps steps near 1e-16 of the
  // parameters' size, which a tighter absolute threshold never sees (50 iterations each).
  const double stop = 1e-13 * std::max(surface_domain_u(s).width(), surface_domain_v(s).width());
  for (int it = 0; it < 50; ++it) {
    const SurfaceDerivatives d = surface_derivatives(s, uv.x, uv.y);
    const glm::dvec3 r = d.s - p;
    // Jacobian of (r . Su, r . Sv) (The NURBS Book eq. 6.7).
    const double a = glm::dot(d.su, d.su) + glm::dot(r, d.suu), b = glm::dot(d.su, d.sv) + glm::dot(r, d.suv);
    const double c = glm::dot(d.sv, d.sv) + glm::dot(r, d.svv);
    const double f = glm::dot(r, d.su), g = glm::dot(r, d.sv);
    const double det = a * c - b * b;
    if (!(std::abs(det) > 0.0)) break;  // degenerate point (a pole): keep the best so far
    const glm::dvec2 next = clamp_to_domain(s, uv - glm::dvec2((c * f - b * g) / det, (a * g - b * f) / det));
    const double step = glm::length(next - uv);
    uv = next;
    if (!(step > stop)) break;
  }
  return uv;
}

glm::dvec2 closest_parameter(const Surface& s, glm::dvec3 p) {
  const Interval u = surface_domain_u(s), v = surface_domain_v(s);
  const int nu = std::min(257, 8 * (s.count_u - s.degree_u) + 1), nv = std::min(257, 8 * (s.count_v - s.degree_v) + 1);
  glm::dvec2 best{u.min, v.min};
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const glm::dvec2 q{u.min + u.width() * i / (nu - 1), v.min + v.width() * j / (nv - 1)};
      const double d = glm::length(surface_point(s, q.x, q.y) - p);
      if (d < best_d) best_d = d, best = q;
    }
  return closest_parameter(s, p, best);
}

ProjectedCurve project_curve(const Surface& s, const Curve3& c, double tolerance) {
  ProjectedCurve out;
  const Interval dom = curve_domain(c);
  // Sample parameters: 16 per non-empty knot span.
  std::vector<double> ts;
  for (size_t k = static_cast<size_t>(c.degree); k + 1 < c.knots.size() - static_cast<size_t>(c.degree); ++k) {
    const double a = c.knots[k], b = c.knots[k + 1];
    if (!(b > a)) continue;
    for (int i = 0; i < 16; ++i) ts.push_back(a + (b - a) * i / 16.0);
  }
  ts.push_back(dom.max);
  auto project = [&](double t, glm::dvec2 start, bool from_grid) {
    const glm::dvec3 p = curve_point(c, t);
    const glm::dvec2 uv = from_grid ? closest_parameter(s, p) : closest_parameter(s, p, start);
    out.distance = std::max(out.distance, glm::length(surface_point(s, uv.x, uv.y) - p));
    return Sample{t, uv};
  };
  std::vector<Sample> samples{project(ts.front(), {}, true)};
  for (size_t i = 1; i < ts.size(); ++i) {
    // Refine [previous, t] until the chord's (u, v) midpoint maps onto the curve's midpoint.
    std::vector<Sample> stack{project(ts[i], samples.back().uv, false)};
    int splits = 0;
    while (!stack.empty()) {
      const Sample a = samples.back(), b = stack.back();
      const double tm = (a.t + b.t) / 2.0;
      const glm::dvec2 mid = (a.uv + b.uv) / 2.0;
      if (splits < 4096 && glm::length(surface_point(s, mid.x, mid.y) - curve_point(c, tm)) > tolerance) {
        stack.push_back(project(tm, a.uv, false));
        ++splits;
        continue;
      }
      samples.push_back(b);
      stack.pop_back();
    }
  }
  if (!(out.distance <= tolerance)) {
    out.problem = fmt::format("lies {:.3g} from the surface (tolerance {:.3g})", out.distance, tolerance);
    return out;
  }
  Curve2 k;
  k.degree = 1;
  k.knots.push_back(samples.front().t);
  for (const Sample& q : samples) k.knots.push_back(q.t), k.points.push_back(q.uv);
  k.knots.push_back(samples.back().t);
  out.curve = std::move(k);
  return out;
}

}  // namespace nurbs
