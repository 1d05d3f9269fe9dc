// STEP B-rep geometry to nurbs::Model: the instances of a parsed Part 21 file (step_file.h) read as
// ISO 10303-42 geometry and topology, placed by the assembly structure of AP203 / AP214 / AP242.
#include "nurbs/io/step_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/io/analytic_nurbs.h"
#include "nurbs/io/conic_arcs.h"
#include "nurbs/io/curve_utils.h"
#include "nurbs/io/iges_faces.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/step_file.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/project_curve.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "nurbs/validate.h"

namespace nurbs::io {
namespace {

constexpr double kPi = std::numbers::pi;
// Reference chains (a trimmed curve of a trimmed curve ..., assemblies in assemblies) deeper than
// this are refused: CAD files nest a handful of levels.
constexpr int kMaxDepth = 32;
// Placed instances of solids in all: an assembly naming a sub-assembly twice at every level would
// otherwise multiply without bound.
constexpr size_t kMaxInstances = 100'000;

using Kind = StepValue::Kind;

struct Frame {
  glm::dvec3 o{0.0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
};

double control_box_diagonal(const Curve3& c) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec3& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return glm::length(hi - lo);
}

glm::dmat4 frame_matrix(const Frame& f) {
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(f.x, 0.0);
  m[1] = glm::dvec4(f.y, 0.0);
  m[2] = glm::dvec4(f.z, 0.0);
  m[3] = glm::dvec4(f.o, 1.0);
  return m;
}

double wrap_near(double a, double ref) { return a + 2 * kPi * std::round((ref - a) / (2 * kPi)); }

// An analytic surface by its STEP parameters ("natural" (u, v): angles in radians, lengths in file
// units, curve parameters), with the inverse map from a point on it.
struct Analytic {
  enum Type { Plane, Cylinder, Cone, Sphere, Torus, Revolution, Extrusion } type = Plane;
  Frame f;
  double r = 0.0, r2 = 0.0, tan_angle = 0.0;
  Curve3 curve;         // revolution: profile; extrusion: directrix
  Curve3 flat;          // extrusion: the directrix projected along dir
  double accept = 0.0;  // a curve point this near a point of the surface is its parameter
  bool line = false;    // the curve is a LINE: unbounded, its parameter in closed form

  // The swept curve's point at t (a LINE's beyond its unit segment too).
  [[nodiscard]] glm::dvec3 curve_at(double t) const {
    return line ? curve.points[0] + t * (curve.points[1] - curve.points[0]) : curve_point(curve, t);
  }

  // The parameter of the foot of p on the line through the segment c (LINE: point + t vector).
  static double line_t(const Curve3& c, glm::dvec3 p) {
    const glm::dvec3 d = c.points[1] - c.points[0];
    const double dd = glm::dot(d, d);
    return dd > 0 ? glm::dot(p - c.points[0], d) / dd : 0.0;
  }
  double phi0 = 0.0;    // revolution: angle of the profile about the axis
  glm::dvec3 dir{0.0};  // extrusion: unit direction
  Interval t_range{0, 1};

  [[nodiscard]] bool u_angular() const { return type != Plane && type != Extrusion; }
  [[nodiscard]] bool v_angular() const { return type == Torus || type == Sphere; }
  [[nodiscard]] bool v_periodic() const { return type == Torus; }

  [[nodiscard]] glm::dvec3 point(glm::dvec2 uv) const {
    const double cu = std::cos(uv.x), su = std::sin(uv.x);
    switch (type) {
      case Plane:
        return f.o + uv.x * f.x + uv.y * f.y;
      case Cylinder:
        return f.o + r * (cu * f.x + su * f.y) + uv.y * f.z;
      case Cone:
        return f.o + (r + uv.y * tan_angle) * (cu * f.x + su * f.y) + uv.y * f.z;
      case Sphere:
        return f.o + r * std::cos(uv.y) * (cu * f.x + su * f.y) + r * std::sin(uv.y) * f.z;
      case Torus:
        return f.o + (r + r2 * std::cos(uv.y)) * (cu * f.x + su * f.y) + r2 * std::sin(uv.y) * f.z;
      case Revolution: {
        const glm::dvec3 d = curve_at(uv.y) - f.o;
        const glm::dvec3 along = glm::dot(d, f.z) * f.z, rr = d - along;
        return f.o + along + cu * rr + su * glm::cross(f.z, rr);
      }
      case Extrusion:
        return curve_at(uv.x) + uv.y * dir;
    }
    return {};
  }

  // Newton's method on (C(t) - p) . C'(t) = 0 from t, clamped to the range.
  static double newton_t(const Curve3& c, glm::dvec3 p, Interval range, double t) {
    for (int it = 0; it < 30; ++it) {
      const auto d = curve_derivatives(c, t, 2);
      const glm::dvec3 e = d[0] - p;
      const double f1 = glm::dot(e, d[1]), f2 = glm::dot(d[1], d[1]) + glm::dot(e, d[2]);
      if (!(std::abs(f2) > 0)) break;
      const double nt = std::clamp(t - f1 / f2, range.min, range.max);
      const bool done = std::abs(nt - t) < 1e-15 * (1 + range.width());
      t = nt;
      if (done) break;
    }
    return t;
  }

  // Parameter t of the curve point nearest p: Newton from `start` when it lands within `accept` of
  // p, else from the nearest of 16 samples per knot span.
  static double nearest_t(const Curve3& c, glm::dvec3 p, Interval range, std::optional<double> start = std::nullopt,
                          double accept = 0.0) {
    if (start && std::isfinite(*start)) {
      const double t = newton_t(c, p, range, std::clamp(*start, range.min, range.max));
      if (glm::length(curve_point(c, t) - p) <= accept) return t;
    }
    double best = range.min, best_d = std::numeric_limits<double>::infinity();
    const int n = 16 * std::max<int>(1, static_cast<int>(c.points.size()) - c.degree);
    for (int i = 0; i <= n; ++i) {
      const double t = range.min + range.width() * i / n;
      const double d = glm::length(curve_point(c, t) - p);
      if (d < best_d) best_d = d, best = t;
    }
    return newton_t(c, p, range, best);
  }

  // Natural (u, v) of p; angles taken on the branch nearest `prev` (when given). NaN u on the axis.
  [[nodiscard]] glm::dvec2 natural(glm::dvec3 p, const std::optional<glm::dvec2>& prev) const {
    const glm::dvec3 d = p - f.o;
    const double x = glm::dot(d, f.x), y = glm::dot(d, f.y), z = glm::dot(d, f.z);
    glm::dvec2 uv;
    const double rho = std::hypot(x, y);
    switch (type) {
      case Plane:
        return {x, y};
      case Extrusion: {
        // The directrix point whose line along dir passes nearest p: nearest in the plane normal to dir.
        const double t = line ? line_t(flat, p - glm::dot(p, dir) * dir)
                              : nearest_t(flat, p - glm::dot(p, dir) * dir, t_range,
                                          prev ? std::optional(prev->x) : std::nullopt, accept);
        return {t, glm::dot(p - curve_at(t), dir)};
      }
      case Cylinder:
        uv = {std::atan2(y, x), z};
        break;
      case Cone:
        // Beyond the apex the radius r + z tan(angle) is negative (the other nappe, where a cone
        // placed at its apex, r = 0, keeps its faces when its axis points away from them): the
        // angle turns by half a turn.
        uv = r + z * tan_angle < 0.0 ? glm::dvec2(std::atan2(-y, -x), z) : glm::dvec2(std::atan2(y, x), z);
        break;
      case Sphere:
        uv = {std::atan2(y, x), std::atan2(z, rho)};
        break;
      case Torus:
        uv = {std::atan2(y, x), std::atan2(z, rho - r)};
        break;
      case Revolution: {
        const double u = std::atan2(y, x) - phi0;
        // Turn p back by u into the profile's half-plane, then the nearest profile point.
        const glm::dvec3 along = z * f.z, rr = d - along;
        const glm::dvec3 back = f.o + along + std::cos(-u) * rr + std::sin(-u) * glm::cross(f.z, rr);
        uv = {u, line ? line_t(curve, back)
                      : nearest_t(curve, back, t_range, prev ? std::optional(prev->y) : std::nullopt, accept)};
        break;
      }
    }
    // On the axis within what the file's digits carry (its points are written to about 12 significant
    // figures; an apex reached along a LINE from another point lands 1e-10 of its distance from the
    // origin off it): the angle there is noise.
    if (rho <= 1e-9 * (glm::length(p) + r)) uv.x = std::numeric_limits<double>::quiet_NaN();
    if (prev) {
      if (std::isfinite(uv.x) && std::isfinite(prev->x)) uv.x = wrap_near(uv.x, prev->x);
      if (v_periodic() && std::isfinite(prev->y)) uv.y = wrap_near(uv.y, prev->y);
    }
    return uv;
  }

  // The curve on [a, b] within its domain (the same parameters).
  Curve3 part(const Curve3& c, double a, double b) const {
    if (line)
      return segment(c.points[0] + a * (c.points[1] - c.points[0]), c.points[0] + b * (c.points[1] - c.points[0]), a,
                     b);
    const Interval d = curve_domain(c);
    a = std::max(a, d.min), b = std::min(b, d.max);
    return a <= d.min && b >= d.max ? c : restrict_curve(c, a, b);
  }

