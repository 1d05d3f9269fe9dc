#include "nurbs/raycast/trim_test.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "nurbs/bezier_extraction.h"
#include "nurbs/curve_eval.h"

namespace nurbs::ray {
namespace {

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

using Cubic = std::array<glm::dvec2, 4>;

glm::dvec2 cubic_point(const Cubic& c, double t) {
  const double s = 1.0 - t;
  return s * s * s * c[0] + 3.0 * s * s * t * c[1] + 3.0 * s * t * t * c[2] + t * t * t * c[3];
}
glm::dvec2 cubic_d1(const Cubic& c, double t) {
  const double s = 1.0 - t;
  return 3.0 * (s * s * (c[1] - c[0]) + 2.0 * s * t * (c[2] - c[1]) + t * t * (c[3] - c[2]));
}
glm::dvec2 cubic_d2(const Cubic& c, double t) {
  return 6.0 * ((1.0 - t) * (c[2] - 2.0 * c[1] + c[0]) + t * (c[3] - 2.0 * c[2] + c[1]));
}

/// c' x c'' of a trim segment (its sign changes at inflections), 0 where c' x c'' is round-off.
double curvature_sign(const Curve2& seg, double u) {
  const auto d = curve_derivatives(seg, u, 2);
  const double k = cross2(d[1], d[2]), ref = glm::dot(d[1], d[1]) * std::sqrt(glm::dot(d[2], d[2]));
  return std::abs(k) <= 1e-9 * ref ? 0.0 : k;
}

/// Inflection parameters of one Bézier segment on [a, b]: sign changes of c' x c'' on 32 samples, bisected.
std::vector<double> inflections(const Curve2& seg, double a, double b) {
  std::vector<double> out;
  constexpr int kSamples = 32;
  double u0 = a, k0 = curvature_sign(seg, a);
  for (int i = 1; i <= kSamples; ++i) {
    const double u1 = a + (b - a) * i / kSamples, k1 = curvature_sign(seg, u1);
    if (k0 * k1 < 0.0) {
      double lo = u0, hi = u1;
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi), km = curvature_sign(seg, mid);
        (km * k0 > 0.0 ? lo : hi) = mid;
      }
      out.push_back(0.5 * (lo + hi));
    }
    if (k1 != 0.0) u0 = u1, k0 = k1;
  }
  return out;
}

/// Cubic Hermite of seg on [a, b], bisected until its 9 interior samples are within tol.
void hermite_pieces(const Curve2& seg, double a, double b, double tol, int depth, std::vector<Cubic>& out,
                    double& max_error) {
  const auto da = curve_derivatives(seg, a, 1), db = curve_derivatives(seg, b, 1);
  const double h = b - a;
  const Cubic c{da[0], da[0] + h / 3.0 * da[1], db[0] - h / 3.0 * db[1], db[0]};
  double err = 0.0;
  for (int i = 1; i <= 9; ++i)
    err = std::max(err, glm::length(cubic_point(c, i / 10.0) - curve_point(seg, a + h * i / 10.0)));
  if (err > tol && depth < 24) {
    hermite_pieces(seg, a, a + 0.5 * h, tol, depth + 1, out, max_error);
    hermite_pieces(seg, a + 0.5 * h, b, tol, depth + 1, out, max_error);
    return;
  }
  max_error = std::max(max_error, err);
  out.push_back(c);
}

double loop_area(const std::vector<Cubic>& loop) {
  double area = 0.0;
  for (const auto& c : loop)
    for (int i = 0; i < 8; ++i) area += 0.5 * cross2(cubic_point(c, i / 8.0), cubic_point(c, (i + 1) / 8.0));
  return area;
}

void append_loop(TrimCubics& out, std::vector<Cubic> loop, bool ccw) {
  if (loop.empty()) return;
  if ((loop_area(loop) > 0.0) != ccw) {  // re-orient: material on the left
    std::reverse(loop.begin(), loop.end());
    for (auto& c : loop) std::reverse(c.begin(), c.end());
  }
  const int first = static_cast<int>(out.cubics.size()), n = static_cast<int>(loop.size());
  for (int i = 0; i < n; ++i) out.cubics.push_back({loop[i], first + (i + 1) % n, first + (i + n - 1) % n});
}

}  // namespace

