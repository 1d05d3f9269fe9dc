#include "nurbs/trim_classify.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "nurbs/bezier_extraction.h"
#include "nurbs/curve_eval.h"
#include "nurbs/surface_eval.h"

namespace nurbs {
namespace {

double distance_to_chord(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (len2 == 0.0) return glm::length(p - a);
  const double t = std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

void push_unique(std::vector<glm::dvec2>& out, glm::dvec2 p) {
  if (out.empty() || out.back() != p) out.push_back(p);
}

/// Point of a Bézier segment (clamped knots of full multiplicity, as extract_bezier_segments makes)
/// by de Casteljau's algorithm in homogeneous coordinates on the stack: flattening evaluates
/// thousands of points per loop, and the general evaluator allocates per call.
glm::dvec2 bezier_point(const Curve2& seg, double t) {
  constexpr int kMaxDegree = 31;
  const int p = seg.degree;
  if (p > kMaxDegree || seg.points.size() != size_t(p) + 1) return curve_point(seg, t);
  const double a = seg.knots.front(), b = seg.knots.back();
  const double s = b > a ? (t - a) / (b - a) : 0.0;
  std::array<glm::dvec3, kMaxDegree + 1> h;
  for (int i = 0; i <= p; ++i) {
    const double w = seg.weights.empty() ? 1.0 : seg.weights[size_t(i)];
    h[size_t(i)] = glm::dvec3(seg.points[size_t(i)] * w, w);
  }
  for (int r = 1; r <= p; ++r)
    for (int i = 0; i <= p - r; ++i) h[size_t(i)] = (1.0 - s) * h[size_t(i)] + s * h[size_t(i) + 1];
  return glm::dvec2(h[0].x, h[0].y) / h[0].z;
}

/// Appends points of (t0, t1] of a Bézier segment, bisecting until flat. Depth <= 30 bounds the
/// recursion for tiny tolerances; a non-finite deviation (overflowing or NaN points, from a damaged
/// file) counts as flat: bisection cannot fix it, and every branch would run to depth 30 (2^30 points).
void flatten_piece(const Curve2& seg, double t0, glm::dvec2 p0, double t1, glm::dvec2 p1, double tol, int depth,
                   std::vector<glm::dvec2>& out) {
  const double tm = 0.5 * (t0 + t1);
  const glm::dvec2 pm = bezier_point(seg, tm);
  auto flat_at = [&](glm::dvec2 p) {
    const double d = distance_to_chord(p, p0, p1);
    return d <= tol || !std::isfinite(d);
  };
  const bool flat = depth >= 30 || (flat_at(pm) && flat_at(bezier_point(seg, 0.5 * (t0 + tm))) &&
                                    flat_at(bezier_point(seg, 0.5 * (tm + t1))));
  // Depth >= 2 always: a whole Bézier segment can be symmetric with its quarter points on the chord.
  if (flat && depth >= 2) {
    push_unique(out, p1);
    return;
  }
  flatten_piece(seg, t0, p0, tm, pm, tol, depth + 1, out);
  flatten_piece(seg, tm, pm, t1, p1, tol, depth + 1, out);
}

}  // namespace

std::vector<glm::dvec2> flatten_curve(const Curve2& curve, double tolerance) {
  std::vector<glm::dvec2> out;
  for (const auto& seg : extract_bezier_segments(curve)) {
    const glm::dvec2 a = bezier_point(seg.curve, seg.range.min), b = bezier_point(seg.curve, seg.range.max);
    push_unique(out, a);
    if (seg.curve.degree == 1 && !seg.curve.rational()) {
      push_unique(out, b);
    } else {
      flatten_piece(seg.curve, seg.range.min, a, seg.range.max, b, tolerance, 0, out);
    }
  }
  return out;
}

double query_flatten_tolerance(const Surface& s) {
  return 1e-6 * std::min(surface_domain_u(s).width(), surface_domain_v(s).width());
}

double mesh_flatten_tolerance(const Surface& s) {
  return 1e-7 * std::max(surface_domain_u(s).width(), surface_domain_v(s).width());
}

TrimPolygons flatten_trim(const TrimmedSurface& face, double tolerance) {
  TrimPolygons t;
  t.domain_u = surface_domain_u(face.surface);
  t.domain_v = surface_domain_v(face.surface);
  // Curve ends that meet up to rounding (1e-6 of the flattening tolerance) are one vertex: a
  // sliver edge of length ~1e-15 at a junction would make its neighbours look non-adjacent and
  // their shared corner a self-crossing.
  const double merge = 1e-6 * tolerance;
  auto near = [merge](glm::dvec2 a, glm::dvec2 b) { return glm::length(a - b) <= merge; };
  for (const auto& loop : face.loops) {
    std::vector<glm::dvec2> poly;
    for (const auto& c : loop.curves) {
      const std::vector<glm::dvec2> pts = flatten_curve(c, tolerance);
      for (size_t i = 0; i < pts.size(); ++i)
        if (i > 0 || poly.empty() || !near(poly.back(), pts[i])) push_unique(poly, pts[i]);
    }
    if (poly.size() > 1 && near(poly.front(), poly.back())) poly.pop_back();
    t.loops.push_back(std::move(poly));
    t.outer.push_back(loop.outer);
  }
  return t;
}

int winding_number(const std::vector<glm::dvec2>& poly, glm::dvec2 p) {
  int wn = 0;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2 a = poly[i], b = poly[(i + 1) % n];
    const double side = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);  // > 0: p left of a->b
    if (a.y <= p.y) {
      if (b.y > p.y && side > 0) ++wn;
    } else if (b.y <= p.y && side < 0) {
      --wn;
    }
  }
  return wn;
}

