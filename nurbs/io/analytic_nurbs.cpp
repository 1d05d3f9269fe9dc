// Exact rational NURBS of the analytic surfaces: rational quadratic arcs in every angular direction
// (The NURBS Book §7.3) and surfaces of revolution as the tensor product of a profile and those
// arcs (§8.5).
#include "nurbs/io/analytic_nurbs.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <numbers>

namespace nurbs::io {
namespace {

// Rational quadratic arcs of the unit circle from `start` over `sweep` radians, each at most 90
// degrees: control points (cos, sin) at the arc ends, the middle ones at 1 / cos(h / 2) with weight
// cos(h / 2); knot k (doubled inside) at start + k h, so the parameter equals the angle at the knots.
struct UnitArcs {
  std::vector<double> knots;
  std::vector<glm::dvec2> points;
  std::vector<double> weights;
};

int arc_count(double sweep) { return std::max(1, static_cast<int>(std::ceil(sweep / (std::numbers::pi / 2) - 1e-9))); }

UnitArcs unit_arcs(double start, double sweep) {
  const int n = arc_count(sweep);
  const double h = sweep / n, w = std::cos(h / 2);
  UnitArcs a;
  a.knots = {start, start, start};
  for (int k = 0; k < n; ++k) {
    const double a0 = start + k * h, am = a0 + h / 2;
    a.points.emplace_back(std::cos(a0), std::sin(a0));
    a.weights.push_back(1.0);
    a.points.push_back(glm::dvec2(std::cos(am), std::sin(am)) / w);
    a.weights.push_back(w);
    const double knot = k + 1 == n ? start + sweep : start + (k + 1) * h;
    a.knots.insert(a.knots.end(), k + 1 == n ? 3 : 2, knot);
  }
  a.points.emplace_back(std::cos(start + sweep), std::sin(start + sweep));
  a.weights.push_back(1.0);
  return a;
}

}  // namespace

ParameterAxis angular_axis(double scale, double x0, double x1) {
  ParameterAxis axis;
  axis.angular = true;
  axis.scale = scale;
  axis.start = scale * x0;
  axis.sweep = scale * (x1 - x0);
  axis.arcs = arc_count(axis.sweep);
  return axis;
}

// The arc of the circle centre + rho (cos a e1 + sin a e2), a in [a0, a0 + sweep].
Curve3 circle_arc(glm::dvec3 centre, glm::dvec3 e1, glm::dvec3 e2, double rho, double a0, double sweep) {
  const UnitArcs a = unit_arcs(a0, sweep);
  Curve3 c;
  c.degree = 2;
  c.knots = a.knots;
  c.weights = a.weights;
  for (const glm::dvec2& q : a.points) c.points.push_back(centre + rho * (q.x * e1 + q.y * e2));
  return c;
}

Surface plane_patch(glm::dvec3 origin, glm::dvec3 x, glm::dvec3 y, glm::dvec2 lo, glm::dvec2 hi) {
  Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = {lo.x, lo.x, hi.x, hi.x};
  s.knots_v = {lo.y, lo.y, hi.y, hi.y};
  for (double v : {lo.y, hi.y})
    for (double u : {lo.x, hi.x}) s.points.push_back(origin + u * x + v * y);
  return s;
}

Surface extrude(const Curve3& c, glm::dvec3 d0, glm::dvec3 d1, double v0, double v1) {
  Surface s;
  s.degree_u = c.degree;
  s.degree_v = 1;
  s.count_u = static_cast<int>(c.points.size());
  s.count_v = 2;
  s.knots_u = c.knots;
  s.knots_v = {v0, v0, v1, v1};
  for (const glm::dvec3& d : {d0, d1})
    for (const glm::dvec3& q : c.points) s.points.push_back(q + d);
  if (c.rational()) {
    s.weights = c.weights;
    s.weights.insert(s.weights.end(), c.weights.begin(), c.weights.end());
  }
  return s;
}

Curve3 segment(glm::dvec3 a, glm::dvec3 b, double t0, double t1) {
  Curve3 c;
  c.degree = 1;
  c.knots = {t0, t0, t1, t1};
  c.points = {a, b};
  return c;
}

// The profile turned about the axis through `origin` along unit `dir` by the angles a0..a0 + sweep
// (right-handed): P - origin = h dir + r gives O + h dir + cos a r + sin a (dir x r), exact for
// rational profiles as the tensor product with the arcs (weights multiply). The angle runs along
// u when `angle_in_u`, else along v.
Surface revolve(const Curve3& profile, glm::dvec3 origin, glm::dvec3 dir, double a0, double sweep, bool angle_in_u) {
  const UnitArcs a = unit_arcs(a0, sweep);
  const int na = static_cast<int>(a.points.size()), np = static_cast<int>(profile.points.size());
  Surface s;
  s.degree_u = angle_in_u ? 2 : profile.degree;
  s.degree_v = angle_in_u ? profile.degree : 2;
  s.count_u = angle_in_u ? na : np;
  s.count_v = angle_in_u ? np : na;
  s.knots_u = angle_in_u ? a.knots : profile.knots;
  s.knots_v = angle_in_u ? profile.knots : a.knots;
  s.points.resize(static_cast<size_t>(na) * np);
  s.weights.resize(s.points.size());
  for (int j = 0; j < np; ++j) {
    const glm::dvec3 d = profile.points[static_cast<size_t>(j)] - origin;
    const glm::dvec3 along = glm::dot(d, dir) * dir, r = d - along, r90 = glm::cross(dir, r);
    const double wp = profile.rational() ? profile.weights[static_cast<size_t>(j)] : 1.0;
    for (int i = 0; i < na; ++i) {
      const glm::dvec2 q = a.points[static_cast<size_t>(i)];
      const size_t k = angle_in_u ? static_cast<size_t>(j) * na + i : static_cast<size_t>(i) * np + j;
      s.points[k] = origin + along + q.x * r + q.y * r90;
      s.weights[k] = a.weights[static_cast<size_t>(i)] * wp;
    }
  }
  return s;
}

// OpenCASCADE's gp_Ax2(P, V) choice of X for an axis without reference direction (form 0): one
// coordinate zeroed, the smallest of |V|'s.
glm::dvec3 default_x(glm::dvec3 v) {
  const glm::dvec3 m = glm::abs(v);
  glm::dvec3 d;
  if (m.y <= m.x && m.y <= m.z)
    d = m.x > m.z ? glm::dvec3(-v.z, 0, v.x) : glm::dvec3(v.z, 0, -v.x);
  else if (m.x <= m.y && m.x <= m.z)
    d = m.y > m.z ? glm::dvec3(0, -v.z, v.y) : glm::dvec3(0, v.z, -v.y);
  else
    d = m.x > m.y ? glm::dvec3(-v.y, v.x, 0) : glm::dvec3(v.y, -v.x, 0);
  return glm::normalize(d);
}

double ParameterAxis::operator()(double x) const {
  if (!angular) return offset + scale * x;
  if (!std::isfinite(x)) return x;
  const double h = sweep / arcs, a = scale * x - start;
  const int k = std::clamp(static_cast<int>(std::floor(a / h)), 0, arcs - 1);
  const double sigma = std::tan(0.5 * (a - (k + 0.5) * h)) / std::tan(0.25 * h);
  return start + (k + 0.5 * (sigma + 1.0)) * h;
}

double ParameterAxis::inverse(double s) const {
  if (!angular) return (s - offset) / scale;
  if (!std::isfinite(s)) return s;
  const double h = sweep / arcs, q = (s - start) / h;
  const int k = std::clamp(static_cast<int>(std::floor(q)), 0, arcs - 1);
  const double sigma = 2.0 * (q - k) - 1.0;
  return (start + (k + 0.5) * h + 2.0 * std::atan(sigma * std::tan(0.25 * h))) / scale;
}

}  // namespace nurbs::io