  // Exact NURBS over [lo, hi] of the natural parameters, with the map natural -> NURBS parameters.
  [[nodiscard]] AnalyticSurface build(glm::dvec2 lo, glm::dvec2 hi) const {
    AnalyticSurface out;
    const double du = hi.x - lo.x, dv = hi.y - lo.y;
    switch (type) {
      case Plane:
        out.surface = plane_patch(f.o, f.x, f.y, lo, hi);
        return out;
      case Cylinder:
      case Cone: {
        const Curve3 profile = segment(point({0.0, lo.y}), point({0.0, hi.y}), lo.y, hi.y);
        out.surface = revolve(profile, f.o, f.z, lo.x, du, true);
        out.u = angular_axis(1.0, lo.x, hi.x);
        return out;
      }
      case Sphere: {
        out.surface = revolve(circle_arc(f.o, f.x, f.z, r, lo.y, dv), f.o, f.z, lo.x, du, true);
        out.u = angular_axis(1.0, lo.x, hi.x);
        out.v = angular_axis(1.0, lo.y, hi.y);
        return out;
      }
      case Torus: {
        out.surface = revolve(circle_arc(f.o + r * f.x, f.x, f.z, r2, lo.y, dv), f.o, f.z, lo.x, du, true);
        out.u = angular_axis(1.0, lo.x, hi.x);
        out.v = angular_axis(1.0, lo.y, hi.y);
        return out;
      }
      case Revolution: {  // the profile over the edges' part of it only
        out.surface = revolve(part(curve, lo.y, hi.y), f.o, f.z, lo.x, du, true);
        out.u = angular_axis(1.0, lo.x, hi.x);
        return out;
      }
      case Extrusion: {
        out.surface = extrude(part(curve, lo.x, hi.x), lo.y * dir, hi.y * dir, lo.y, hi.y);
        return out;
      }
    }
    return out;
  }
};

// A face's surface: B-spline (projected trims) or analytic (closed-form trims).
struct FaceSurface {
  std::optional<Surface> bspline;
  Analytic analytic;
};

// Parameters of points of a face's surface, for its edges: `natural` gives them on the branch of
// each periodic direction nearest `prev` (NaN u on an axis), `point` maps back.
struct Chart {
  std::function<glm::dvec2(glm::dvec3, const std::optional<glm::dvec2>&)> natural;
  std::function<glm::dvec3(glm::dvec2)> point;
  std::function<SurfaceDerivatives(glm::dvec2)> derivatives;  ///< B-spline charts only
  glm::dvec2 period{0.0};                                     ///< 0 = not periodic
};

// The chart of an analytic surface's NURBS `as`: parameters of a point in closed form (Analytic::
// natural, unwrapped near the previous sample's angle) mapped to the NURBS parameters.
Chart analytic_chart(const Analytic& a, const AnalyticSurface& as);

// A B-spline surface is periodic along a direction whose two boundary curves coincide.
Chart bspline_chart(const Surface& s, double accept) {
  const Interval u = surface_domain_u(s), v = surface_domain_v(s);
  const double size = control_box(s).diagonal();
  auto closed = [&](bool along_u) {
    for (int i = 0; i <= 8; ++i) {
      const double t = along_u ? v.min + v.width() * i / 8 : u.min + u.width() * i / 8;
      const glm::dvec3 a = along_u ? surface_point(s, u.min, t) : surface_point(s, t, v.min);
      const glm::dvec3 b = along_u ? surface_point(s, u.max, t) : surface_point(s, t, v.max);
      if (glm::length(a - b) > 1e-9 * size) return false;
    }
    return true;
  };
  Chart c;
  c.period = {closed(true) ? u.width() : 0.0, closed(false) ? v.width() : 0.0};
  // Unwrapped parameters brought back into the domain along periodic directions, clamped to it
  // along the others.
  const glm::dvec2 period = c.period;
  auto wrap = [u, v, period](glm::dvec2 uv) {
    auto w = [](double x, Interval d, double p) {
      if (!(p > 0)) return std::clamp(x, d.min, d.max);
      return x < d.min || x > d.max ? d.min + std::fmod(std::fmod(x - d.min, p) + p, p) : x;
    };
    return glm::dvec2(w(uv.x, u, period.x), w(uv.y, v, period.y));
  };
  c.point = [&s, wrap](glm::dvec2 uv) {
    const glm::dvec2 q = wrap(uv);
    return surface_point(s, q.x, q.y);
  };
  c.derivatives = [&s, wrap](glm::dvec2 uv) {
    const glm::dvec2 q = wrap(uv);
    return surface_derivatives(s, q.x, q.y);
  };
  c.natural = [&s, u, v, period, accept](glm::dvec3 p, const std::optional<glm::dvec2>& prev) {
    // Newton clamps to the domain: on a periodic direction a start on one side of the seam cannot
    // reach a point just across it, so a start near the seam is also tried on its other side.
    glm::dvec2 best{0.0};
    double best_d = std::numeric_limits<double>::infinity();
    auto attempt = [&](glm::dvec2 start) {
      const std::array<glm::dvec2, 2> sides = {start, glm::dvec2(start.x <= u.min + 0.5 * u.width() ? u.max : u.min,
                                                                 start.y <= v.min + 0.5 * v.width() ? v.max : v.min)};
      for (int k = 0; k < 4; ++k) {
        const bool flip_u = k & 1, flip_v = k & 2;
        if ((flip_u && !(period.x > 0 && std::min(start.x - u.min, u.max - start.x) < 0.05 * u.width())) ||
            (flip_v && !(period.y > 0 && std::min(start.y - v.min, v.max - start.y) < 0.05 * v.width())))
          continue;
        const glm::dvec2 st(flip_u ? sides[1].x : start.x, flip_v ? sides[1].y : start.y);
        const glm::dvec2 uv = closest_parameter(s, p, st);
        const double d = glm::length(surface_point(s, uv.x, uv.y) - p);
        if (d < best_d) best_d = d, best = uv;
        if (best_d <= accept) return;  // the other side of the seam only when this one fails
      }
    };
    if (prev) {
      glm::dvec2 start = *prev;  // brought into the domain
      if (period.x > 0) start.x = u.min + std::fmod(std::fmod(start.x - u.min, period.x) + period.x, period.x);
      if (period.y > 0) start.y = v.min + std::fmod(std::fmod(start.y - v.min, period.y) + period.y, period.y);
      attempt(start);
    }
    if (!(best_d <= accept)) attempt(closest_parameter(s, p));
    if (!(best_d <= accept)) {
      // A start on a collapsed boundary (a pole, where Newton's Jacobian is singular): from inside.
      const glm::dvec2 in(std::clamp(best.x, u.min + 0.01 * u.width(), u.max - 0.01 * u.width()),
                          std::clamp(best.y, v.min + 0.01 * v.width(), v.max - 0.01 * v.width()));
      attempt(in);
    }
    glm::dvec2 uv = best;
    if (prev) {
      if (period.x > 0) uv.x += period.x * std::round((prev->x - uv.x) / period.x);
      if (period.y > 0) uv.y += period.y * std::round((prev->y - uv.y) / period.y);
    }
    return uv;
  };
  return c;
}

// The outer loop's natural (u, v) samples (NaN u at points on the axis) where it passes the axis
// twice or more: between two such points a run of the loop may lie on either side of a seam (a
// hemisphere bounded by the meridian circle through its poles: the second meridian at +pi or -pi).
// Each run after the first is turned by -1, 0 or +1 turn so that the loop runs counter-clockwise in
// (u, v) (the material on its left: the natural parameters of ISO 10303-42's surfaces are
// right-handed about the outer normal, and the reader has turned the bounds of a same_sense .F.
// face round) within one turn, the narrowest such choice. Other loops are left as they are.
void choose_branches_across_axis(std::vector<glm::dvec2>& loop) {
  std::vector<size_t> axis;
  for (size_t i = 0; i < loop.size(); ++i)
    if (!std::isfinite(loop[i].x)) axis.push_back(i);
  if (axis.size() < 2) return;
  // Runs between consecutive axis points (cyclically), as [begin, end) index ranges into loop.
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t k = 0; k < axis.size(); ++k) {
    const size_t b = axis[k] + 1, e = k + 1 < axis.size() ? axis[k + 1] : axis.front() + loop.size();
    if (e > b) runs.emplace_back(b, e);
  }
  if (runs.size() < 2 || runs.size() > 4) return;
  const auto at = [&](size_t i) -> glm::dvec2& { return loop[i % loop.size()]; };
  const double turn = 2 * kPi;
  std::vector<int> best, pick(runs.size(), 0);
  double best_extent = std::numeric_limits<double>::infinity();
  const auto combos = static_cast<int>(std::pow(3, runs.size() - 1));
  for (int c = 0; c < combos; ++c) {
    for (size_t r = 1, x = size_t(c); r < runs.size(); ++r, x /= 3) pick[r] = int(x % 3) - 1;
    double area = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    glm::dvec2 last(std::numeric_limits<double>::quiet_NaN());
    std::optional<glm::dvec2> head;
    for (size_t r = 0; r < runs.size(); ++r)
      for (size_t i = runs[r].first; i < runs[r].second; ++i) {
        const glm::dvec2 q = at(i) + glm::dvec2(turn * pick[r], 0.0);
        if (!std::isfinite(q.x)) continue;
        if (head) area += last.x * q.y - q.x * last.y;
        else head = q;
        last = q, lo = std::min(lo, q.x), hi = std::max(hi, q.x);
      }
    if (!head) return;
    area += last.x * head->y - head->x * last.y;
    if (area > 0.0 && hi - lo <= turn + 1e-9 && hi - lo < best_extent) best_extent = hi - lo, best = pick;
  }
  if (best.empty()) return;
  for (size_t r = 1; r < runs.size(); ++r)
    for (size_t i = runs[r].first; i < runs[r].second; ++i) at(i).x += turn * best[r];
}

// A loop's (u, v) points on a surface periodic in u with period `period`, split by its points on
// the axis (a pole, an apex; NaN u, no angle): each run between them made continuous (every point
// within half a period of the one before: the samples next to a pole, which have no neighbour's
// angle to follow, land on either side of a seam edge), and the run that ends the loop shifted by
// whole periods to end where the loop starts (a ball's seam used down to the pole and up again:
// the way up is on the other side of the seam).
void unwrap_across_axis(std::vector<std::vector<glm::dvec2>>& loop, double period) {
  std::vector<glm::dvec2*> pts;
  for (auto& l : loop)
    for (glm::dvec2& q : l) pts.push_back(&q);
  const glm::dvec2* last = nullptr;
  size_t run = 0;  // first point of the current run
  bool axis = false;
  for (size_t i = 0; i < pts.size(); ++i) {
    glm::dvec2& q = *pts[i];
    if (!std::isfinite(q.x)) {
      last = nullptr, axis = true;
      continue;
    }
    if (last)
      q.x += period * std::round((last->x - q.x) / period);
    else
      run = i;
    last = &q;
  }
  if (!axis || run == 0 || !last || !std::isfinite(pts.front()->x)) return;
  const double shift = period * std::round((pts.front()->x - last->x) / period);
  for (size_t i = run; i < pts.size(); ++i) pts[i]->x += shift;
}

Chart analytic_chart(const Analytic& a, const AnalyticSurface& as) {
  Chart c = bspline_chart(as.surface, 0.0);
  const Interval u = surface_domain_u(as.surface), v = surface_domain_v(as.surface);
  const glm::dvec2 period = c.period;
  c.natural = [&a, &as, u, v, period](glm::dvec3 p, const std::optional<glm::dvec2>& prev) {
    std::optional<glm::dvec2> near, anchor = prev;
    if (anchor) {
      // After a point on the axis (no angle), the angle is taken nearest the patch's middle: the
      // branch the patch was built on, not atan2's.
      if (!std::isfinite(anchor->x)) anchor->x = 0.5 * (u.min + u.max);
      if (!std::isfinite(anchor->y)) anchor->y = 0.5 * (v.min + v.max);
    }
    if (anchor) {
      glm::dvec2 q = *anchor;  // into the domain, then the file's parameters
      if (period.x > 0) q.x = u.min + std::fmod(std::fmod(q.x - u.min, period.x) + period.x, period.x);
      if (period.y > 0) q.y = v.min + std::fmod(std::fmod(q.y - v.min, period.y) + period.y, period.y);
      near = glm::dvec2(as.u.inverse(q.x), as.v.inverse(q.y));
    }
    glm::dvec2 st = as.map(a.natural(p, near));
    if (anchor) {
      if (period.x > 0 && std::isfinite(st.x)) st.x += period.x * std::round((anchor->x - st.x) / period.x);
      if (period.y > 0 && std::isfinite(st.y)) st.y += period.y * std::round((anchor->y - st.y) / period.y);
    }
    return st;
  };
  return c;
}

struct Box2 {
  glm::dvec2 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
  void add(glm::dvec2 q) { lo = glm::min(lo, q), hi = glm::max(hi, q); }
  [[nodiscard]] glm::dvec2 centre() const { return 0.5 * (lo + hi); }
};

// Marks the loop with the largest parameter box as the outer one.
void mark_outer(TrimmedSurface& f) {
  // The loop enclosing the largest area (its curves sampled, shoelace): the box of a loop's control
  // points overstates a rotated circle's reach, so a circle of radius 0.255 out-boxed one of 0.278.
  double best = -1.0;
  TrimLoop* outer = nullptr;
  for (TrimLoop& l : f.loops) {
    std::vector<glm::dvec2> polygon;
    for (const Curve2& c : l.curves) {
      const Interval d = curve_domain(c);
      for (int i = 0; i < 32; ++i) polygon.push_back(curve_point(c, d.min + d.width() * i / 32.0));
    }
    const double area = std::abs(signed_area(polygon));
    if (area > best) best = area, outer = &l;
  }
  if (outer) outer->outer = true;
}

// Samples of an edge at which the gap between it and its face's trim is measured (besides the
// samples the trim's construction takes): ends, middle and every 1/32 of its parameter range.
constexpr int kGapSamples = 32;

// Largest distance from the surface points of the parameter-space curve `pc` (in s's (u, v), z = 0)
// to its 3D edge `c`, at kGapSamples + 1 points evenly spaced in parameter: at the ends to the
// edge's ends, inside to the nearest edge point (Newton from the same fraction of the edge, so
// differently parametrised curves are not taken for a gap). Infinite when a point is not finite.
double trim_gap(const Curve3& pc, const Curve3& c, const Surface& s) {
  const Interval dp = curve_domain(pc), dc = curve_domain(c);
  double worst = 0.0;
  for (int i = 0; i <= kGapSamples; ++i) {
    const double x = static_cast<double>(i) / kGapSamples, tc = dc.min + x * dc.width();
    const glm::dvec3 q = curve_point(pc, dp.min + x * dp.width());
    const glm::dvec3 p = surface_point(s, q.x, q.y);
    double d = glm::length(p - curve_point(c, tc));
    if (i > 0 && i < kGapSamples) d = std::min(d, glm::length(curve_point(c, Analytic::newton_t(c, p, dc, tc)) - p));
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

struct Instance {
  glm::dmat4 m{1.0};
  std::string path;
};

class StepReader {
 public:
  StepReader(const StepFile& f, IgesReadLog& log) : f_(f), log_(log) {}

  Model read();

 private:
  std::vector<DroppedFace> dropped_;  // those dropped, with the reason
  std::vector<std::string> warnings_;  // read differently from the letter of the file (Model::read_warnings)

  // ---- access -------------------------------------------------------------------------------------
  [[noreturn]] void fail(const StepEntity& e, const std::string& problem) const {
    throw ReadError(f_.name, fmt::format("line {}: #{} ({})", e.line, e.id, e.type_name()), problem);
  }
  /// A B-spline curve or surface read from `e`, checked as the IGES reader checks them (knots,
  /// weights, the magnitude limits): the first problem fails `e`.
  template <class Geometry>
  void check_geometry(const StepEntity& e, const Geometry& g) const {
    std::vector<std::string> problems = validate(g);
    for (std::string& p : validate_magnitude(g, kMaxCoordinate)) problems.push_back(std::move(p));
    if (!problems.empty()) fail(e, problems.front());
  }
  const StepEntity& entity(long id, const StepEntity& from) {
    const StepEntity* e = f_.find(id);
    if (!e) fail(from, fmt::format("refers to #{}, which is not defined", id));
    intact(*e);
    visited_.insert(id);
    return *e;
  }
  /// Fails `e` when its parameters were damaged in the file (StepEntity::damage): the reader uses it.
  void intact(const StepEntity& e) const {
    if (!e.damage.empty()) fail(e, e.damage);
  }
  /// Marks `id` and everything it refers to as reached (up to kMaxDepth references deep, each
  /// instance once), leaving damaged instances unmarked: the parameter-space geometry of an edge
  /// that is read.
  void mark_reached(long id, int depth);
  /// Marks the PCURVEs of an edge's curve `e` (SURFACE_CURVE, SEAM_CURVE, INTERSECTION_CURVE, also
  /// through TRIMMED_CURVE) and their curves as reached, whether the reader takes them or not; the
  /// surfaces they lie on stay unmarked (a surface no face reads is geometry left out).
  void mark_pcurves(const StepEntity& e, int depth);
  const StepRecord& record(const StepEntity& e, const std::string& type) const {
    const StepRecord* r = e.record(type);
    if (!r) fail(e, fmt::format("is not a {}", type));
    return *r;
  }
  const StepValue& param(const StepEntity& e, const StepRecord& r, size_t i, const char* what) const {
    if (i >= r.params.size())
      fail(e, fmt::format("{} has {} parameters; parameter {} ({}) is missing", r.type, r.params.size(), i + 1, what));
    return r.params[i];
  }
  double real(const StepEntity& e, const StepValue& v, const char* what) const {
    const StepValue* x = &v;
    if (x->kind == Kind::Typed && x->items.size() == 1) x = &x->items.front();
    if (x->kind != Kind::Real && x->kind != Kind::Integer) fail(e, fmt::format("{} is not a number", what));
    if (!(std::abs(x->number) <= kMaxCoordinate))
      fail(e, fmt::format("{} {} is beyond {:g}", what, x->number, kMaxCoordinate));
    return x->number;
  }
  double real(const StepEntity& e, const StepRecord& r, size_t i, const char* what) const {
    return real(e, param(e, r, i, what), what);
  }
  int integer(const StepEntity& e, const StepValue& v, const char* what, int lo, int hi) const {
    if (v.kind != Kind::Integer || !(v.number >= lo && v.number <= hi))
      fail(e, fmt::format("{} is not an integer in [{}, {}]", what, lo, hi));
    return static_cast<int>(v.number);
  }
  long ref(const StepEntity& e, const StepValue& v, const char* what) const {
    if (v.kind != Kind::Ref) fail(e, fmt::format("{} is not a reference #N", what));
    return v.ref;
  }
  long ref(const StepEntity& e, const StepRecord& r, size_t i, const char* what) const {
    return ref(e, param(e, r, i, what), what);
  }
  const std::vector<StepValue>& list(const StepEntity& e, const StepValue& v, const char* what) const {
    if (v.kind != Kind::List) fail(e, fmt::format("{} is not a list", what));
    return v.items;
  }
  bool logical(const StepEntity& e, const StepValue& v, const char* what) const {
    if (v.kind == Kind::Enum && (v.text == "T" || v.text == "F")) return v.text == "T";
    fail(e, fmt::format("{} is not .T. or .F.", what));
  }
  static bool is(const StepEntity& e, const char* type) { return e.record(type) != nullptr; }
  /// The record of a curve on surfaces, whose parameters are (name, curve_3d, associated_geometry,
  /// master_representation): SURFACE_CURVE or its subtypes SEAM_CURVE and INTERSECTION_CURVE.
  static const StepRecord* surface_curve(const StepEntity& e) {
    for (const char* t : {"SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"})
      if (const StepRecord* r = e.record(t)) return r;
    return nullptr;
  }

  // ---- geometry -----------------------------------------------------------------------------------
  glm::dvec3 point(long id, const StepEntity& from);
  glm::dvec3 direction(long id, const StepEntity& from);
  Frame placement(long id, const StepEntity& from);
  /// The records of a B-spline: with knots, and the one holding degree and control points (the
  /// same for a simple instance, whose parameters start after the name: offset 1).
  /// Without knots (`knots` null): the knot type the record names, whose knots the standard implies.
  struct SplineRecords {
    const StepRecord* knots;
    const StepRecord& base;
    size_t offset;
    std::string implied;  ///< "QUASI_UNIFORM", "UNIFORM" or "BEZIER" where knots is null
  };
  SplineRecords spline_records(const StepEntity& e, const std::string& type) const;
  /// The knots ISO 10303-42 implies for `count` control points of `degree` of a B-spline of the
  /// knot type `implied` (quasi_uniform: clamped, unit steps; uniform: unit steps from -degree;
  /// bezier: clamped, each inner value `degree` times); fails `e` where the count does not fit.
  std::vector<double> implied_knots(const StepEntity& e, const std::string& implied, int degree, int count) const;
  /// Knots from multiplicities and distinct values (parameters mults_at and knots_at of r).
  std::vector<double> knot_vector(const StepEntity& e, const StepRecord& r, size_t mults_at, size_t knots_at,
                                  int degree) const;
  Curve3 bspline_curve(const StepEntity& e);
  Surface bspline_surface(const StepEntity& e);
  /// The curve entity as NURBS (conics over their full turn), with a frame for conics.
  struct CurveGeom {
    /// Hyperbola: o + a cosh(t) x + b sinh(t) y; parabola: o + a (t^2 x + 2 t y) (ISO 10303-42):
    /// unbounded, so no `nurbs`: an edge's arc between its vertices is built where it is used.
    enum { Line, Conic, Hyperbola, Parabola, Spline } type = Spline;
    Curve3 nurbs;
    Frame f;  // conic: x, y axes scaled by the semi-axes
    double a = 0, b = 0;
  };
  CurveGeom curve(long id, const StepEntity& from, int depth);
  /// A piece of an edge, with the same piece of its parameter-space curves where the file gives
  /// them (PCURVEs of a SURFACE_CURVE / SEAM_CURVE over a B-spline, by the surface they lie on).
  struct EdgePiece {
    Curve3 c;
    std::vector<std::pair<long, Curve3>> pcurves;  // surface instance, curve in its (u, v) (z = 0)
  };
  /// The pieces of an EDGE_CURVE from its start vertex to its end vertex.
  const std::vector<EdgePiece>& edge(long id, const StepEntity& from);
  /// The PCURVEs of edge geometry `e` (a SURFACE_CURVE or SEAM_CURVE) over [t0, t1] of its curve
  /// `g` as ISO 10303-42 parametrises it: a B-spline's knots, a line's point + t vector, a conic's
  /// angle (here in radians).
  std::vector<std::pair<long, Curve3>> pcurves(const StepEntity& e, const CurveGeom& g, double t0, double t1);
  FaceSurface surface(long id, const StepEntity& from);

  // ---- topology -----------------------------------------------------------------------------------
  struct Loop {
    std::vector<Curve3> curves;
    std::vector<int> edges;
    std::vector<std::vector<Curve3>> pcurves;  // per curve: its parameter-space curves on the face's surface
    bool outer = false;
  };
  std::vector<Loop> face_loops(const StepEntity& face, long surface);
  /// The loop run the other way: curves in reverse order, each reversed (pcurves alike).
  static void reverse(Loop& loop);
  /// A face's entities read (sequentially: the caches and the visited set are shared), its
  /// geometry not yet built.
  struct FaceJob {
    TrimmedSurface f;  // id, name, orientation
    std::vector<Loop> loops;
    FaceSurface fs;
    std::string skipped;  // why the face is dropped, when it is
  };
  FaceJob face_job(long id, const StepEntity& from);
  /// The face's surface and trims from its job: no shared state, run on worker threads.
  TrimmedSurface build_face(FaceJob& job) const;
  /// The loop from its edges' parameter-space curves on `s` (of a seam's two, the one continuing the
  /// loop) when each edge has one, with the largest distance from their surface points to their
  /// edges (trim_gap); else none.
  struct GivenLoop {
    TrimLoop loop;
    double gap = 0.0;
  };
  static std::optional<GivenLoop> given_loop(const Loop& loop, const Surface& s);
  /// Builds every job on all cores; dropped faces are logged and left out.
  std::vector<TrimmedSurface> build_faces(std::vector<FaceJob>& jobs);
  void shell_faces(long id, const StepEntity& from, bool reversed, std::vector<FaceJob>& out);
  std::vector<FaceJob> solid(const StepEntity& e);

  // ---- units and assemblies ------------------------------------------------------------------------
  void read_units(long context, const StepEntity& from);
  std::vector<Instance> instances(long rep, int depth);
  std::string product_name(long rep);
  void link_representations();
  long group(long rep) {
    auto it = group_.find(rep);
    if (it == group_.end()) return rep;
    const long g = group(it->second);
    it->second = g;
    return g;
  }

  const StepFile& f_;
  IgesReadLog& log_;
  std::unordered_set<long> visited_;
  std::unordered_set<long> marked_;  // visited with everything they refer to (mark_reached)
  double length_scale_ = 1.0;        // file length unit in mm (of the representation being read)
  double angle_scale_ = 1.0;         // file plane angle unit in radians
  double resolution_ = 0.0;
  bool units_read_ = false;
  std::unordered_map<long, std::vector<EdgePiece>> edges_;
  std::unordered_map<long, int> edge_index_;
  std::unordered_map<long, long> group_;  // union-find of representations related without a transform
  struct Link {
    long parent;
    glm::dmat4 m;
    std::string name;
  };
  std::unordered_map<long, std::vector<Link>> parents_;  // representation group -> its placements
  std::unordered_map<long, long> product_of_group_;      // representation group -> PRODUCT instance
};

glm::dvec3 StepReader::point(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  const StepRecord& r = record(e, "CARTESIAN_POINT");
  const auto& c = list(e, param(e, r, 1, "coordinates"), "coordinates");
  if (c.empty() || c.size() > 3) fail(e, fmt::format("has {} coordinates", c.size()));
  glm::dvec3 p(0.0);
  for (size_t i = 0; i < c.size(); ++i) p[static_cast<int>(i)] = real(e, c[i], "coordinate");
  return p;
}

glm::dvec3 StepReader::direction(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  const StepRecord& r = record(e, "DIRECTION");
  const auto& c = list(e, param(e, r, 1, "direction ratios"), "direction ratios");
  if (c.empty() || c.size() > 3) fail(e, fmt::format("has {} direction ratios", c.size()));
  glm::dvec3 d(0.0);
  for (size_t i = 0; i < c.size(); ++i) d[static_cast<int>(i)] = real(e, c[i], "direction ratio");
  const double n = glm::length(d);
  if (!(n > 0) || !std::isfinite(n)) fail(e, "is a zero direction");
  return d / n;
}

Frame StepReader::placement(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  const StepRecord& r = record(e, "AXIS2_PLACEMENT_3D");
  Frame f;
  f.o = point(ref(e, r, 1, "location"), e) * 1.0;
  const StepValue& axis = param(e, r, 2, "axis");
  const StepValue& refd = param(e, r, 3, "ref_direction");
  f.z = axis.kind == Kind::Null ? glm::dvec3(0, 0, 1) : direction(ref(e, axis, "axis"), e);
  // ISO 10303-42 first_proj_axis: the reference direction made orthogonal to the axis; without
  // one, (1, 0, 0), or (0, 1, 0) where the axis is +-(1, 0, 0).
  const auto project = [&](glm::dvec3 v) { return v - glm::dot(v, f.z) * f.z; };
  const glm::dvec3 fallback = project(std::abs(f.z.x) == 1.0 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0));
  glm::dvec3 v = refd.kind == Kind::Null ? fallback : project(direction(ref(e, refd, "ref_direction"), e));
  if (!(glm::length(v) > 1e-12) && refd.kind != Kind::Null) {
    // The standard leaves the frame undefined; OpenCASCADE reads such files. Take the frame the
    // file would have without a reference direction: a circle or a surface of revolution keeps its
    // shape, only where its parameter starts may differ from the writer's.
    std::string w = fmt::format("line {}: #{} (AXIS2_PLACEMENT_3D): its reference direction is parallel to its "
                                "axis; the default first axis of ISO 10303-42 is used",
                                e.line, e.id);
    if (std::find(warnings_.begin(), warnings_.end(), w) == warnings_.end()) warnings_.push_back(std::move(w));
    v = fallback;
  }
  if (!(glm::length(v) > 1e-12)) fail(e, "its reference direction is parallel to its axis");
  f.x = glm::normalize(v);
  f.y = glm::cross(f.z, f.x);
  return f;
}

StepReader::SplineRecords StepReader::spline_records(const StepEntity& e, const std::string& type) const {
  const std::string kind = type.substr(std::string("B_SPLINE_").size());  // CURVE or SURFACE
  for (const char* implied : {"QUASI_UNIFORM", "UNIFORM", "BEZIER"})
    if (const StepRecord* r = e.record(std::string(implied) + "_" + kind); r && !e.record(type + "_WITH_KNOTS")) {
      if (e.records.size() == 1) return {nullptr, *r, 1, implied};  // simple instance: the name comes first
      return {nullptr, record(e, type), 0, implied};
    }
  const StepRecord& k = record(e, type + "_WITH_KNOTS");
  if (e.records.size() == 1) return {&k, k, 1, {}};
  return {&k, record(e, type), 0, {}};
}

std::vector<double> StepReader::implied_knots(const StepEntity& e, const std::string& implied, int degree,
                                              int count) const {
  if (count < degree + 1) fail(e, fmt::format("has {} control points for degree {}", count, degree));
  std::vector<double> k;
  if (implied == "UNIFORM") {
    for (int i = 0; i < count + degree + 1; ++i) k.push_back(i - degree);
  } else if (implied == "QUASI_UNIFORM") {
    const int spans = count - degree;
    k.assign(static_cast<size_t>(degree) + 1, 0.0);
    for (int i = 1; i < spans; ++i) k.push_back(i);
    k.insert(k.end(), static_cast<size_t>(degree) + 1, static_cast<double>(spans));
  } else {  // BEZIER: pieces of degree + 1 points sharing their ends
    if ((count - 1) % degree != 0)
      fail(e, fmt::format("has {} control points, not a chain of Bezier pieces of degree {}", count, degree));
    const int pieces = (count - 1) / degree;
    k.assign(static_cast<size_t>(degree) + 1, 0.0);
    for (int i = 1; i < pieces; ++i) k.insert(k.end(), static_cast<size_t>(degree), static_cast<double>(i));
    k.insert(k.end(), static_cast<size_t>(degree) + 1, static_cast<double>(pieces));
  }
  return k;
}

std::vector<double> StepReader::knot_vector(const StepEntity& e, const StepRecord& r, size_t mults_at, size_t knots_at,
                                            int degree) const {
  const auto& mults = list(e, param(e, r, mults_at, "knot multiplicities"), "knot multiplicities");
  const auto& knots = list(e, param(e, r, knots_at, "knots"), "knots");
  if (mults.size() != knots.size())
    fail(e, fmt::format("has {} knot multiplicities for {} knots", mults.size(), knots.size()));
  std::vector<double> out;
  for (size_t i = 0; i < knots.size(); ++i) {
    const int m = integer(e, mults[i], "knot multiplicity", 1, degree + 1);
    out.insert(out.end(), static_cast<size_t>(m), real(e, knots[i], "knot"));
  }
  return out;
}

Curve3 StepReader::bspline_curve(const StepEntity& e) {
  // Simple: B_SPLINE_CURVE_WITH_KNOTS(name, degree, points, form, closed, self_int, mults, knots,
  // spec). Complex: B_SPLINE_CURVE(degree, points, form, closed, self_int)
  // B_SPLINE_CURVE_WITH_KNOTS(mults, knots, spec) RATIONAL_B_SPLINE_CURVE(weights).
  const auto [k, base, o, implied] = spline_records(e, "B_SPLINE_CURVE");
  const bool simple = o == 1;
  Curve3 c;
  c.degree = integer(e, param(e, base, o, "degree"), "degree", 1, kMaxDegree);
  for (const StepValue& p : list(e, param(e, base, o + 1, "control points"), "control points"))
    c.points.push_back(point(ref(e, p, "control point"), e));
  const size_t ko = simple ? 6 : 0;
  c.knots = k ? knot_vector(e, *k, ko, ko + 1, c.degree)
              : implied_knots(e, implied, c.degree, static_cast<int>(c.points.size()));
  if (const StepRecord* w = e.record("RATIONAL_B_SPLINE_CURVE"))
    for (const StepValue& x : list(e, param(e, *w, 0, "weights"), "weights")) c.weights.push_back(real(e, x, "weight"));
  if (c.knots.size() != c.points.size() + static_cast<size_t>(c.degree) + 1)
    fail(e, fmt::format("has {} knots for {} control points of degree {} (needs {})", c.knots.size(), c.points.size(),
                        c.degree, c.points.size() + static_cast<size_t>(c.degree) + 1));
  check_geometry(e, c);
  return c;
}

Surface StepReader::bspline_surface(const StepEntity& e) {
  // Simple: B_SPLINE_SURFACE_WITH_KNOTS(name, du, dv, points, form, uc, vc, si, umults, vmults,
  // uknots, vknots, spec). Complex: B_SPLINE_SURFACE(du, dv, points, form, uc, vc, si)
  // B_SPLINE_SURFACE_WITH_KNOTS(umults, vmults, uknots, vknots, spec) RATIONAL_B_SPLINE_SURFACE(weights).
  const auto [k, base, o, implied] = spline_records(e, "B_SPLINE_SURFACE");
  const bool simple = o == 1;
  Surface s;
  s.degree_u = integer(e, param(e, base, o, "u degree"), "u degree", 1, kMaxDegree);
  s.degree_v = integer(e, param(e, base, o + 1, "v degree"), "v degree", 1, kMaxDegree);
  const auto& rows = list(e, param(e, base, o + 2, "control points"), "control points");
  s.count_u = static_cast<int>(rows.size());
  std::vector<std::vector<glm::dvec3>> grid;
  for (const StepValue& row : rows) {
    const auto& items = list(e, row, "control point row");
    if (grid.empty()) s.count_v = static_cast<int>(items.size());
    if (static_cast<int>(items.size()) != s.count_v) fail(e, "its control point rows differ in length");
    grid.emplace_back();
    for (const StepValue& p : items) grid.back().push_back(point(ref(e, p, "control point"), e));
  }
  s.points.resize(static_cast<size_t>(s.count_u) * s.count_v);
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) s.points[static_cast<size_t>(j) * s.count_u + i] = grid[i][j];
  const size_t ko = simple ? 8 : 0;
  s.knots_u = k ? knot_vector(e, *k, ko, ko + 2, s.degree_u) : implied_knots(e, implied, s.degree_u, s.count_u);
  s.knots_v = k ? knot_vector(e, *k, ko + 1, ko + 3, s.degree_v) : implied_knots(e, implied, s.degree_v, s.count_v);
  if (const StepRecord* w = e.record("RATIONAL_B_SPLINE_SURFACE")) {
    const auto& wrows = list(e, param(e, *w, 0, "weights"), "weights");
    if (static_cast<int>(wrows.size()) != s.count_u) fail(e, "its weights and control points differ in number");
    s.weights.resize(s.points.size());
    for (int i = 0; i < s.count_u; ++i) {
      const auto& ws = list(e, wrows[i], "weight row");
      if (static_cast<int>(ws.size()) != s.count_v) fail(e, "its weights and control points differ in number");
      for (int j = 0; j < s.count_v; ++j) s.weights[static_cast<size_t>(j) * s.count_u + i] = real(e, ws[j], "weight");
    }
  }
  check_geometry(e, s);
  return s;
}

StepReader::CurveGeom StepReader::curve(long id, const StepEntity& from, int depth) {
  const StepEntity& e = entity(id, from);
  if (depth > kMaxDepth) fail(e, fmt::format("curves nest deeper than {} (a reference cycle?)", kMaxDepth));
  CurveGeom g;
  if (const StepRecord* r = e.record("LINE")) {
    g.type = CurveGeom::Line;
    const glm::dvec3 p = point(ref(e, *r, 1, "point"), e);
    const StepEntity& vec = entity(ref(e, *r, 2, "direction vector"), e);
    const StepRecord& vr = record(vec, "VECTOR");
    const glm::dvec3 d = direction(ref(vec, vr, 1, "orientation"), vec) * real(vec, vr, 2, "magnitude");
    g.nurbs = segment(p, p + d, 0.0, 1.0);  // the line's own parameter on [0, 1]
    g.f.o = p;
    g.f.x = d;
    return g;
  }
  if (e.record("CIRCLE") || e.record("ELLIPSE")) {
    const bool circle = e.record("CIRCLE") != nullptr;
    const StepRecord& r = *e.record(circle ? "CIRCLE" : "ELLIPSE");
    g.type = CurveGeom::Conic;
    g.f = placement(ref(e, r, 1, "position"), e);
    g.a = real(e, r, 2, "radius");
    g.b = circle ? g.a : real(e, r, 3, "second semi-axis");
    if (!(g.a > 0 && g.b > 0)) fail(e, "has a radius that is not positive");
    // Full turn: the unit circle's arcs mapped by the axes (affine: exact).
    g.nurbs = circle_arc(g.f.o, g.f.x * g.a, g.f.y * g.b, 1.0, 0.0, 2 * kPi);
    return g;
  }
  if (const StepRecord* r = e.record("HYPERBOLA")) {
    g.type = CurveGeom::Hyperbola;
    g.f = placement(ref(e, *r, 1, "position"), e);
    g.a = real(e, *r, 2, "semi-axis");
    g.b = real(e, *r, 3, "imaginary semi-axis");
    if (!(g.a > 0 && g.b > 0)) fail(e, "has a semi-axis that is not positive");
    return g;
  }
  if (const StepRecord* r = e.record("PARABOLA")) {
    g.type = CurveGeom::Parabola;
    g.f = placement(ref(e, *r, 1, "position"), e);
    g.a = real(e, *r, 2, "focal distance");
    if (!(g.a != 0 && std::isfinite(g.a))) fail(e, "has a focal distance of 0");
    return g;
  }
  if (e.record("B_SPLINE_CURVE_WITH_KNOTS") || e.record("QUASI_UNIFORM_CURVE") || e.record("UNIFORM_CURVE") ||
      e.record("BEZIER_CURVE")) {
    g.nurbs = bspline_curve(e);
    return g;
  }
  if (const StepRecord* r = e.record("POLYLINE")) {
    g.nurbs.degree = 1;
    const auto& pts = list(e, param(e, *r, 1, "points"), "points");
    if (pts.size() < 2) fail(e, "has fewer than 2 points");
    for (size_t i = 0; i < pts.size(); ++i) {
      g.nurbs.points.push_back(point(ref(e, pts[i], "point"), e));
      g.nurbs.knots.push_back(static_cast<double>(i));
    }
    g.nurbs.knots.insert(g.nurbs.knots.begin(), 0.0);
    g.nurbs.knots.push_back(static_cast<double>(pts.size() - 1));
    return g;
  }
  if (const StepRecord* r = e.record("TRIMMED_CURVE")) return curve(ref(e, *r, 1, "basis curve"), e, depth + 1);
  if (const StepRecord* r = surface_curve(e)) return curve(ref(e, *r, 1, "3D curve"), e, depth + 1);
  throw SkipFace{fmt::format("its edge curve #{} is a {}, which is not read", e.id, e.type_name())};
}

void StepReader::mark_reached(long id, int depth) {
  const StepEntity* e = f_.find(id);
  if (!e || !e->damage.empty() || depth > kMaxDepth || !marked_.insert(id).second) return;
  visited_.insert(id);
  std::function<void(const StepValue&)> walk = [&](const StepValue& v) {
    if (v.kind == Kind::Ref) mark_reached(v.ref, depth + 1);
    for (const StepValue& item : v.items) walk(item);
  };
  for (const StepRecord& r : e->records)
    for (const StepValue& v : r.params) walk(v);
}

void StepReader::mark_pcurves(const StepEntity& e, int depth) {
  if (depth > kMaxDepth) return;
  if (const StepRecord* t = e.record("TRIMMED_CURVE"); t && t->params.size() > 1 && t->params[1].kind == Kind::Ref) {
    if (const StepEntity* basis = f_.find(t->params[1].ref)) mark_pcurves(*basis, depth + 1);
    return;
  }
  const StepRecord* r = surface_curve(e);
  if (!r || r->params.size() < 3 || r->params[2].kind != Kind::List) return;
  for (const StepValue& gv : r->params[2].items) {
    const StepEntity* pc = gv.kind == Kind::Ref ? f_.find(gv.ref) : nullptr;
    const StepRecord* pr = pc ? pc->record("PCURVE") : nullptr;
    if (!pr || !pc->damage.empty()) continue;
    visited_.insert(pc->id);
    if (pr->params.size() > 2 && pr->params[2].kind == Kind::Ref) mark_reached(pr->params[2].ref, depth + 1);
  }
}

std::vector<std::pair<long, Curve3>> StepReader::pcurves(const StepEntity& e, const CurveGeom& g, double t0,
                                                         double t1) {
  std::vector<std::pair<long, Curve3>> out;
  const StepRecord* r = surface_curve(e);
  if (!r || r->params.size() < 3 || r->params[2].kind != Kind::List) return out;
  if (g.type == CurveGeom::Conic) t0 /= angle_scale_, t1 /= angle_scale_;  // radians: the file's angle unit
  for (const StepValue& gv : r->params[2].items) {
    if (gv.kind != Kind::Ref) continue;
    const StepEntity& pc = entity(gv.ref, e);
    const StepRecord* pr = pc.record("PCURVE");
    if (!pr) continue;
    const long surface = ref(pc, *pr, 1, "basis surface");
    const StepEntity& dr = entity(ref(pc, *pr, 2, "reference to curve"), pc);
    const StepRecord& drr = dr.records.front();
    const auto& items = list(dr, param(dr, drr, 1, "items"), "items");
    if (items.size() != 1) continue;
    CurveGeom pg;
    try {
      pg = curve(ref(dr, items.front(), "curve"), dr, 1);
    } catch (const SkipFace&) {  // a parameter-space curve of a type not read: the edge is projected
      continue;
    } catch (const ReadError&) {  // nor one this reader cannot read (a 2D conic's AXIS2_PLACEMENT_2D)
      continue;
    }
    if (pg.type == CurveGeom::Line) {
      out.emplace_back(surface, segment(pg.f.o + t0 * pg.f.x, pg.f.o + t1 * pg.f.x, t0, t1));
    } else if (pg.type == CurveGeom::Spline) {
      const Interval d = curve_domain(pg.nurbs);
      // A conic's angles may be counted from another turn than the first.
      const double turn = g.type == CurveGeom::Conic ? 2 * kPi / angle_scale_ : 0.0;
      double a = t0, b = t1;
      if (turn > 0 && (a < d.min - 1e-9 * d.width() || b > d.max + 1e-9 * d.width())) {
        const double k = std::round((d.min + d.max - a - b) / (2 * turn));
        a += k * turn, b += k * turn;
      }
      if (a < d.min - 1e-9 * d.width() || b > d.max + 1e-9 * d.width()) continue;
      out.emplace_back(surface, restrict_curve(pg.nurbs, std::max(a, d.min), std::min(b, d.max)));
    }
  }
  return out;
}

const std::vector<StepReader::EdgePiece>& StepReader::edge(long id, const StepEntity& from) {
  if (auto it = edges_.find(id); it != edges_.end()) return it->second;
  const StepEntity& e = entity(id, from);
  const StepRecord& r = record(e, "EDGE_CURVE");
  auto vertex = [&](size_t i) {
    const StepEntity& v = entity(ref(e, r, i, "vertex"), e);
    return point(ref(v, record(v, "VERTEX_POINT"), 1, "vertex point"), v);
  };
  const glm::dvec3 a = vertex(1), b = vertex(2);
  const long geometry = ref(e, r, 3, "edge geometry");
  const CurveGeom g = curve(geometry, e, 0);
  mark_pcurves(entity(geometry, e), 0);
  const bool same = logical(e, param(e, r, 4, "same_sense"), "same_sense");
  std::vector<EdgePiece> pieces;
  const double size = std::max(glm::length(a - b), 1e-300);
  if (g.type == CurveGeom::Line) {
    // The line between the vertices' feet on it: the curve is the edge's geometry, a vertex may lie
    // off it within the writer's tolerance (CATIA: up to 0.014 mm on the Ventilator).
    const glm::dvec3 d = g.f.x / glm::dot(g.f.x, g.f.x);
    auto foot = [&](glm::dvec3 q) { return g.f.o + glm::dot(q - g.f.o, d) * g.f.x; };
    const double ta = glm::dot(a - g.f.o, d), tb = glm::dot(b - g.f.o, d);
    std::vector<std::pair<long, Curve3>> pc = pcurves(entity(geometry, e), g, std::min(ta, tb), std::max(ta, tb));
    if (ta > tb)
      for (auto& q : pc) q.second = reversed(q.second);
    pieces.push_back({segment(foot(a), foot(b), 0.0, 1.0), std::move(pc)});
  } else if (g.type == CurveGeom::Conic) {
    // Angles of the vertices on the ellipse; the edge runs counter-clockwise from start to end when
    // same_sense, else clockwise (= counter-clockwise from end to start, reversed).
    auto angle = [&](glm::dvec3 p) {
      const glm::dvec3 d = p - g.f.o;
      return std::atan2(glm::dot(d, g.f.y) / g.b, glm::dot(d, g.f.x) / g.a);
    };
    const double s = angle(same ? a : b), t = angle(same ? b : a);
    double sweep = t - s;
    while (sweep <= 1e-12) sweep += 2 * kPi;
    if (glm::length(a - b) <= 1e-9 * g.a) sweep = 2 * kPi;
    Curve3 c = circle_arc(g.f.o, g.f.x * g.a, g.f.y * g.b, 1.0, s, sweep);
    std::vector<std::pair<long, Curve3>> pc = pcurves(entity(geometry, e), g, s, s + sweep);
    if (!same)
      for (auto& q : pc) q.second = reversed(q.second);
    pieces.push_back({same ? c : reversed(c), std::move(pc)});
  } else if (g.type == CurveGeom::Hyperbola || g.type == CurveGeom::Parabola) {
    // The vertices' feet on the conic (in its plane, by the parameter of their y coordinate), then
    // the arc between them as one rational quadratic (conic_arcs.h), mapped by the frame (affine:
    // exact). The edge runs from its start vertex to its end vertex whatever same_sense says: on an
    // open conic the arc between two points is one.
    const bool hyperbola = g.type == CurveGeom::Hyperbola;
    auto foot = [&](glm::dvec3 p) {
      const double y = glm::dot(p - g.f.o, g.f.y);
      const double t = hyperbola ? std::asinh(y / g.b) : y / (2 * g.a);
      return hyperbola ? glm::dvec2(g.a * std::cosh(t), g.b * std::sinh(t)) : glm::dvec2(g.a * t * t, 2 * g.a * t);
    };
    const glm::dvec2 s = foot(a), t = foot(b);
    if (glm::length(s - t) <= 1e-12 * (std::abs(g.a) + g.b)) fail(e, "its vertices are one point of an open conic");
    const std::array<double, 6> coef = hyperbola ? std::array<double, 6>{1 / (g.a * g.a), 0, -1 / (g.b * g.b), 0, 0, -1}
                                                 : std::array<double, 6>{0, 0, 1, -4 * g.a, 0, 0};
    Curve3 c;
    try {
      c = conic_arc(coef, s, t, 0.0, hyperbola ? 2 : 3);
    } catch (const std::invalid_argument& x) {
      fail(e, fmt::format("its arc between the vertices: {}", x.what()));
    }
    for (glm::dvec3& q : c.points) q = g.f.o + q.x * g.f.x + q.y * g.f.y;
    pieces.push_back({c, {}});
  } else {
    const Curve3& c = g.nurbs;
    const Interval d = curve_domain(c);
    const double ta = Analytic::nearest_t(c, a, d), tb = Analytic::nearest_t(c, b, d);
    const double t0 = same ? ta : tb, t1 = same ? tb : ta;
    const bool closed = glm::length(curve_point(c, d.min) - curve_point(c, d.max)) <= 1e-9 * (1 + size);
    const double eps = 1e-12 * d.width();
    std::vector<Interval> along;  // in the curve's direction from t0 to t1
    if (t1 > t0 + eps) {
      along.push_back(t0 <= d.min + eps && t1 >= d.max - eps ? d : Interval{t0, t1});
    } else if (closed) {  // through the closing point (or the whole closed curve)
      if (t0 < d.max - eps) along.push_back({t0, d.max});
      if (t1 > d.min + eps) along.push_back({d.min, t1});
      if (along.empty()) along.push_back(d);
    } else {
      fail(e, "its vertices do not lie in order on its curve");
    }
    if (!same) std::reverse(along.begin(), along.end());
    const StepEntity& ge = entity(geometry, e);
    for (const Interval& range : along) {
      EdgePiece piece{range.min <= d.min && range.max >= d.max ? c : restrict_curve(c, range.min, range.max),
                      pcurves(ge, g, range.min, range.max)};
      if (!same) {
        piece.c = reversed(piece.c);
        for (auto& pc : piece.pcurves) pc.second = reversed(pc.second);
      }
      pieces.push_back(std::move(piece));
    }
  }
  edge_index_.emplace(id, static_cast<int>(edge_index_.size()));
  return edges_.emplace(id, std::move(pieces)).first->second;
}

FaceSurface StepReader::surface(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  FaceSurface s;
  Analytic& a = s.analytic;
  if (e.record("B_SPLINE_SURFACE_WITH_KNOTS") || e.record("QUASI_UNIFORM_SURFACE") || e.record("UNIFORM_SURFACE") ||
      e.record("BEZIER_SURFACE")) {
    s.bspline = bspline_surface(e);
    return s;
  }
  if (const StepRecord* r = e.record("PLANE")) {
    a.type = Analytic::Plane;
    a.f = placement(ref(e, *r, 1, "position"), e);
    return s;
  }
  auto positive = [&](const StepRecord& r, size_t i, const char* what) {
    const double x = real(e, r, i, what);
    if (!(x > 0)) fail(e, fmt::format("its {} {} is not positive", what, x));
    return x;
  };
  if (const StepRecord* r = e.record("CYLINDRICAL_SURFACE")) {
    a.type = Analytic::Cylinder;
    a.f = placement(ref(e, *r, 1, "position"), e);
    a.r = positive(*r, 2, "radius");
    return s;
  }
  if (const StepRecord* r = e.record("CONICAL_SURFACE")) {
    a.type = Analytic::Cone;
    a.f = placement(ref(e, *r, 1, "position"), e);
    a.r = real(e, *r, 2, "radius");
    const double angle = real(e, *r, 3, "semi-angle") * angle_scale_;
    if (!(a.r >= 0)) fail(e, "its radius is negative");
    if (!(angle > 0 && angle < kPi / 2)) fail(e, fmt::format("its semi-angle {} rad is not in (0, pi/2)", angle));
    a.tan_angle = std::tan(angle);
    return s;
  }
  if (const StepRecord* r = e.record("SPHERICAL_SURFACE")) {
    a.type = Analytic::Sphere;
    a.f = placement(ref(e, *r, 1, "position"), e);
    a.r = positive(*r, 2, "radius");
    return s;
  }
  if (const StepRecord* r = e.record("TOROIDAL_SURFACE")) {
    a.type = Analytic::Torus;
    a.f = placement(ref(e, *r, 1, "position"), e);
    a.r = positive(*r, 2, "major radius");
    a.r2 = positive(*r, 3, "minor radius");
    return s;
  }
  if (const StepRecord* r = e.record("SURFACE_OF_REVOLUTION")) {
    a.type = Analytic::Revolution;
    const CurveGeom swept = curve(ref(e, *r, 1, "swept curve"), e, 0);
    if (swept.nurbs.points.empty())
      throw SkipFace{fmt::format("its surface #{} sweeps an open conic (hyperbola or parabola), which is not read", e.id)};
    a.curve = swept.nurbs;
    a.line = swept.type == CurveGeom::Line;
    const StepEntity& ax = entity(ref(e, *r, 2, "axis position"), e);
    const StepRecord& ar = record(ax, "AXIS1_PLACEMENT");
    a.f.o = point(ref(ax, ar, 1, "location"), ax);
    const StepValue& dv = param(ax, ar, 2, "axis");
    a.f.z = dv.kind == Kind::Null ? glm::dvec3(0, 0, 1) : direction(ref(ax, dv, "axis"), ax);
    a.f.x = default_x(a.f.z);
    a.f.y = glm::cross(a.f.z, a.f.x);
    a.t_range = curve_domain(a.curve);
    a.accept = 1e-6 * control_box_diagonal(a.curve);
    // The profile's angle about the axis, at its control point farthest from the axis.
    double best = -1;
    for (const glm::dvec3& q : a.curve.points) {
      const glm::dvec3 d = q - a.f.o;
      const double x = glm::dot(d, a.f.x), y = glm::dot(d, a.f.y);
      if (std::hypot(x, y) > best) best = std::hypot(x, y), a.phi0 = std::atan2(y, x);
    }
    return s;
  }
  if (const StepRecord* r = e.record("SURFACE_OF_LINEAR_EXTRUSION")) {
    a.type = Analytic::Extrusion;
    const CurveGeom swept = curve(ref(e, *r, 1, "swept curve"), e, 0);
    if (swept.nurbs.points.empty())
      throw SkipFace{fmt::format("its surface #{} sweeps an open conic (hyperbola or parabola), which is not read", e.id)};
    a.curve = swept.nurbs;
    a.line = swept.type == CurveGeom::Line;
    const StepEntity& vec = entity(ref(e, *r, 2, "extrusion axis"), e);
    a.dir = direction(ref(vec, record(vec, "VECTOR"), 1, "orientation"), vec);
    a.t_range = curve_domain(a.curve);
    a.flat = a.curve;
    for (glm::dvec3& q : a.flat.points) q -= glm::dot(q, a.dir) * a.dir;
    a.accept = 1e-6 * control_box_diagonal(a.curve);
    return s;
  }
  throw SkipFace{fmt::format("its surface #{} is a {}, which is not read", e.id, e.type_name())};
}

std::vector<StepReader::Loop> StepReader::face_loops(const StepEntity& face, long surface) {
  const StepRecord& fr = face.record("ADVANCED_FACE") ? *face.record("ADVANCED_FACE") : record(face, "FACE_SURFACE");
  std::vector<Loop> loops;
  for (const StepValue& bv : list(face, param(face, fr, 1, "bounds"), "bounds")) {
    const StepEntity& bound = entity(ref(face, bv, "bound"), face);
    const bool outer = is(bound, "FACE_OUTER_BOUND");
    const StepRecord& br = outer ? record(bound, "FACE_OUTER_BOUND") : record(bound, "FACE_BOUND");
    const bool orientation = logical(bound, param(bound, br, 2, "orientation"), "orientation");
    const StepEntity& le = entity(ref(bound, br, 1, "loop"), bound);
    if (is(le, "VERTEX_LOOP")) continue;  // a pole or apex: no curve
    Loop loop;
    loop.outer = outer;
    for (const StepValue& ov : list(le, param(le, record(le, "EDGE_LOOP"), 1, "edge list"), "edge list")) {
      const StepEntity& oe = entity(ref(le, ov, "oriented edge"), le);
      // ISO 10303-42 ORIENTED_EDGE (and AP242's SEAM_EDGE, one of them): (name, edge_start,
      // edge_end (both derived: *), edge_element, orientation[, pcurve_reference]).
      const StepRecord& orr = oe.record("SEAM_EDGE") ? *oe.record("SEAM_EDGE") : record(oe, "ORIENTED_EDGE");
      const long ec = ref(oe, orr, 3, "edge element");
      const bool forward = logical(oe, param(oe, orr, 4, "orientation"), "orientation");
      const std::vector<EdgePiece>& pieces = edge(ec, oe);
      const int index = edge_index_.at(ec);
      auto add = [&](const EdgePiece& p, bool flip) {
        loop.curves.push_back(flip ? reversed(p.c) : p.c);
        loop.edges.push_back(index);
        loop.pcurves.emplace_back();
        for (const auto& [on, pc] : p.pcurves)
          if (on == surface) loop.pcurves.back().push_back(flip ? reversed(pc) : pc);
      };
      if (forward) {
        for (const EdgePiece& p : pieces) add(p, false);
      } else {
        for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) add(*it, true);
      }
    }
    if (!orientation) reverse(loop);
    if (!loop.curves.empty()) loops.push_back(std::move(loop));
  }
  return loops;
}

