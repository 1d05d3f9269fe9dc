#include "nurbs/io/conic_arcs.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nurbs::io {
namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Unit circle arc from angle a0 over `sweep` radians (0 < sweep <= 2π), mapped by
// p -> origin + p.x * ax + p.y * ay; affine maps keep rational curves exact with the same weights.
Curve3 mapped_unit_arc(double a0, double sweep, const glm::dvec2& origin, const glm::dvec2& ax, const glm::dvec2& ay,
                       double z) {
  const double quarter = std::numbers::pi / 2.0;
  // 1e-9: a sweep of exactly 90° or 180° must not become one more segment through rounding.
  const int n = std::max(1, static_cast<int>(std::ceil(sweep / quarter - 1e-9)));
  const double delta = sweep / n;
  const double w = std::cos(delta / 2.0);
  Curve3 c;
  c.degree = 2;
  auto put = [&](double angle, double scale, double weight) {
    glm::dvec2 p = origin + (std::cos(angle) * scale) * ax + (std::sin(angle) * scale) * ay;
    c.points.emplace_back(p.x, p.y, z);
    c.weights.push_back(weight);
  };
  c.knots = {0.0, 0.0, 0.0};
  for (int i = 0; i < n; ++i) {
    const double a = a0 + i * delta;
    put(a, 1.0, 1.0);
    put(a + delta / 2.0, 1.0 / w, w);
    const double k = (i + 1) * delta;
    c.knots.insert(c.knots.end(), i + 1 < n ? 2 : 3, k);
  }
  put(a0 + sweep, 1.0, 1.0);
  return c;
}

// Counter-clockwise sweep from angle a0 to a1 in (0, 2π]; `full` forces 2π.
double ccw_sweep(double a0, double a1, bool full) {
  const double two_pi = 2.0 * std::numbers::pi;
  if (full) return two_pi;
  double s = std::fmod(a1 - a0, two_pi);
  if (s <= 0.0) s += two_pi;
  return s;
}

}  // namespace

Curve3 circle_arc(const glm::dvec2& centre, const glm::dvec2& start, const glm::dvec2& end, double z) {
  const double r = glm::length(start - centre);
  if (!(r > 0.0)) throw std::invalid_argument("circular arc has zero radius");
  // Writers print start and end of a full circle with the same digits; 1e-9 r absorbs rounding.
  const bool full = glm::length(end - start) <= 1e-9 * r;
  const double a0 = std::atan2(start.y - centre.y, start.x - centre.x);
  const double a1 = std::atan2(end.y - centre.y, end.x - centre.x);
  return mapped_unit_arc(a0, ccw_sweep(a0, a1, full), centre, {r, 0.0}, {0.0, r}, z);
}

Curve3 conic_arc(const std::array<double, 6>& k, const glm::dvec2& s, const glm::dvec2& e, double z, int form) {
  // Named copies, not a structured binding: the lambdas below capture them (clang before 16 cannot
  // capture a binding).
  const double A = k[0], B = k[1], C = k[2], D = k[3], E = k[4], F = k[5];
  const double disc = B * B - 4.0 * A * C;
  if (form == 0) form = disc < 0.0 ? 1 : (disc > 0.0 ? 2 : 3);
  auto value = [&](const glm::dvec2& p) {
    return A * p.x * p.x + B * p.x * p.y + C * p.y * p.y + D * p.x + E * p.y + F;
  };
  auto gradient = [&](const glm::dvec2& p) {
    return glm::dvec2(2.0 * A * p.x + B * p.y + D, B * p.x + 2.0 * C * p.y + E);
  };

  if (form == 1) {
    if (!(disc < 0.0)) throw std::invalid_argument("form 1 (ellipse) but B^2 - 4AC >= 0");
    // Centre: gradient = 0; then principal axes of the quadratic form [[A, B/2], [B/2, C]].
    const double det = 4.0 * A * C - B * B;
    const glm::dvec2 c((B * E - 2.0 * C * D) / det, (B * D - 2.0 * A * E) / det);
    const double fc = value(c);
    const double theta = 0.5 * std::atan2(B, A - C);
    const glm::dvec2 e1(std::cos(theta), std::sin(theta));
    const glm::dvec2 e2(-e1.y, e1.x);  // e1 rotated +90°: the map keeps counter-clockwise
    const double l1 = A * e1.x * e1.x + B * e1.x * e1.y + C * e1.y * e1.y;
    const double l2 = A * e2.x * e2.x + B * e2.x * e2.y + C * e2.y * e2.y;
    const double a2 = -fc / l1;
    const double b2 = -fc / l2;
    if (!(a2 > 0.0) || !(b2 > 0.0)) throw std::invalid_argument("conic coefficients describe no real ellipse");
    const double a = std::sqrt(a2);
    const double b = std::sqrt(b2);
    auto angle = [&](const glm::dvec2& p) { return std::atan2(glm::dot(p - c, e2) / b, glm::dot(p - c, e1) / a); };
    const double a0 = angle(s);
    const bool full = glm::length(e - s) <= 1e-9 * std::max(a, b);  // as for circles
    return mapped_unit_arc(a0, ccw_sweep(a0, angle(e), full), c, a * e1, b * e2, z);
  }
  if (form != 2 && form != 3) throw std::invalid_argument("conic form " + std::to_string(form) + " is not 1, 2 or 3");
  // One rational quadratic Bézier: P1 = intersection of the end tangents.
  const glm::dvec2 gs = gradient(s), ge = gradient(e);
  const glm::dvec2 t0(-gs.y, gs.x), t1(-ge.y, ge.x);
  const double denom = cross(t0, t1);
  if (std::abs(denom) <= 1e-14 * glm::length(t0) * glm::length(t1))
    throw std::invalid_argument("conic arc end tangents are parallel (degenerate arc)");
  const glm::dvec2 p1 = s + (cross(e - s, t1) / denom) * t0;
  // The Bézier midpoint is M + w/(1+w) (P1 - M), M the chord midpoint: find where the segment M->P1
  // meets the conic, F(M + σ d) = F(M) + σ ∇F(M)·d + σ² Q(d) = 0, then w = σ / (1 - σ).
  const glm::dvec2 m = 0.5 * (s + e), d = p1 - m;
  const double q0 = value(m), q1 = glm::dot(gradient(m), d), q2 = A * d.x * d.x + B * d.x * d.y + C * d.y * d.y;
  double sigma = -1.0;
  if (std::abs(q2) <= 1e-14 * (std::abs(q1) + std::abs(q0))) {
    if (q1 != 0.0) sigma = -q0 / q1;
  } else {
    const double dd = q1 * q1 - 4.0 * q2 * q0;
    if (dd >= 0.0) {
      const double r1 = (-q1 - std::sqrt(dd)) / (2.0 * q2), r2 = (-q1 + std::sqrt(dd)) / (2.0 * q2);
      sigma = (r1 > 0.0 && r1 < 1.0) ? r1 : r2;
    }
  }
  if (!(sigma > 0.0 && sigma < 1.0))
    throw std::invalid_argument("conic arc end points do not lie on one branch of the conic");
  Curve3 c;
  c.degree = 2;
  c.knots = {0.0, 0.0, 0.0, 1.0, 1.0, 1.0};
  c.points = {{s.x, s.y, z}, {p1.x, p1.y, z}, {e.x, e.y, z}};
  c.weights = {1.0, sigma / (1.0 - sigma), 1.0};
  return c;
}

}  // namespace nurbs::io
