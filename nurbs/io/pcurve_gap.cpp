#include "nurbs/io/pcurve_gap.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <vector>

#include "nurbs/curve_eval.h"
#include "nurbs/surface_eval.h"

namespace nurbs::io {
namespace {

// A point and its derivative along one side's curve `i` at parameter t.
struct PointTangent {
  glm::dvec3 x, dx;
};

// The model-space side: the edge's curves themselves.
struct ModelSide {
  std::span<const Curve3> curves;
  [[nodiscard]] size_t size() const { return curves.size(); }
  [[nodiscard]] Interval domain(size_t i) const { return curve_domain(curves[i]); }
  [[nodiscard]] glm::dvec3 point(size_t i, double t) const { return curve_point(curves[i], t); }
  [[nodiscard]] PointTangent tangent(size_t i, double t) const {
    const auto d = curve_derivatives(curves[i], t, 1);
    return {d[0], d[1]};
  }
};

// The period of `s` along `axis` (0: u, 1: v) when some parameter curve reaches beyond its domain
// there and the surface closes on itself along it within `tolerance` (S(u0, v) = S(u1, v) at 9
// values of v), else 0. Files may put a closed surface's seam elsewhere than the surface's own
// (pcurves over [2 pi, 4 pi] on a domain [4 pi / 3, 10 pi / 3]); the reader moves such loops into
// the domain later (wrap_loops_into_domain), the points in space are the same.
double period_beyond_domain(const Surface& s, std::span<const Curve2> curves, int axis, double tolerance) {
  const Interval d = axis == 0 ? surface_domain_u(s) : surface_domain_v(s),
                 e = axis == 0 ? surface_domain_v(s) : surface_domain_u(s);
  const double slack = 1e-9 * d.width();
  bool beyond = false;
  for (const Curve2& c : curves)
    for (const glm::dvec2& q : c.points) beyond = beyond || q[axis] < d.min - slack || q[axis] > d.max + slack;
  if (!beyond) return 0.0;
  for (int i = 0; i <= 8; ++i) {
    const double w = e.min + e.width() * i / 8.0;
    const glm::dvec3 a = axis == 0 ? surface_point(s, d.min, w) : surface_point(s, w, d.min);
    const glm::dvec3 b = axis == 0 ? surface_point(s, d.max, w) : surface_point(s, w, d.max);
    if (!(glm::length(a - b) <= tolerance)) return 0.0;
  }
  return d.width();
}

// The face's side: the surface along the parameter curves, X(t) = S(pc(t)), X' = Su u' + Sv v';
// points beyond the domain of a closed direction taken whole periods back into it.
struct SurfaceSide {
  const Surface& s;
  std::span<const Curve2> curves;
  glm::dvec2 period{0.0};  // per direction, 0 where not wrapped
  Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  [[nodiscard]] size_t size() const { return curves.size(); }
  [[nodiscard]] Interval domain(size_t i) const { return curve_domain(curves[i]); }
  [[nodiscard]] static double wrap(double x, Interval d, double period) {
    if (period <= 0.0 || (x >= d.min && x <= d.max)) return x;
    return x - period * std::floor((x - d.min) / period);
  }
  [[nodiscard]] glm::dvec2 in_domain(glm::dvec2 q) const { return {wrap(q.x, du, period.x), wrap(q.y, dv, period.y)}; }
  [[nodiscard]] glm::dvec3 point(size_t i, double t) const {
    const glm::dvec2 q = in_domain(curve_point(curves[i], t));
    return surface_point(s, q.x, q.y);
  }
  [[nodiscard]] PointTangent tangent(size_t i, double t) const {
    const auto d = curve_derivatives(curves[i], t, 1);
    const glm::dvec2 q = in_domain(d[0]);
    const SurfaceDerivatives sd = surface_derivatives(s, q.x, q.y);
    return {sd.s, sd.su * d[1].x + sd.sv * d[1].y};
  }
};

struct Sample {
  glm::dvec3 x;
  double t = 0.0;
};

// kPcurveGapSamples + 1 samples of every curve of a side, curve after curve.
template <class Side>
std::vector<Sample> samples(const Side& side) {
  std::vector<Sample> out;
  out.reserve(side.size() * (kPcurveGapSamples + 1));
  for (size_t i = 0; i < side.size(); ++i) {
    const Interval d = side.domain(i);
    for (int k = 0; k <= kPcurveGapSamples; ++k) {
      const double t = d.min + d.width() * k / kPcurveGapSamples;
      out.push_back({side.point(i, t), t});
    }
  }
  return out;
}

// Largest distance from the samples `from` to the side `to` (sampled as `to_samples`), each
// sample's distance refined only beyond `floor` (pcurve_gap).
template <class Side>
double one_sided(const std::vector<Sample>& from, const Side& to, const std::vector<Sample>& to_samples, double floor) {
  constexpr int kPerCurve = kPcurveGapSamples + 1;
  constexpr int kNewtonSteps = 8;
  struct Nearest {
    double vertex = std::numeric_limits<double>::infinity();  // to the nearest sample: a point of `to`
    double chord = std::numeric_limits<double>::infinity();   // to the nearest chord point
    size_t curve = 0;
    double t = 0.0;  // the chord point's parameter, interpolated
  };
  std::vector<Nearest> near(from.size());
  for (size_t s = 0; s < from.size(); ++s) {
    Nearest& n = near[s];
    for (size_t i = 0; i < to.size(); ++i)
      for (int k = 0; k < kPerCurve; ++k) {
        const Sample& b = to_samples[i * kPerCurve + k];
        n.vertex = std::min(n.vertex, glm::length(b.x - from[s].x));
        if (k + 1 == kPerCurve) continue;
        const Sample& c = to_samples[i * kPerCurve + k + 1];
        const glm::dvec3 chord = c.x - b.x;
        const double len2 = glm::dot(chord, chord);
        const double f = len2 > 0.0 ? std::clamp(glm::dot(from[s].x - b.x, chord) / len2, 0.0, 1.0) : 0.0;
        const double dist = glm::length(b.x + f * chord - from[s].x);
        if (dist < n.chord) n.chord = dist, n.curve = i, n.t = b.t + f * (c.t - b.t);
      }
    if (!std::isfinite(n.vertex)) return std::numeric_limits<double>::infinity();
  }
  // Farthest chords first: a refined distance never exceeds the sample's vertex distance, so once
  // the worst found reaches it the sample cannot raise the result.
  std::vector<size_t> order(from.size());
  for (size_t s = 0; s < order.size(); ++s) order[s] = s;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return near[a].chord > near[b].chord; });
  double worst = 0.0;
  for (const size_t s : order) {
    const Nearest& n = near[s];
    double d = n.vertex;
    if (d > std::max(worst, floor)) {
      // Gauss-Newton on |X(t) - a|^2 from the nearest chord point's parameter; every point it
      // visits is on the curve, so the smallest distance seen bounds the true one from above.
      const Interval dom = to.domain(n.curve);
      double t = n.t;
      for (int it = 0; it < kNewtonSteps; ++it) {
        const PointTangent pt = to.tangent(n.curve, t);
        const glm::dvec3 r = pt.x - from[s].x;
        if (std::isfinite(r.x + r.y + r.z)) d = std::min(d, glm::length(r));
        const double g2 = glm::dot(pt.dx, pt.dx);
        if (!(g2 > 0.0)) break;
        const double next = std::clamp(t - glm::dot(pt.dx, r) / g2, dom.min, dom.max);
        if (std::abs(next - t) <= 1e-12 * dom.width()) break;
        t = next;
      }
      d = std::min(d, glm::length(to.point(n.curve, t) - from[s].x));
    }
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace

double pcurve_gap(const Surface& s, std::span<const Curve2> pcurves, std::span<const Curve3> edge, double floor) {
  if (pcurves.empty() || edge.empty()) return 0.0;
  const ModelSide model{edge};
  SurfaceSide face{s, pcurves};
  face.period = {period_beyond_domain(s, pcurves, 0, floor), period_beyond_domain(s, pcurves, 1, floor)};
  const std::vector<Sample> on_model = samples(model), on_face = samples(face);
  return std::max(one_sided(on_face, model, on_model, floor), one_sided(on_model, face, on_face, floor));
}

}  // namespace nurbs::io
