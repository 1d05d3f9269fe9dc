#include "nurbs/trim_surface_gaps.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/knot_insertion.h"
#include "nurbs/knot_vector.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"

namespace nurbs {
namespace {

// Largest model-space distance from S(a) to the image of the (u, v) segment a-b, at 16 samples.
double image_extent(const Surface& s, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec3 pa = surface_point(s, a.x, a.y);
  double extent = 0.0;
  for (int i = 1; i <= 16; ++i) {
    const glm::dvec2 m = a + (b - a) * (i / 16.0);
    extent = std::max(extent, glm::length(surface_point(s, m.x, m.y) - pa));
  }
  return extent;
}

// Parameter of `c` nearest to `q` in (u, v): the best of 64 samples, refined by golden-section
// search between its neighbours (the distance is unimodal there for any curve a trim tolerance apart).
double nearest_parameter(const Curve2& c, glm::dvec2 q) {
  const Interval d = curve_domain(c);
  constexpr int kSamples = 64;
  auto dist = [&](double t) { return glm::length(curve_point(c, t) - q); };
  int best = 0;
  for (int i = 1; i <= kSamples; ++i)
    if (dist(d.min + (d.max - d.min) * i / kSamples) < dist(d.min + (d.max - d.min) * best / kSamples)) best = i;
  double lo = d.min + (d.max - d.min) * std::max(0, best - 1) / kSamples;
  double hi = d.min + (d.max - d.min) * std::min(kSamples, best + 1) / kSamples;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 100 && hi - lo > 1e-15 * (d.max - d.min); ++it) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    (dist(x1) < dist(x2) ? hi : lo) = dist(x1) < dist(x2) ? x2 : x1;
  }
  return (lo + hi) / 2.0;
}

// Largest model-space distance from `p` to the image of curve `c` on [t0, t1], at 17 samples.
double piece_extent(const Surface& s, const Curve2& c, double t0, double t1, glm::dvec3 p) {
  double extent = 0.0;
  for (int i = 0; i <= 16; ++i) {
    const glm::dvec2 q = curve_point(c, t0 + (t1 - t0) * (i / 16.0));
    extent = std::max(extent, glm::length(surface_point(s, q.x, q.y) - p));
  }
  return extent;
}

// The curve cut to [t0, t1] (restrict.h, clamped) with its first (`at_start`) or last control point
// moved onto `q`, the point it must join.
Curve2 cut(const Curve2& c, double t0, double t1, bool at_start, glm::dvec2 q) {
  Curve2 out = restrict_curve(c, t0, t1);
  if (!is_clamped(out.knots, out.degree)) out = from_homogeneous<2>(clamp_curve(to_homogeneous(out)), out.rational());
  out.edge = c.edge;
  (at_start ? out.points.front() : out.points.back()) = q;
  return out;
}

// Overshoot: `curve` passes through `q`, the end of its neighbour in the loop, and runs on a little
// beyond it (the Ventilator's sides drawn 0.024 mm past the corner). When that part lies within
// `tolerance_3d` of S(q) on the surface, it is cut off. `at_start`: the part before q (curve is the
// one after the gap), else the part after q (curve is the one before the gap).
bool trim_overshoot(const Surface& s, Curve2& curve, glm::dvec2 q, bool at_start, double tolerance_3d, double min_gap,
                    double* cut_extent = nullptr) {
  const Interval d = curve_domain(curve);
  const double t = nearest_parameter(curve, q);
  if (!(t > d.min && t < d.max)) return false;  // nearest at an end: nothing overshoots
  // The curve must pass through q in (u, v) (within the 2D repair gap): moving its new end onto q
  // then changes it by no more than that. A curve that only meets q's image (a pole) is not cut.
  if (!(glm::length(curve_point(curve, t) - q) <= min_gap)) return false;
  const glm::dvec3 p = surface_point(s, q.x, q.y);
  const double extent = at_start ? piece_extent(s, curve, d.min, t, p) : piece_extent(s, curve, t, d.max, p);
  if (!(extent <= tolerance_3d)) return false;  // NaN: left alone
  curve = at_start ? cut(curve, t, d.max, true, q) : cut(curve, d.min, t, false, q);
  if (cut_extent) *cut_extent = extent;
  return true;
}