void StepReader::reverse(Loop& loop) {
  std::reverse(loop.curves.begin(), loop.curves.end());
  std::reverse(loop.edges.begin(), loop.edges.end());
  std::reverse(loop.pcurves.begin(), loop.pcurves.end());
  for (Curve3& c : loop.curves) c = reversed(c);
  for (auto& options : loop.pcurves)
    for (Curve3& c : options) c = reversed(c);
}

StepReader::FaceJob StepReader::face_job(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  const StepRecord& fr = e.record("ADVANCED_FACE") ? *e.record("ADVANCED_FACE") : record(e, "FACE_SURFACE");
  FaceJob job;
  job.f.face_id = static_cast<int>(e.id);
  if (const StepValue& n = param(e, fr, 0, "name"); n.kind == Kind::String) job.f.name = n.text;
  job.f.reversed = !logical(e, param(e, fr, 3, "same_sense"), "same_sense");
  try {
    const long surface_id = ref(e, fr, 2, "face geometry");
    job.loops = face_loops(e, surface_id);
    // The bounds run counter-clockwise round the material seen against the face's normal, which is
    // the surface's turned round where same_sense is false: on the surface, they run the other way.
    // (Only a loop going round a closed surface alone, a cap, needs the direction: its material side
    // picks the side of the domain it is closed along.)
    if (job.f.reversed)
      for (Loop& l : job.loops) reverse(l);
    job.fs = surface(surface_id, e);
  } catch (const SkipFace& s) {
    job.skipped = s.reason;
  }
  return job;
}