bool segment_meets_box(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi) {
  double t0 = 0.0, t1 = 1.0;
  const glm::dvec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) {
      if (a[axis] < lo[axis] || a[axis] > hi[axis]) return false;
      continue;
    }
    double ta = (lo[axis] - a[axis]) / d[axis], tb = (hi[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

double signed_area(const std::vector<glm::dvec2>& poly) {
  double a = 0.0;
  const size_t n = poly.size();
  // Relative to the first vertex: fewer cancellation digits for loops far from the origin.
  for (size_t i = 1; i + 1 < n; ++i) {
    const glm::dvec2 e1 = poly[i] - poly[0], e2 = poly[i + 1] - poly[0];
    a += e1.x * e2.y - e2.x * e1.y;
  }
  return 0.5 * a;
}

bool is_material(const TrimPolygons& trim, glm::dvec2 uv) {
  if (uv.x < trim.domain_u.min || uv.x > trim.domain_u.max || uv.y < trim.domain_v.min || uv.y > trim.domain_v.max) {
    return false;
  }
  bool any_outer = false, in_outer = false;
  for (size_t k = 0; k < trim.loops.size(); ++k) {
    const bool inside = winding_number(trim.loops[k], uv) != 0;
    if (trim.outer[k]) {
      any_outer = true;
      in_outer = in_outer || inside;
    } else if (inside) {
      return false;
    }
  }
  return any_outer ? in_outer : true;
}

bool is_material(const TrimmedSurface& face, glm::dvec2 uv, double tolerance) {
  return is_material(flatten_trim(face, tolerance), uv);
}

double distance_to_loops(const TrimPolygons& trim, glm::dvec2 p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& loop : trim.loops)
    for (size_t k = 0; k < loop.size(); ++k) {
      const glm::dvec2 a = loop[k], d = loop[(k + 1) % loop.size()] - a;
      const double len2 = glm::dot(d, d);
      const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, glm::distance(a + t * d, p));
    }
  return best;
}

BandedTrim::BandedTrim(const TrimPolygons& trim) : trim_(&trim) {
  for (const auto& poly : trim.loops) {
    Loop l;
    double lo = 1e300, hi = -1e300;
    for (const glm::dvec2& q : poly) lo = std::min(lo, q.y), hi = std::max(hi, q.y);
    for (const glm::dvec2& q : poly) l.u0 = std::min(l.u0, q.x), l.u1 = std::max(l.u1, q.x);
    const int bands = std::clamp(int(poly.size() / 4), 1, kMaxBands);
    l.v0 = lo;
    l.height = hi > lo ? (hi - lo) / bands : 1.0;
    l.bands.resize(size_t(bands));
    for (size_t e = 0; e < poly.size(); ++e) {
      const double a = poly[e].y, b = poly[(e + 1) % poly.size()].y;
      for (size_t k = band(l, std::min(a, b)); k <= band(l, std::max(a, b)); ++k) l.bands[k].push_back(int(e));
    }
    loops_.push_back(std::move(l));
  }
}