/// The gap from the end a of `prev` to the start b of `next` runs along one side of the surface's
/// parameter domain (both ends on it within 1e-6 of its width), and neither curve runs back along
/// that side over the gap (a curve moved off its joint, whose gap the side would retrace).
bool along_one_side(const Surface& s, const Curve2& prev, const Curve2& next) {
  const glm::dvec2 a = end_point(prev), b = start_point(next);
  const Interval dp = curve_domain(prev), dn = curve_domain(next);
  const glm::dvec2 before = curve_point(prev, dp.max - 1e-3 * dp.width()),
                   after = curve_point(next, dn.min + 1e-3 * dn.width());
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  for (int axis = 0; axis < 2; ++axis) {
    const Interval d = axis == 0 ? du : dv;
    const double tol = 1e-6 * d.width();
    for (const double side : {d.min, d.max}) {
      if (!(std::abs(a[axis] - side) <= tol && std::abs(b[axis] - side) <= tol)) continue;
      const auto over_gap = [&](glm::dvec2 p, glm::dvec2 from, glm::dvec2 to) {
        return std::abs(p[axis] - side) <= tol && glm::dot(p - from, to - from) > 0.0;
      };
      return !over_gap(after, b, a) && !over_gap(before, a, b);
    }
  }
  return false;
}

}  // namespace

int close_gaps_on_surface(TrimmedSurface& face, double tolerance_3d, double min_gap) {
  int added = 0;
  for (TrimLoop& loop : face.loops) {
    const size_t n = loop.curves.size();
    std::vector<char> segment_after(n, 0);
    for (size_t c = 0; c < n; ++c) {
      Curve2 &prev = loop.curves[c], &next = loop.curves[(c + 1) % n];
      const glm::dvec2 a = end_point(prev), b = start_point(next);
      if (!(glm::length(a - b) > min_gap)) continue;
      // Overshoots first: cutting them leaves no spike; then a joining segment (a pole, a short gap).
      if (n > 1 && (trim_overshoot(face.surface, next, a, true, tolerance_3d, min_gap) ||
                    trim_overshoot(face.surface, prev, b, false, tolerance_3d, min_gap))) {
        ++added;
      } else if (image_extent(face.surface, a, b) <= tolerance_3d) {  // NaN: left alone
        segment_after[c] = 1;
        ++added;
      }
    }
    std::vector<Curve2> closed;
    for (size_t c = 0; c < n; ++c) {
      closed.push_back(loop.curves[c]);
      if (segment_after[c])
        closed.push_back(segment_curve(end_point(loop.curves[c]), start_point(loop.curves[(c + 1) % n])));
    }
    loop.curves = std::move(closed);
  }
  return added;
}