std::optional<StepReader::GivenLoop> StepReader::given_loop(const Loop& loop, const Surface& s) {
  const size_t n = loop.curves.size();
  for (size_t k = 0; k < n; ++k)
    if (loop.pcurves[k].empty()) return std::nullopt;
  auto start = [](const Curve3& c) { return glm::dvec2(c.points.front()); };
  auto end = [](const Curve3& c) { return glm::dvec2(c.points.back()); };
  // Each first choice, then the nearest continuation; the choice whose gaps sum least.
  double best_gap = std::numeric_limits<double>::infinity();
  std::vector<const Curve3*> best;
  for (const Curve3& first : loop.pcurves[0]) {
    std::vector<const Curve3*> chosen{&first};
    double gap = 0.0;
    for (size_t k = 1; k < n; ++k) {
      const Curve3* pick = nullptr;
      double d = std::numeric_limits<double>::infinity();
      for (const Curve3& o : loop.pcurves[k])
        if (glm::length(start(o) - end(*chosen.back())) < d) d = glm::length(start(o) - end(*chosen.back())), pick = &o;
      chosen.push_back(pick);
      gap += d;
    }
    gap += glm::length(start(*chosen.front()) - end(*chosen.back()));
    if (gap < best_gap) best_gap = gap, best = chosen;
  }
  GivenLoop out;
  out.loop.outer = loop.outer;
  for (size_t k = 0; k < n; ++k) {
    out.gap = std::max(out.gap, trim_gap(*best[k], loop.curves[k], s));
    out.loop.curves.push_back(to_2d(*best[k]));
    out.loop.curves.back().edge = loop.edges[k];
  }
  return out;
}