size_t BandedTrim::band(const Loop& l, double v) {
  // Monotone in v (clamped below and above): an edge is listed in every band from that of its
  // lowest to that of its highest v, so every band of a v within its range lists it.
  return !(v > l.v0) ? 0 : std::min(size_t((v - l.v0) / l.height), l.bands.size() - 1);
}

int BandedTrim::winding(size_t k, glm::dvec2 p) const {
  const Loop& l = loops_[k];
  // Outside the loop's box the winding number is 0 (a loop collapsed onto a line of (u, v), as a
  // failed projection leaves it, holds 100,000 edges in one band and encloses nothing).
  if (p.y < l.v0 || l.bands.empty() || !(p.x >= l.u0 && p.x <= l.u1)) return 0;
  const size_t b = band(l, p.y);
  const auto& poly = trim_->loops[k];
  int wn = 0;
  // The arithmetic of nurbs::winding_number, on the edges whose v range may hold p.y.
  for (int e : l.bands[b]) {
    const glm::dvec2 a = poly[size_t(e)], c = poly[(size_t(e) + 1) % poly.size()];
    const double side = (c.x - a.x) * (p.y - a.y) - (p.x - a.x) * (c.y - a.y);
    if (a.y <= p.y) {
      if (c.y > p.y && side > 0) ++wn;
    } else if (c.y <= p.y && side < 0) {
      --wn;
    }
  }
  return wn;
}

bool BandedTrim::is_material(glm::dvec2 uv) const {
  // The rules of is_material.
  const TrimPolygons& t = *trim_;
  if (uv.x < t.domain_u.min || uv.x > t.domain_u.max || uv.y < t.domain_v.min || uv.y > t.domain_v.max) return false;
  bool any_outer = false, in_outer = false;
  for (size_t k = 0; k < t.loops.size(); ++k) {
    const bool inside = winding(k, uv) != 0;
    if (t.outer[k]) {
      any_outer = true;
      in_outer = in_outer || inside;
    } else if (inside) {
      return false;
    }
  }
  return any_outer ? in_outer : true;
}

std::vector<std::pair<glm::dvec2, glm::dvec2>> BandedTrim::edges_in_box(glm::dvec2 lo, glm::dvec2 hi,
                                                                        size_t limit) const {
  std::vector<std::pair<glm::dvec2, glm::dvec2>> out;
  std::vector<std::pair<size_t, int>> seen;  // (loop, edge): an edge is listed in several bands
  for (size_t k = 0; k < loops_.size() && out.size() < limit; ++k) {
    const Loop& l = loops_[k];
    const auto& poly = trim_->loops[k];
    if (l.bands.empty()) continue;
    for (size_t b = band(l, lo.y), last = band(l, hi.y); b <= last && out.size() < limit; ++b)
      for (int e : l.bands[b]) {
        const glm::dvec2 p = poly[size_t(e)], q = poly[(size_t(e) + 1) % poly.size()];
        if (!segment_meets_box(p, q, lo, hi) || std::find(seen.begin(), seen.end(), std::pair{k, e}) != seen.end())
          continue;
        seen.emplace_back(k, e);
        out.emplace_back(p, q);
        if (out.size() >= limit) break;
      }
  }
  return out;
}

bool BandedTrim::meets_box(glm::dvec2 lo, glm::dvec2 hi) const {
  for (size_t k = 0; k < loops_.size(); ++k) {
    const Loop& l = loops_[k];
    const auto& poly = trim_->loops[k];
    if (l.bands.empty()) continue;
    // An edge meeting the box has a point with v in [lo.y, hi.y]: listed in that point's band.
    for (size_t b = band(l, lo.y), last = band(l, hi.y); b <= last; ++b)
      for (int e : l.bands[b])
        if (segment_meets_box(poly[size_t(e)], poly[(size_t(e) + 1) % poly.size()], lo, hi)) return true;
  }
  return false;
}

}  // namespace nurbs