double bridge_open_joints(TrimmedSurface& face, double cap_3d, double min_gap, int& added) {
  double largest = 0.0;
  for (TrimLoop& loop : face.loops) {
    const size_t n = loop.curves.size();
    // Overshoots first, as close_gaps_on_surface does: a curve running on past its neighbour's end
    // is cut there (the cut piece's extent is the gap).
    for (size_t c = 0; c < n && n > 1; ++c) {
      Curve2 &prev = loop.curves[c], &next = loop.curves[(c + 1) % n];
      const glm::dvec2 a = end_point(prev), b = start_point(next);
      double extent = 0.0;
      if (glm::length(a - b) > min_gap && (trim_overshoot(face.surface, next, a, true, cap_3d, min_gap, &extent) ||
                                           trim_overshoot(face.surface, prev, b, false, cap_3d, min_gap, &extent)))
        largest = std::max(largest, extent), ++added;
    }
    std::vector<Curve2> closed;
    for (size_t c = 0; c < n; ++c) {
      closed.push_back(loop.curves[c]);
      const glm::dvec2 a = end_point(loop.curves[c]), b = start_point(loop.curves[(c + 1) % n]);
      if (!(glm::length(a - b) > min_gap)) continue;
      // The image at 33 samples: its length, and its reach from either end.
      const glm::dvec3 pa = surface_point(face.surface, a.x, a.y), pb = surface_point(face.surface, b.x, b.y);
      double length = 0.0, reach = 0.0;
      glm::dvec3 last = pa;
      for (int i = 1; i <= 32; ++i) {
        const glm::dvec2 m = a + (b - a) * (i / 32.0);
        const glm::dvec3 q = surface_point(face.surface, m.x, m.y);
        length += glm::length(q - last), last = q;
        reach = std::max({reach, std::min(glm::length(q - pa), glm::length(q - pb))});
      }
      const double chord = glm::length(pb - pa);
      // Both ends on one side of the domain: the missing edge is that side (a loop round three sides
      // of a pipe's half, its fourth missing: PyGeM's deformed pipes), whatever its length; the face
      // is bounded there by its surface's own side, which the straight (u, v) segment is exactly.
      const bool along_side = along_one_side(face.surface, loop.curves[c], loop.curves[(c + 1) % n]);
      if (!along_side && !(length <= 2.0 * chord && chord <= cap_3d && reach <= cap_3d)) continue;  // NaN: open
      closed.push_back(segment_curve(a, b));
      if (!along_side) largest = std::max(largest, length);
      ++added;
    }
    loop.curves = std::move(closed);
  }
  return largest;
}

namespace {

/// pair_added_edges within one body's faces, numbering from `next_edge`.
int pair_in_body(std::vector<TrimmedSurface>& faces, double tolerance, int& next_edge) {
  struct Added {
    size_t face;
    Curve2* curve;
    glm::dvec3 a, b;
  };
  std::vector<Added> added;
  for (size_t f = 0; f < faces.size(); ++f)
    for (TrimLoop& l : faces[f].loops)
      for (Curve2& c : l.curves) {
        if (c.edge != -1) continue;
        const glm::dvec2 p = start_point(c), q = end_point(c);
        const Surface& s = faces[f].surface;
        added.push_back({f, &c, surface_point(s, p.x, p.y), surface_point(s, q.x, q.y)});
      }
  const auto same = [&](const Added& x, const Added& y) {
    const auto near = [&](glm::dvec3 p, glm::dvec3 q) { return glm::length(p - q) <= tolerance; };
    return x.face != y.face && ((near(x.a, y.b) && near(x.b, y.a)) || (near(x.a, y.a) && near(x.b, y.b)));
  };
  int pairs = 0;
  for (size_t i = 0; i < added.size(); ++i) {
    if (added[i].curve->edge != -1) continue;
    std::vector<size_t> match;
    for (size_t j = 0; j < added.size(); ++j)
      if (j != i && same(added[i], added[j])) match.push_back(j);
    if (match.size() != 1 || added[match[0]].curve->edge != -1) continue;
    size_t others = 0;  // the partner's own matches: the pair must be alone
    for (size_t j = 0; j < added.size(); ++j) others += j != match[0] && same(added[match[0]], added[j]);
    if (others != 1) continue;
    added[i].curve->edge = added[match[0]].curve->edge = next_edge++;
    ++pairs;
  }
  return pairs;
}

}  // namespace

int pair_added_edges(std::vector<Body>& bodies, double tolerance) {
  int next_edge = 0;
  for (const Body& b : bodies)
    for (const TrimmedSurface& f : b.faces)
      for (const TrimLoop& l : f.loops)
        for (const Curve2& c : l.curves) next_edge = std::max(next_edge, c.edge + 1);
  int pairs = 0;
  for (Body& b : bodies) pairs += pair_in_body(b.faces, tolerance, next_edge);
  return pairs;
}

}  // namespace nurbs