std::vector<TrimmedSurface> StepReader::build_faces(std::vector<FaceJob>& jobs) {
  std::vector<std::optional<TrimmedSurface>> built(jobs.size());
  parallel_for(jobs.size(), 0, [&](size_t k, int) {
    if (!jobs[k].skipped.empty()) return;
    try {
      built[k] = build_face(jobs[k]);
    } catch (const SkipFace& s) {
      jobs[k].skipped = s.reason;
    }
  });
  std::vector<TrimmedSurface> out;
  for (size_t k = 0; k < jobs.size(); ++k) {
    if (built[k]) {
      out.push_back(std::move(*built[k]));
    } else {
      log_.warnings.push_back(fmt::format("face #{} dropped: {}", jobs[k].f.face_id, jobs[k].skipped));
      dropped_.push_back({fmt::format("#{}", jobs[k].f.face_id), jobs[k].skipped});
    }
  }
  return out;
}

TrimmedSurface StepReader::build_face(FaceJob& job) const {
  const std::vector<Loop>& loops = job.loops;
  const FaceSurface& fs = job.fs;
  TrimmedSurface f = job.f;
  const Analytic& a = fs.analytic;
  if (loops.empty()) {
    if (fs.bspline) {
      f.surface = *fs.bspline;  // the whole surface
      return f;
    }
    // A closed analytic surface without edges (a sphere bounded by a VERTEX_LOOP at a pole, a
    // torus) is the whole surface; the others have no extent.
    if (a.type == Analytic::Sphere) {
      f.surface = a.build({-kPi, -kPi / 2}, {kPi, kPi / 2}).surface;
      return f;
    }
    if (a.type == Analytic::Torus) {
      f.surface = a.build({-kPi, -kPi}, {kPi, kPi}).surface;
      return f;
    }
    throw SkipFace{"an analytic surface without edges has no extent"};
  }
  // Size of the face from its edges: the flattening tolerance scales with it.
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const Loop& l : loops)
    for (const Curve3& c : l.curves)
      for (const glm::dvec3& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double size = glm::length(hi - lo);
  // Edges within this distance of the surface (trims' surface points within it of the edges) lie on
  // it up to rounding: TrimmedSurface::edge_gap stays 0. The same floor as the IGES reader's, and
  // not the file's stated uncertainty: a writer's 0.01 mm is far above the bounds of answers near
  // the edge, which must carry the gap.
  const double lie_off = kProjectionTolerance * size;
  // The face's edge_gap from the largest gap `off` measured; beyond kStepMaxEdgeGap of the face's size
  // (or not finite) the face is dropped.
  auto set_gap = [&](double off) {
    if (!(off <= kStepMaxEdgeGap * size))
      throw SkipFace{
          fmt::format("its edges lie up to {:.3g} from its surface, more than {:g} % of the face's size {:.3g}", off,
                      100 * kStepMaxEdgeGap, size)};
    f.edge_gap = off > lie_off ? off : 0.0;
  };
  if (!fs.bspline && a.type == Analytic::Plane) {
    // Affine: the control points' plane coordinates (exact, weights kept). The patch spans the
    // curves' box (16 samples per knot span, 1 % wider: an arc of a 90-degree span bulges 0.12 %
    // of its radius between them), not their control points' (a circle's reach 1.41 times out).
    Box2 box;
    for (const Loop& l : loops) {
      TrimLoop t;
      t.outer = l.outer;
      for (size_t k = 0; k < l.curves.size(); ++k) {
        const Curve3& c = l.curves[k];
        Curve2 c2{c.degree, c.knots, {}, c.weights, l.edges[k]};
        for (const glm::dvec3& q : c.points) c2.points.push_back(a.natural(q, std::nullopt));
        const Interval d = curve_domain(c2);
        const int n = 16 * std::max<int>(1, static_cast<int>(c2.points.size()) - c2.degree);
        for (int i = 0; i <= n; ++i) box.add(curve_point(c2, d.min + d.width() * i / n));
        t.curves.push_back(std::move(c2));
      }
      f.loops.push_back(std::move(t));
    }
    const glm::dvec2 margin = 0.01 * (box.hi - box.lo);
    if (!(margin.x > 0 && margin.y > 0)) throw SkipFace{"its edges span no area of its plane"};
    // The edges are projected onto the plane along its normal: the gap is their height above it.
    double off = 0.0;
    for (const Loop& l : loops)
      for (const Curve3& c : l.curves) {
        const Interval d = curve_domain(c);
        for (int i = 0; i <= kGapSamples; ++i)
          off = std::max(off, std::abs(glm::dot(curve_point(c, d.min + d.width() * i / kGapSamples) - a.f.o, a.f.z)));
      }
    set_gap(off);
    f.surface = a.build(box.lo - margin, box.hi + margin).surface;
    if (std::none_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; })) mark_outer(f);
    return f;
  }
  // An analytic surface becomes NURBS first, over the box of its edges' parameters from a coarse
  // pass (angles unwrapped along each loop, loops shifted by whole turns onto the first outer loop's
  // branch), widened by a margin for what the edges reach between samples; its edges are then
  // brought into the NURBS parameters as on a B-spline surface, with the closed-form inverse.
  AnalyticSurface as;
  std::vector<glm::dvec2> loop_start(loops.size(), glm::dvec2(std::numeric_limits<double>::quiet_NaN()));
  if (fs.bspline) {
    as.surface = *fs.bspline;
  } else {
    std::vector<Box2> boxes(loops.size());
    std::vector<std::vector<glm::dvec2>> coarse(loops.size());  // per loop: its samples, NaN u on the axis
    for (size_t li = 0; li < loops.size(); ++li) {
      std::optional<glm::dvec2> prev;
      for (const Curve3& c : loops[li].curves) {
        const Interval d = curve_domain(c);
        const int n = 8 * std::max<int>(1, static_cast<int>(c.points.size()) - c.degree);
        for (int i = 0; i <= n; ++i) {
          const glm::dvec2 uv = a.natural(curve_point(c, d.min + d.width() * i / n), prev);
          if (!std::isfinite(uv.y)) continue;
          coarse[li].push_back(uv);
          if (std::isfinite(uv.x)) prev = uv;
        }
      }
    }
    size_t first = 0;
    for (size_t li = 0; li < loops.size(); ++li)
      if (loops[li].outer) {
        first = li;
        break;
      }
    if (a.u_angular() && !coarse.empty()) choose_branches_across_axis(coarse[first]);
    for (size_t li = 0; li < loops.size(); ++li) {
      // A point on the axis (a pole, an apex) has no angle of its own but its latitude or height
      // belongs to the box: a meridian ending at a pole takes the patch up to it.
      for (const glm::dvec2& uv : coarse[li])
        if (std::isfinite(uv.x)) {
          if (!std::isfinite(loop_start[li].x)) loop_start[li] = uv;
          boxes[li].add(uv);
        }
      if (!std::isfinite(loop_start[li].x)) throw SkipFace{"an edge loop has no parameters on its surface"};
      for (const glm::dvec2& uv : coarse[li])
        if (!std::isfinite(uv.x)) boxes[li].add({boxes[li].lo.x, uv.y});
    }
    const glm::dvec2 centre = boxes[first].centre();
    Box2 all;
    for (size_t li = 0; li < loops.size(); ++li) {
      const glm::dvec2 m = boxes[li].centre();
      glm::dvec2 shift(0.0);
      if (a.u_angular()) shift.x = wrap_near(m.x, centre.x) - m.x;
      if (a.v_periodic()) shift.y = wrap_near(m.y, centre.y) - m.y;
      loop_start[li] += shift;
      all.add(boxes[li].lo + shift);
      all.add(boxes[li].hi + shift);
    }
    // A loop going once round the axis alone bounds a cap: the material reaches the apex of a cone
    // or a pole of a sphere, which no edge touches (a spherical cap bounded by one circle spans
    // no latitude of its own). The patch reaches them, and stops there; the trim keeps the
    // material side.
    int round_loops = 0;
    for (const Box2& b : boxes) round_loops += a.u_angular() && b.hi.x - b.lo.x >= 2 * kPi - 1e-6;
    std::optional<double> apex;
    if (round_loops % 2 == 1 && a.type == Analytic::Sphere) {
      all.lo.y = -kPi / 2, all.hi.y = kPi / 2;
    } else if (round_loops % 2 == 1 && a.type == Analytic::Cone && a.tan_angle != 0.0) {
      apex = -a.r / a.tan_angle;
      all.lo.y = std::min(all.lo.y, *apex), all.hi.y = std::max(all.hi.y, *apex);
    }
    const glm::dvec2 extent = all.hi - all.lo, turn(a.u_angular() ? 2 * kPi : 0.0, a.v_periodic() ? 2 * kPi : 0.0);
    for (int k = 0; k < 2; ++k) {
      const double margin = 0.01 * extent[k] + 1e-9 * size;
      if (turn[k] > 0 && extent[k] + 2 * margin >= turn[k] - 1e-6) {  // a whole turn
        all.lo[k] = 0.5 * (all.lo[k] + all.hi[k]) - kPi;
        all.hi[k] = all.lo[k] + 2 * kPi;
      } else if (a.type != Analytic::Sphere || k == 0) {
        all.lo[k] -= margin, all.hi[k] += margin;
      } else {  // latitude within the poles
        all.lo[k] = std::max(all.lo[k] - margin, -kPi / 2), all.hi[k] = std::min(all.hi[k] + margin, kPi / 2);
      }
    }
    if (apex) (*apex <= all.lo.y + extent.y / 2 ? all.lo.y : all.hi.y) = *apex;  // not past it, onto the other nappe
    if (!(all.hi.x > all.lo.x && all.hi.y > all.lo.y)) throw SkipFace{"its edges span no area of its surface"};
    as = a.build(all.lo, all.hi);
    for (glm::dvec2& q : loop_start) q = as.map(q);
  }
  const double accept = std::max(1e-6 * size, resolution_);
  const Chart chart = fs.bspline ? bspline_chart(as.surface, accept) : analytic_chart(a, as);
  // Each loop sampled along its edges in the surface's parameters, periodic ones unwrapped from
  // sample to sample; chords halved while the surface point of a chord's middle is farther than
  // the tolerance from the surface point of the edge's middle.
  const double tol = std::max(kStepTrimTolerance * size, 1e-300);
  std::vector<std::vector<std::vector<glm::dvec2>>> lines(loops.size());
  std::vector<double> off_loop(loops.size(), 0.0);  // per loop: farthest edge sample from the surface
  // Cubic Hermite pieces in (u, v) through the samples with the edge's (u, v) tangents
  // [Su Sv] (du, dv)' = C'(t) in least squares: few samples for a tight tolerance (error O(h^4));
  // Newton starts from the tangent's prediction.
  // Loops whose every edge has a parameter-space curve on this B-spline surface (files that carry
  // PCURVEs) take those when their surface points lie on the edges within the acceptance distance:
  // exact, no inversion. Otherwise the edges are projected; where the projection lies off too (the
  // edges are not on the surface), the given curves are the face's boundary, as in the writer.
  std::vector<std::optional<GivenLoop>> given(loops.size());
  if (fs.bspline)
    for (size_t li = 0; li < loops.size(); ++li) given[li] = given_loop(loops[li], as.surface);
  auto exact = [&](size_t li) { return given[li] && given[li]->gap <= accept; };
  for (size_t li = 0; li < loops.size(); ++li) {
    if (exact(li)) continue;
    double& off = off_loop[li];
    std::optional<glm::dvec2> prev;
    if (std::isfinite(loop_start[li].x)) prev = loop_start[li];
    for (const Curve3& c : loops[li].curves) {
      const Interval d = curve_domain(c);
      std::vector<glm::dvec2> line;
      struct Sample {
        double t;
        glm::dvec2 uv, duv;
        double gap;  // |S(uv) - C(t)|: how far the edge lies from the surface there
      };
      auto at = [&](double t, const std::optional<glm::dvec2>& near) {
        const std::vector<glm::dvec3> cd = curve_derivatives(c, t, 1);
        Sample out{t, chart.natural(cd[0], near), glm::dvec2(std::numeric_limits<double>::quiet_NaN()), 0.0};
        if (!std::isfinite(out.uv.x) || !std::isfinite(out.uv.y)) return out;
        out.gap = glm::length(chart.point(out.uv) - cd[0]);
        off = std::max(off, out.gap);
        const SurfaceDerivatives sd = chart.derivatives(out.uv);
        const double a11 = glm::dot(sd.su, sd.su), a12 = glm::dot(sd.su, sd.sv), a22 = glm::dot(sd.sv, sd.sv);
        const double b1 = glm::dot(sd.su, cd[1]), b2 = glm::dot(sd.sv, cd[1]), det = a11 * a22 - a12 * a12;
        if (det > 1e-12 * a11 * a22) out.duv = glm::dvec2(a22 * b1 - a12 * b2, a11 * b2 - a12 * b1) / det;
        return out;
      };
      auto predict = [&](const Sample& s, double t) {
        return std::isfinite(s.duv.x) ? s.uv + s.duv * (t - s.t) : s.uv;
      };
      // A piece is kept when the surface point of its Hermite middle lies within the tolerance of
      // the edge's middle, beyond the edge's own distance from the surface at the piece's ends; else
      // the middle is inverted and both halves are tried.
      std::function<void(const Sample&, const Sample&, int)> refine = [&](const Sample& s0, const Sample& s1,
                                                                          int depth) {
        const double h = s1.t - s0.t, tm = 0.5 * (s0.t + s1.t);
        const glm::dvec2 chord = (s1.uv - s0.uv) / h;
        const glm::dvec2 d0 = std::isfinite(s0.duv.x) ? s0.duv : chord, d1 = std::isfinite(s1.duv.x) ? s1.duv : chord;
        const glm::dvec2 mid = 0.5 * (s0.uv + s1.uv) + h / 8 * (d0 - d1);
        const bool finite = std::isfinite(mid.x) && std::isfinite(mid.y);
        if (depth < 12 &&
            (!finite || glm::length(chart.point(mid) - curve_point(c, tm)) > tol + std::max(s0.gap, s1.gap))) {
          const Sample sm = at(tm, predict(s0, tm));
          refine(s0, sm, depth + 1);
          refine(sm, s1, depth + 1);
          return;
        }
        line.insert(line.end(), {s0.uv + h / 3 * d0, s1.uv - h / 3 * d1, s1.uv});
      };
      const int n = 2 * std::max<int>(1, static_cast<int>(c.points.size()) - c.degree);
      Sample s0 = at(d.min, prev);
      line.push_back(s0.uv);
      std::vector<Sample> steps{s0};
      for (int i = 1; i <= n; ++i) {
        const double t1 = d.min + d.width() * i / n;
        const Sample s1 = at(t1, predict(s0, t1));
        refine(s0, s1, 0);
        s0 = s1;
        steps.push_back(s1);
      }
      // The gap between samples as well: the samples above are only as dense as the trim's shape
      // needs. Each starts from the tangent's prediction of the preceding step sample, as above.
      for (int i = 1; i < kGapSamples; ++i) {
        const double t = d.min + d.width() * i / kGapSamples;
        const size_t k = std::min(steps.size() - 1, static_cast<size_t>((t - d.min) / d.width() * n));
        (void)at(t, predict(steps[k], t));
      }
      prev = line.back();
      lines[li].push_back(std::move(line));
    }
  }
  // Per loop: the given curves when exact or when the projection lies off as far as they do or farther
  // (then their gap counts), else the projection (its gap counts).
  double off = 0.0;
  for (size_t li = 0; li < loops.size(); ++li) {
    if (exact(li)) {
      off = std::max(off, given[li]->gap);
      continue;
    }
    if (given[li] && off_loop[li] > lie_off && given[li]->gap <= off_loop[li]) {
      off = std::max(off, given[li]->gap);
      lines[li].clear();
    } else {
      off = std::max(off, off_loop[li]);
      given[li].reset();
    }
  }
  set_gap(off);
  if (!fs.bspline && chart.period.x > 0)
    for (auto& loop : lines) unwrap_across_axis(loop, chart.period.x);
  // Points on an axis (apex, pole) take the angle of their neighbour along the loop.
  for (auto& loop : lines) {
    std::vector<glm::dvec2*> pts;
    for (auto& l : loop)
      for (glm::dvec2& q : l) pts.push_back(&q);
    for (int pass = 0; pass < 2; ++pass)
      for (size_t i = 0; i < pts.size(); ++i)
        if (!std::isfinite(pts[i]->x)) {
          const glm::dvec2* n = i + 1 < pts.size() ? pts[i + 1] : nullptr;
          const glm::dvec2* p = i > 0 ? pts[i - 1] : nullptr;
          if (n && std::isfinite(n->x))
            pts[i]->x = n->x;
          else if (p && std::isfinite(p->x))
            pts[i]->x = p->x;
        }
    for (const glm::dvec2* q : pts)
      if (!std::isfinite(q->x) || !std::isfinite(q->y))
        throw SkipFace{"an edge point has no parameters on its surface"};
  }
  // Loops shifted by whole periods: onto the first (outer) loop's branch for an analytic surface,
  // whose NURBS is then built over them; into the domain of a B-spline surface.
  auto box = [](const std::vector<std::vector<glm::dvec2>>& loop) {
    Box2 b;
    for (const auto& l : loop)
      for (const glm::dvec2& q : l) b.add(q);
    return b;
  };
  {
    const Interval su = surface_domain_u(as.surface), sv = surface_domain_v(as.surface);
    for (auto& loop : lines) {
      const Box2 b = box(loop);
      glm::dvec2 shift(0.0);
      if (chart.period.x > 0)
        shift.x = chart.period.x * std::round((su.min + su.max - b.lo.x - b.hi.x) / (2 * chart.period.x));
      if (chart.period.y > 0)
        shift.y = chart.period.y * std::round((sv.min + sv.max - b.lo.y - b.hi.y) / (2 * chart.period.y));
      for (auto& l : loop)
        for (glm::dvec2& q : l) q += shift;
    }
  }
  f.surface = as.surface;
  const Interval su = surface_domain_u(f.surface), sv = surface_domain_v(f.surface);
  for (size_t li = 0; li < loops.size(); ++li) {
    if (given[li]) {
      f.loops.push_back(std::move(given[li]->loop));
      continue;
    }
    TrimLoop t;
    t.outer = loops[li].outer;
    for (size_t k = 0; k < lines[li].size(); ++k) {
      const auto& line = lines[li][k];
      Curve2 c;
      c.edge = loops[li].edges[k];
      c.degree = 3;
      for (const glm::dvec2& q : line) {
        // Along a periodic direction a loop may run past the domain's side (a circle round a band
        // whose vertex is not on the seam): kept, for wrap_loops_into_domain to cut at the seam.
        c.points.emplace_back(chart.period.x > 0 ? q.x : std::clamp(q.x, su.min, su.max),
                              chart.period.y > 0 ? q.y : std::clamp(q.y, sv.min, sv.max));
      }
      // Knots: 0, 1, ... at the samples, inner ones of multiplicity `degree` (Hermite pieces join C1
      // in shape, their Bezier form is kept).
      const int pieces = static_cast<int>(line.size() - 1) / c.degree;
      c.knots.assign(static_cast<size_t>(c.degree) + 1, 0.0);
      for (int i = 1; i < pieces; ++i)
        c.knots.insert(c.knots.end(), static_cast<size_t>(c.degree), static_cast<double>(i));
      c.knots.insert(c.knots.end(), static_cast<size_t>(c.degree) + 1, static_cast<double>(pieces));
      t.curves.push_back(std::move(c));
    }
    f.loops.push_back(std::move(t));
  }
  // Without FACE_OUTER_BOUND, the loop of the largest parameter box is the outer one.
  if (std::none_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; })) mark_outer(f);
  return f;
}