TrimCubics trim_cubics(const TrimmedSurface& face, double tolerance) {
  TrimCubics out;
  out.domain_u = knot_domain(face.surface.knots_u, face.surface.degree_u, face.surface.count_u);
  out.domain_v = knot_domain(face.surface.knots_v, face.surface.degree_v, face.surface.count_v);
  bool any_outer = false;
  for (const auto& loop : face.loops) {
    std::vector<Cubic> cubics;
    for (const auto& curve : loop.curves)
      for (const auto& seg : extract_bezier_segments(curve)) {
        std::vector<double> breaks{seg.range.min};
        for (double u : inflections(seg.curve, seg.range.min, seg.range.max)) breaks.push_back(u);
        breaks.push_back(seg.range.max);
        for (size_t i = 0; i + 1 < breaks.size(); ++i)
          hermite_pieces(seg.curve, breaks[i], breaks[i + 1], tolerance, 0, cubics, out.max_error);
      }
    append_loop(out, std::move(cubics), loop.outer);
    any_outer = any_outer || loop.outer;
  }
  if (!any_outer) {  // the domain rectangle is the outer boundary
    const glm::dvec2 p[4] = {{out.domain_u.min, out.domain_v.min},
                             {out.domain_u.max, out.domain_v.min},
                             {out.domain_u.max, out.domain_v.max},
                             {out.domain_u.min, out.domain_v.max}};
    std::vector<Cubic> rect;
    for (int i = 0; i < 4; ++i) {
      const glm::dvec2 a = p[i], b = p[(i + 1) % 4];
      rect.push_back({a, a + (b - a) / 3.0, a + 2.0 * (b - a) / 3.0, b});
    }
    append_loop(out, std::move(rect), true);
  }
  return out;
}

bool inside_trim(const TrimCubics& trim, glm::dvec2 p, int newton_iterations) {
  if (p.x < trim.domain_u.min || p.x > trim.domain_u.max || p.y < trim.domain_v.min || p.y > trim.domain_v.max)
    return false;
  // Nearest cubic by its three chords c(0) c(1/3) c(2/3) c(1); t0 by linear interpolation on the chord.
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity(), t = 0.0;
  for (int i = 0; i < static_cast<int>(trim.cubics.size()); ++i) {
    const Cubic& c = trim.cubics[i].p;
    glm::dvec2 q0 = c[0];
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 q1 = cubic_point(c, (k + 1) / 3.0), e = q1 - q0;
      const double ee = glm::dot(e, e);
      const double lam = ee > 0.0 ? std::clamp(glm::dot(p - q0, e) / ee, 0.0, 1.0) : 0.0;
      const glm::dvec2 r = q0 + lam * e - p;
      if (glm::dot(r, r) < best_d2) best_d2 = glm::dot(r, r), best = i, t = (k + lam) / 3.0;
      q0 = q1;
    }
  }
  if (best < 0) return false;
  const Cubic& c = trim.cubics[best].p;
  for (int it = 0; it < newton_iterations; ++it) {  // Eq. 5
    const glm::dvec2 r = cubic_point(c, t) - p, d1 = cubic_d1(c, t), d2 = cubic_d2(c, t);
    const double den = glm::dot(d1, d1) + glm::dot(d2, r);
    if (!(std::abs(den) > 0.0)) break;
    t = std::clamp(t - glm::dot(r, d1) / den, 0.0, 1.0);
  }
  const glm::dvec2 pc = cubic_point(c, t);
  constexpr double kEnd = 1e-9;  // the projection sits on a junction: a possible dead angle
  if (t <= kEnd || t >= 1.0 - kEnd) {
    const Cubic& a = t <= kEnd ? trim.cubics[trim.cubics[best].prev].p : c;
    const Cubic& b = t <= kEnd ? c : trim.cubics[trim.cubics[best].next].p;
    const glm::dvec2 ta = cubic_d1(a, 1.0), tb = cubic_d1(b, 0.0);
    const bool la = cross2(ta, p - pc) > 0.0, lb = cross2(tb, p - pc) > 0.0;
    return cross2(ta, tb) > 0.0 ? (la && lb) : (la || lb);
  }
  return cross2(pc - p, cubic_d1(c, t)) > 0.0;
}

}  // namespace nurbs::ray