void StepReader::shell_faces(long id, const StepEntity& from, bool reversed, std::vector<FaceJob>& out) {
  const StepEntity& e = entity(id, from);
  const StepRecord* oriented = e.record("ORIENTED_CLOSED_SHELL");
  if (!oriented) oriented = e.record("ORIENTED_OPEN_SHELL");
  if (oriented) {
    // ISO 10303-42: (name, cfs_faces (derived: *), closed / open_shell_element, orientation).
    const bool o = logical(e, param(e, *oriented, 3, "orientation"), "orientation");
    const StepEntity& inner = entity(ref(e, *oriented, 2, "shell element"), e);
    if (is(inner, "ORIENTED_CLOSED_SHELL") || is(inner, "ORIENTED_OPEN_SHELL"))
      fail(e, "is an oriented shell of an oriented shell");
    shell_faces(inner.id, e, reversed != !o, out);
    return;
  }
  const StepRecord* r = e.record("CLOSED_SHELL");
  if (!r) r = e.record("OPEN_SHELL");
  if (!r) fail(e, "is not a CLOSED_SHELL or OPEN_SHELL");
  for (const StepValue& fv : list(e, param(e, *r, 1, "faces"), "faces")) {
    const StepEntity& fe = entity(ref(e, fv, "face"), e);
    bool flip = reversed;
    long face = fe.id;
    if (const StepRecord* o = fe.record("ORIENTED_FACE")) {
      // ISO 10303-42: (name, bounds (derived: *), face_element, orientation).
      flip = flip != !logical(fe, param(fe, *o, 3, "orientation"), "orientation");
      face = ref(fe, *o, 2, "face element");
    }
    FaceJob job = face_job(face, fe);
    job.f.reversed = job.f.reversed != flip;
    out.push_back(std::move(job));
  }
}

std::vector<StepReader::FaceJob> StepReader::solid(const StepEntity& e) {
  std::vector<FaceJob> faces;
  if (const StepRecord* r = e.record("MANIFOLD_SOLID_BREP")) {
    shell_faces(ref(e, *r, 1, "outer shell"), e, false, faces);
    if (const StepRecord* v = e.record("BREP_WITH_VOIDS"))
      for (const StepValue& s : list(e, param(e, *v, e.records.size() == 1 ? 2 : 0, "voids"), "voids"))
        shell_faces(ref(e, s, "void shell"), e, false, faces);
  } else if (const StepRecord* b = e.record("BREP_WITH_VOIDS")) {
    shell_faces(ref(e, *b, 1, "outer shell"), e, false, faces);
    for (const StepValue& s : list(e, param(e, *b, 2, "voids"), "voids"))
      shell_faces(ref(e, s, "void shell"), e, false, faces);
  } else if (const StepRecord* m = e.record("SHELL_BASED_SURFACE_MODEL")) {
    for (const StepValue& s : list(e, param(e, *m, 1, "shells"), "shells"))
      shell_faces(ref(e, s, "shell"), e, false, faces);
  }
  return faces;
}

void StepReader::read_units(long context, const StepEntity& from) {
  const StepEntity& c = entity(context, from);
  const StepRecord* units = c.record("GLOBAL_UNIT_ASSIGNED_CONTEXT");
  if (!units) return;
  // SI prefixes of ISO 10303-41.
  static const std::unordered_map<std::string, double> prefixes = {
      {"EXA", 1e18},  {"PETA", 1e15},  {"TERA", 1e12},   {"GIGA", 1e9},   {"MEGA", 1e6},   {"KILO", 1e3},
      {"HECTO", 1e2}, {"DECA", 1e1},   {"DECI", 1e-1},   {"CENTI", 1e-2}, {"MILLI", 1e-3}, {"MICRO", 1e-6},
      {"NANO", 1e-9}, {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};
  // Size of a unit in SI base units (metre, radian), following conversion-based units.
  std::function<double(const StepEntity&, int)> si = [&](const StepEntity& u, int depth) -> double {
    if (depth > kMaxDepth) fail(u, "units nest too deep (a reference cycle?)");
    if (const StepRecord* s = u.record("SI_UNIT")) {
      // (prefix, name) in a complex instance; a simple one leads with NAMED_UNIT's dimensions (*).
      const StepValue& p = param(u, *s, s->params.size() >= 3 ? 1 : 0, "prefix");
      double f = 1.0;
      if (p.kind == Kind::Enum) {
        const auto it = prefixes.find(p.text);
        if (it == prefixes.end()) fail(u, fmt::format("unknown SI prefix .{}.", p.text));
        f = it->second;
      }
      return f;
    }
    if (const StepRecord* cb = u.record("CONVERSION_BASED_UNIT")) {
      const StepEntity& m = entity(ref(u, *cb, 1, "conversion factor"), u);
      if (m.records.empty() || m.records.front().params.size() < 2) fail(m, "is not a measure with unit");
      const StepRecord& mr = m.records.size() == 1 ? m.records.front() : *[&] {
        for (const StepRecord& r : m.records)
          if (r.params.size() >= 2) return &r;
        return &m.records.front();
      }();
      const double value = real(m, mr, 0, "value");
      const StepEntity& base = entity(ref(m, mr, 1, "unit"), m);
      const double x = value * si(base, depth + 1);
      if (!(x > 0) || !std::isfinite(x)) fail(m, "converts to a unit that is not positive");
      return x;
    }
    fail(u, "is a unit nurbsgl does not read");
  };
  for (const StepValue& uv : list(c, param(c, *units, 0, "units"), "units")) {
    const StepEntity& u = entity(ref(c, uv, "unit"), c);
    if (is(u, "LENGTH_UNIT")) length_scale_ = si(u, 0) * 1e3;
    if (is(u, "PLANE_ANGLE_UNIT")) angle_scale_ = si(u, 0);
  }
  if (const StepRecord* g = c.record("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT"))
    for (const StepValue& uv : list(c, param(c, *g, 0, "uncertainty"), "uncertainty")) {
      const StepEntity& u = entity(ref(c, uv, "uncertainty"), c);
      if (const StepRecord* ur = u.record("UNCERTAINTY_MEASURE_WITH_UNIT")) {
        const double x = real(u, *ur, 0, "uncertainty");
        if (x > 0 && (resolution_ == 0 || x < resolution_)) resolution_ = x;
      }
    }
}

void StepReader::link_representations() {
  // Representations related without a transform share one frame (union-find); with a transform,
  // the component's representation is placed in its assembly's.
  // Product structure first: which representation group belongs to which product definition.
  std::unordered_map<long, long> rep_of_pd;  // PRODUCT_DEFINITION -> shape representation
  std::unordered_map<long, long> pd_of_pds;  // PRODUCT_DEFINITION_SHAPE -> its definition
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (const StepRecord* r = e.record("PRODUCT_DEFINITION_SHAPE")) {
      intact(e);  // the assembly structure places the geometry
      if (r->params.size() >= 3 && r->params[2].kind == Kind::Ref) pd_of_pds[id] = r->params[2].ref;
      visited_.insert(id);
    }
  }
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (e.record("SHAPE_DEFINITION_REPRESENTATION")) intact(e);
    if (const StepRecord* r = e.record("SHAPE_DEFINITION_REPRESENTATION");
        r && r->params.size() >= 2 && r->params[0].kind == Kind::Ref && r->params[1].kind == Kind::Ref) {
      if (auto it = pd_of_pds.find(r->params[0].ref); it != pd_of_pds.end()) rep_of_pd[it->second] = r->params[1].ref;
      visited_.insert(id);
    }
  }
  struct Placed {
    long rep1, rep2;
    long transform;
    long relationship;
  };
  std::vector<Placed> placed;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    const StepRecord* r = e.record("REPRESENTATION_RELATIONSHIP");
    if (!r) r = e.record("SHAPE_REPRESENTATION_RELATIONSHIP");
    if (r) intact(e);
    if (!r || r->params.size() < 4) continue;
    visited_.insert(id);
    const long a = ref(e, *r, 2, "rep_1"), b = ref(e, *r, 3, "rep_2");
    entity(a, e), entity(b, e);
    if (const StepRecord* t = e.record("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")) {
      placed.push_back({a, b, ref(e, *t, 0, "transformation operator"), id});
    } else {
      const long ga = group(a), gb = group(b);
      if (ga != gb) group_[ga] = gb;
    }
  }
  // CONTEXT_DEPENDENT_SHAPE_REPRESENTATION: relationship -> the usage occurrence it places.
  std::unordered_map<long, long> nauo_of;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    const StepRecord* r = e.record("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION");
    if (r) intact(e);
    if (!r || r->params.size() < 2 || r->params[0].kind != Kind::Ref || r->params[1].kind != Kind::Ref) continue;
    visited_.insert(id);
    if (auto it = pd_of_pds.find(r->params[1].ref); it != pd_of_pds.end()) nauo_of[r->params[0].ref] = it->second;
  }
  for (const Placed& p : placed) {
    const StepEntity& rel = f_.entities.at(p.relationship);
    const StepEntity& t = entity(p.transform, rel);
    const StepRecord& tr = record(t, "ITEM_DEFINED_TRANSFORMATION");
    const glm::dmat4 m1 = frame_matrix(placement(ref(t, tr, 2, "transform_item_1"), t));
    const glm::dmat4 m2 = frame_matrix(placement(ref(t, tr, 3, "transform_item_2"), t));
    long child = p.rep1, parent = p.rep2;
    glm::dmat4 m = m2 * glm::inverse(m1);  // rep_1's item_1 frame onto rep_2's item_2 frame
    std::string name;
    if (auto it = nauo_of.find(p.relationship); it != nauo_of.end()) {
      const StepEntity& nauo = entity(it->second, rel);
      if (const StepRecord* nr = nauo.record("NEXT_ASSEMBLY_USAGE_OCCURRENCE"); nr && nr->params.size() >= 5) {
        if (nr->params[0].kind == Kind::String) name = nr->params[0].text;
        if (name.empty() && nr->params[1].kind == Kind::String) name = nr->params[1].text;
        // The component is the related product definition: if its shape is rep_2, turn round.
        if (nr->params[4].kind == Kind::Ref)
          if (auto rp = rep_of_pd.find(nr->params[4].ref);
              rp != rep_of_pd.end() && group(rp->second) == group(p.rep2)) {
            std::swap(child, parent);
            m = m1 * glm::inverse(m2);
          }
      }
    }
    parents_[group(child)].push_back({group(parent), m, name});
  }
  // Products by representation group, for body names.
  for (auto [pd, rep] : rep_of_pd) {
    const StepEntity* e = f_.find(pd);
    if (!e || !e->damage.empty()) continue;
    const StepRecord* r = e->record("PRODUCT_DEFINITION");
    if (!r || r->params.size() < 3 || r->params[2].kind != Kind::Ref) continue;
    const StepEntity* formation = f_.find(r->params[2].ref);
    if (!formation || !formation->damage.empty() || formation->records.empty() ||
        formation->records.front().params.size() < 3)
      continue;
    const StepValue& prod = formation->records.front().params[2];
    if (prod.kind == Kind::Ref) product_of_group_.emplace(group(rep), prod.ref);
  }
}

std::vector<Instance> StepReader::instances(long rep, int depth) {
  const long g = group(rep);
  const StepEntity* e = f_.find(rep);
  if (depth > kMaxDepth && e) fail(*e, fmt::format("assemblies nest deeper than {} (a reference cycle?)", kMaxDepth));
  const auto it = parents_.find(g);
  if (it == parents_.end()) return {Instance{}};
  std::vector<Instance> out;
  for (const Link& l : it->second)
    for (const Instance& p : instances(l.parent, depth + 1)) {
      out.push_back({p.m * l.m, p.path.empty() ? l.name : p.path + "/" + l.name});
      if (out.size() > kMaxInstances && e) fail(*e, fmt::format("is placed more than {} times", kMaxInstances));
    }
  return out;
}

std::string StepReader::product_name(long rep) {
  const auto it = product_of_group_.find(group(rep));
  if (it == product_of_group_.end()) return {};
  const StepEntity* p = f_.find(it->second);
  if (!p || !p->damage.empty()) return {};
  const StepRecord* r = p->record("PRODUCT");
  if (!r || r->params.size() < 2) return {};
  const std::string& name = r->params[1].kind == Kind::String ? r->params[1].text : std::string();
  if (!name.empty()) return name;
  return r->params[0].kind == Kind::String ? r->params[0].text : std::string();
}

Model StepReader::read() {
  Model model;
  model.source = f_.name;
  link_representations();
  // Solids and the representations that hold them.
  std::unordered_map<long, long> rep_of_item;
  std::unordered_map<long, long> context_of_rep;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    for (const StepRecord& r : e.records) {
      const std::string& t = r.type;
      if (t.size() < 14 || t.compare(t.size() - 14, 14, "REPRESENTATION") != 0 || r.params.size() < 3) continue;
      if (r.params[1].kind != Kind::List) continue;
      for (const StepValue& item : r.params[1].items)
        if (item.kind == Kind::Ref) rep_of_item.emplace(item.ref, id);
      if (r.params[2].kind == Kind::Ref) context_of_rep[id] = r.params[2].ref;
      if (e.damage.empty()) visited_.insert(id);
    }
  }
  int edge_base = 0;
  long long placed_points = 0;
  double model_scale = 0.0;
  std::unordered_map<std::string, int> name_count;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (!is(e, "MANIFOLD_SOLID_BREP") && !is(e, "BREP_WITH_VOIDS") && !is(e, "SHELL_BASED_SURFACE_MODEL")) continue;
    intact(e);
    visited_.insert(id);
    const auto rep = rep_of_item.find(id);
    if (rep != rep_of_item.end()) entity(rep->second, e);  // its units and placements
    length_scale_ = 1.0;
    angle_scale_ = 1.0;
    if (rep != rep_of_item.end())
      if (auto c = context_of_rep.find(rep->second); c != context_of_rep.end()) read_units(c->second, e);
    if (model_scale == 0.0) model_scale = length_scale_;
    edges_.clear();
    edge_index_.clear();
    std::vector<FaceJob> jobs = solid(e);
    if (rep != rep_of_item.end() && is(f_.entities.at(rep->second), "CONSTRUCTIVE_GEOMETRY_REPRESENTATION")) {
      // Supplemental geometry (reference planes, axes, construction surfaces: ISO 10303-242's
      // constructive geometry, as CATIA and NX write it beside the part): not the part's shape,
      // which OpenCASCADE does not transfer either. Said, not read.
      warnings_.push_back(fmt::format("#{} ({} face(s)): supplemental geometry of #{} (CONSTRUCTIVE_GEOMETRY_"
                                      "REPRESENTATION), not part of the shape, not read",
                                      id, jobs.size(), rep->second));
      model.skipped_types["supplemental geometry (CONSTRUCTIVE_GEOMETRY_REPRESENTATION) faces"] +=
          static_cast<int>(jobs.size());
      continue;
    }
    const std::vector<TrimmedSurface> faces = build_faces(jobs);
    const double to_model = length_scale_ / model_scale;
    std::string name = rep != rep_of_item.end() ? product_name(rep->second) : std::string();
    if (name.empty() && !e.records.front().params.empty() && e.records.front().params[0].kind == Kind::String)
      name = e.records.front().params[0].text;
    if (name.empty()) name = fmt::format("{} #{}", is(e, "SHELL_BASED_SURFACE_MODEL") ? "surface model" : "solid", id);
    const std::vector<Instance> placed =
        rep != rep_of_item.end() ? instances(rep->second, 0) : std::vector<Instance>{{}};
    const int edges = static_cast<int>(edge_index_.size());
    // Placed copies count against the IGES reader's budget of control points (kMaxPointsBase plus
    // one per byte): an assembly naming a part at every level twice would otherwise grow without
    // bound.
    long long points = 0;
    for (const TrimmedSurface& f : faces) points += static_cast<long long>(f.surface.points.size());
    placed_points += points * static_cast<long long>(placed.size());
    if (placed_points > kMaxPointsBase + static_cast<long long>(f_.bytes))
      fail(e, fmt::format("its {} placements would create more than {} control points in all", placed.size(),
                          kMaxPointsBase + static_cast<long long>(f_.bytes)));
    for (size_t k = 0; k < placed.size(); ++k) {
      Body body;
      const int n = name_count[name]++;
      body.name = n == 0 ? name : fmt::format("{} #{}", name, n + 1);
      body.instance = placed[k].path;
      body.closed = is(e, "MANIFOLD_SOLID_BREP") || is(e, "BREP_WITH_VOIDS");
      glm::dmat4 m = placed[k].m;
      if (to_model != 1.0) m = glm::scale(glm::dmat4(1.0), glm::dvec3(to_model)) * m;
      for (const TrimmedSurface& f : faces) {
        TrimmedSurface g = m == glm::dmat4(1.0) ? f : transformed(f, m);
        g.edge_gap = f.edge_gap * to_model;  // placements are rigid: only the unit scales it
        for (TrimLoop& l : g.loops)
          for (Curve2& c : l.curves) c.edge += edge_base;
        body.faces.push_back(std::move(g));
      }
      edge_base += edges;
      model.bodies.push_back(std::move(body));
    }
  }
  // Faces outside any shell (and shells outside any solid): one body of loose faces, as the IGES
  // reader keeps faces outside shells.
  Body loose{"faces", {}, glm::dmat4(1.0), {}};
  edges_.clear();
  edge_index_.clear();
  std::vector<FaceJob> jobs;
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    if (is(e, "CLOSED_SHELL") || is(e, "OPEN_SHELL")) shell_faces(id, e, false, jobs);
  }
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    if (is(e, "ADVANCED_FACE") || is(e, "FACE_SURFACE")) jobs.push_back(face_job(id, e));
  }
  loose.faces = build_faces(jobs);
  for (TrimmedSurface& f : loose.faces)
    for (TrimLoop& l : f.loops)
      for (Curve2& c : l.curves) c.edge += edge_base;
  if (!loose.faces.empty()) model.bodies.push_back(std::move(loose));
  model.unit_scale_to_mm = model_scale == 0.0 ? 1.0 : model_scale;
  model.resolution = resolution_;
  // Faces as placed: a solid an assembly places twice counts its faces twice, as the model holds them.
  model.faces_in_file = int(dropped_.size());
  for (const Body& b : model.bodies) model.faces_in_file += int(b.faces.size());
  model.dropped_faces = dropped_;
  // Loops finished once the model size is known (as the IGES reader does).
  std::vector<TrimmedSurface*> all;  // placements are in the geometry: no body transform
  for (Body& b : model.bodies)
    for (TrimmedSurface& f : b.faces) all.push_back(&f);
  std::vector<Box> boxes(all.size());  // model_size, the faces sampled on every core
  parallel_for(all.size(), 0, [&](size_t k, int) { boxes[k] = sampled_box(all[k]->surface); });
  Box box = boxes.empty() ? Box{} : boxes.front();
  for (const Box& b : boxes) box.min = glm::min(box.min, b.min), box.max = glm::max(box.max, b.max);
  double size = box.diagonal();
  if (!validate_model_size(size).empty()) size = 0.0;
  std::vector<IgesReadLog> logs(all.size());
  parallel_for(all.size(), 0, [&](size_t k, int) { finish_trim_loops(*all[k], size, logs[k]); });
  for (const IgesReadLog& l : logs) {
    log_.reoriented_loops += l.reoriented_loops;
    log_.outer_loops_fixed += l.outer_loops_fixed;
    log_.loops_wrapped += l.loops_wrapped;
    log_.reordered_loops += l.reordered_loops;
    log_.domain_loops_added += l.domain_loops_added;
    log_.gaps_closed += l.gaps_closed;
    log_.trim_problems.insert(log_.trim_problems.end(), l.trim_problems.begin(), l.trim_problems.end());
  }
  // Geometry and topology the reader did not reach.
  static const char* kinds[] = {"SURFACE", "CURVE", "FACE", "SHELL",  "BREP",    "SOLID",
                                "EDGE",    "LOOP",  "LINE", "CIRCLE", "ELLIPSE", "VERTEX"};
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    const std::string t = e.type_name();
    if (t == "CARTESIAN_POINT" || t == "DIRECTION" || t == "VECTOR" || t == "AXIS2_PLACEMENT_3D") continue;
    if (t.find("UNIT") != std::string::npos) continue;  // SOLID_ANGLE_UNIT and the like: not geometry
    for (const char* k : kinds)
      if (t.find(k) != std::string::npos && t.find("REPRESENTATION") == std::string::npos &&
          t.find("STYLE") == std::string::npos && t.find("PRESENTATION") == std::string::npos) {
        ++model.skipped_types[t];
        break;
      }
  }
  model.read_warnings.insert(model.read_warnings.end(), warnings_.begin(), warnings_.end());
  // Damaged records the geometry never reached (a reached one failed the read).
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (!e.damage.empty() && !visited_.count(id))
      model.read_warnings.push_back(fmt::format("line {}: #{} ({}): {}; the record is not used by the geometry", e.line,
                                                id, e.type_name(), e.damage));
  }
  return model;
}

}  // namespace

Model read_step_text(const std::string& text, const std::string& name, IgesReadLog* log) {
  IgesReadLog local;
  IgesReadLog& lg = log ? *log : local;
  const StepFile file = parse_step_file(text, name);
  StepReader reader(file, lg);
  return reader.read();
}

Model read_step(const std::filesystem::path& path, IgesReadLog* log) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ReadError(path.string(), "", "is a directory, not a STEP file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReadError(path.string(), "", "cannot open file");
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw ReadError(path.string(), "", "read error");
  return read_step_text(buf.str(), path.string(), log);
}

}  // namespace nurbs::io
