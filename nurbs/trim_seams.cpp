#include "nurbs/trim_seams.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <glm/geometric.hpp>
#include <vector>

#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace nurbs {
namespace {

// Domain of the surface along axis 0 (u) or 1 (v).
Interval domain(const Surface& s, int axis) { return axis == 0 ? surface_domain_u(s) : surface_domain_v(s); }

glm::dvec2 at(int axis, double along, double across) {
  return axis == 0 ? glm::dvec2(along, across) : glm::dvec2(across, along);
}

// S(u0, v) = S(u1, v) (axis 0; v swapped for axis 1) at 9 parameters across, within the tolerance.
bool closed_along(const Surface& s, int axis, double tolerance_3d) {
  const Interval d = domain(s, axis), e = domain(s, 1 - axis);
  for (int i = 0; i <= 8; ++i) {
    const double w = e.min + e.width() * i / 8.0;
    const glm::dvec2 a = at(axis, d.min, w), b = at(axis, d.max, w);
    if (!(glm::length(surface_point(s, a.x, a.y) - surface_point(s, b.x, b.y)) <= tolerance_3d)) return false;
  }
  return true;
}

// Indices of the curves right after the loop's seam jumps along `axis`.
std::vector<size_t> jumps(const TrimLoop& loop, const Interval& d, int axis, double min_gap) {
  std::vector<size_t> found;
  const size_t n = loop.curves.size();
  for (size_t c = 0; c < n; ++c) {
    const glm::dvec2 a = end_point(loop.curves[c]), b = start_point(loop.curves[(c + 1) % n]);
    const bool on_sides = (std::abs(a[axis] - d.min) <= min_gap && std::abs(b[axis] - d.max) <= min_gap) ||
                          (std::abs(a[axis] - d.max) <= min_gap && std::abs(b[axis] - d.min) <= min_gap);
    if (on_sides && std::abs(a[1 - axis] - b[1 - axis]) <= min_gap) found.push_back((c + 1) % n);
  }
  return found;
}

// The curves [first, last) of `loop` closed by a segment from their end back to their start.
TrimLoop closed_piece(const TrimLoop& loop, size_t first, size_t last) {
  TrimLoop piece;
  piece.outer = loop.outer;
  piece.curves.assign(loop.curves.begin() + static_cast<std::ptrdiff_t>(first),
                      loop.curves.begin() + static_cast<std::ptrdiff_t>(last));
  piece.curves.push_back(segment_curve(end_point(piece.curves.back()), start_point(piece.curves.front())));
  return piece;
}

void turn_round(TrimLoop& loop) {
  std::reverse(loop.curves.begin(), loop.curves.end());
  for (Curve2& c : loop.curves) c = reversed(c);
}

// The signed area the loop's curves enclose (signed_area of 16 samples a curve; counter-clockwise > 0).
double loop_area(const TrimLoop& loop) {
  std::vector<glm::dvec2> polygon;
  for (const Curve2& c : loop.curves) {
    const Interval cd = curve_domain(c);
    for (int k = 0; k < 16; ++k) polygon.push_back(curve_point(c, cd.min + cd.width() * k / 16.0));
  }
  return signed_area(polygon);
}

// A loop that goes once round the seam but crosses it 3, 5, ... times (a thread's run-out dipping
// back across the seam): its pieces between jumps that start and end on the same side of the
// domain, each a region (or a hole) against that side. Returns them (the curves [first, last) of
// the loop as it is, rotated to start right after a jump), and leaves in `loop` the one piece that
// runs from one side to the other, started right after its jump; nothing when more than one piece
// crosses (the loop then stays as it is).
std::vector<TrimLoop> split_dips(TrimLoop& loop, const std::vector<size_t>& at_jump, const Interval& d, int axis,
                                 double min_gap) {
  const size_t n = loop.curves.size(), m = at_jump.size();
  const auto side = [&](glm::dvec2 q) { return std::abs(q[axis] - d.min) <= min_gap ? 0 : 1; };
  std::vector<TrimLoop> dips;
  std::optional<TrimLoop> crossing;
  for (size_t i = 0; i < m; ++i) {
    const size_t first = at_jump[i], last = at_jump[(i + 1) % m];  // last: first curve after the piece
    const size_t count = (last + n - first) % n == 0 ? n : (last + n - first) % n;
    TrimLoop piece;
    piece.outer = loop.outer;
    for (size_t k = 0; k < count; ++k) piece.curves.push_back(loop.curves[(first + k) % n]);
    if (side(start_point(piece.curves.front())) == side(end_point(piece.curves.back()))) {
      dips.push_back(std::move(piece));
    } else {
      if (crossing) return {};
      crossing = std::move(piece);
    }
  }
  if (!crossing) return {};
  loop.curves = std::move(crossing->curves);
  return dips;
}

// Makes the open piece `dip` (from one point of a side of the domain to another on the same side)
// part of the straight segment of `loop` along that side whose span holds both its ends: the
// segment is replaced by the segment to the dip's nearer end, the dip (turned round when it runs
// against the segment), and the segment from its other end on. False when no such segment.
bool splice_dip(TrimLoop& loop, TrimLoop dip, int axis, double min_gap) {
  const glm::dvec2 d0 = start_point(dip.curves.front()), d1 = end_point(dip.curves.back());
  for (size_t k = 0; k < loop.curves.size(); ++k) {
    const Curve2& c = loop.curves[k];
    if (c.degree != 1 || c.points.size() != 2) continue;
    const glm::dvec2 s0 = c.points.front(), s1 = c.points.back();
    if (std::abs(s0[axis] - d0[axis]) > min_gap || std::abs(s1[axis] - d0[axis]) > min_gap ||
        std::abs(d1[axis] - d0[axis]) > min_gap)
      continue;  // not along the dip's side
    const double lo = std::min(s0[1 - axis], s1[1 - axis]), hi = std::max(s0[1 - axis], s1[1 - axis]);
    const auto within = [&](glm::dvec2 q) { return q[1 - axis] >= lo - min_gap && q[1 - axis] <= hi + min_gap; };
    if (!within(d0) || !within(d1)) continue;
    const auto along = [&](glm::dvec2 q) { return std::abs(q[1 - axis] - s0[1 - axis]); };
    if (along(d0) > along(d1)) turn_round(dip);
    const glm::dvec2 e0 = start_point(dip.curves.front()), e1 = end_point(dip.curves.back());
    std::vector<Curve2> replaced;
    if (s0 != e0) replaced.push_back(segment_curve(s0, e0));
    for (Curve2& piece : dip.curves) replaced.push_back(std::move(piece));
    if (e1 != s1) replaced.push_back(segment_curve(e1, s1));
    loop.curves.erase(loop.curves.begin() + static_cast<std::ptrdiff_t>(k));
    loop.curves.insert(loop.curves.begin() + static_cast<std::ptrdiff_t>(k), replaced.begin(), replaced.end());
    return true;
  }
  return false;
}

int close_along(TrimmedSurface& face, int axis, double tolerance_3d, double min_gap) {
  if (!closed_along(face.surface, axis, tolerance_3d)) return 0;
  const Interval d = domain(face.surface, axis), across = domain(face.surface, 1 - axis);
  std::vector<size_t> open;      // loops with one seam jump, rotated to start right after it
  std::vector<TrimLoop> halves;  // second halves of loops that cross the seam twice
  std::vector<std::vector<TrimLoop>> dips(face.loops.size());  // per loop: split_dips
  int closed = 0;
  for (size_t k = 0; k < face.loops.size(); ++k) {
    TrimLoop& loop = face.loops[k];
    const std::vector<size_t> at_jump = jumps(loop, d, axis, min_gap);
    if (at_jump.size() >= 3 && at_jump.size() % 2 == 1) {
      dips[k] = split_dips(loop, at_jump, d, axis, min_gap);
      if (!dips[k].empty()) open.push_back(k);
      continue;
    }
    if (at_jump.size() != 1 && at_jump.size() != 2) continue;
    std::rotate(loop.curves.begin(), loop.curves.begin() + static_cast<std::ptrdiff_t>(at_jump[0]), loop.curves.end());
    if (at_jump.size() == 1) {
      open.push_back(k);
      continue;
    }
    // Across the seam and back (a patch or hole straddling it): the two pieces, one on each side
    // of the domain, each closed along its seam side.
    const size_t split = (at_jump[1] + loop.curves.size() - at_jump[0]) % loop.curves.size();
    halves.push_back(closed_piece(loop, split, loop.curves.size()));
    loop = closed_piece(loop, 0, split);
    ++closed;
  }
  // The dips of loop k, each closed along its side of the domain from its end back to its start: a
  // region of the face where, running that way, the material lies on its left, else a hole. The
  // loop the dips came from is closed (into a band or a cap, `into`) into a loop whose inside is
  // the material: running counter-clockwise there, its dips run with the material on their left
  // too; `turned` when the loop's curves were turned round for it, `clockwise` when the closed loop
  // runs clockwise (the material then on the right of every piece of it). A hole lies against the
  // closed loop's segment along the same side: it is made part of that segment (the boundary runs
  // in round the hole and out again), not a loop of its own that would share the segment.
  const auto close_dips = [&](size_t k, TrimLoop& into, bool turned, bool clockwise) {
    for (TrimLoop& dip : dips[k]) {
      if (turned) turn_round(dip);
      TrimLoop closed_dip = dip;
      closed_dip.curves.push_back(segment_curve(end_point(dip.curves.back()), start_point(dip.curves.front())));
      const bool region = (loop_area(closed_dip) > 0.0) != clockwise;
      ++closed;
      if (!region && splice_dip(into, dip, axis, min_gap)) continue;
      closed_dip.outer = region;
      halves.push_back(std::move(closed_dip));
    }
  };
  std::vector<size_t> merged_away;
  for (size_t i = 0; i + 1 < open.size(); i += 2) {  // pairs: the two boundaries of a band
    TrimLoop &a = face.loops[open[i]], &b = face.loops[open[i + 1]];
    const double a_end = end_point(a.curves.back())[axis];
    const bool turned = std::abs(start_point(b.curves.front())[axis] - a_end) > min_gap;  // both run the same way
    if (turned) turn_round(b);
    const glm::dvec2 a0 = start_point(a.curves.front()), a1 = end_point(a.curves.back());
    const glm::dvec2 b0 = start_point(b.curves.front()), b1 = end_point(b.curves.back());
    a.curves.push_back(segment_curve(a1, b0));  // along the seam side where a ends
    for (Curve2& c : b.curves) a.curves.push_back(std::move(c));
    a.curves.push_back(segment_curve(b1, a0));
    a.outer = a.outer || b.outer;
    const bool clockwise = loop_area(a) < 0.0;  // the band: its inside is the material
    close_dips(open[i], a, false, clockwise);
    close_dips(open[i + 1], a, turned, clockwise);
    merged_away.push_back(open[i + 1]);
    ++closed;
  }
  if (open.size() % 2 == 1) {  // a cap: closed along the domain side on its material (left) side
    TrimLoop& a = face.loops[open.back()];
    const glm::dvec2 a0 = start_point(a.curves.front()), a1 = end_point(a.curves.back());
    // Running towards u1 (axis 0) the left is towards v1; along v (axis 1) towards v1 the left is u0.
    const bool increasing = a1[axis] > a0[axis];
    const double side = (axis == 0) == increasing ? across.max : across.min;
    const glm::dvec2 c1 = at(axis, a1[axis], side), c0 = at(axis, a0[axis], side);
    for (const Curve2& c : {segment_curve(a1, c1), segment_curve(c1, c0), segment_curve(c0, a0)}) a.curves.push_back(c);
    close_dips(open.back(), a, false, loop_area(a) < 0.0);
    ++closed;
  }
  std::sort(merged_away.rbegin(), merged_away.rend());
  for (size_t k : merged_away) face.loops.erase(face.loops.begin() + static_cast<std::ptrdiff_t>(k));
  for (TrimLoop& h : halves) face.loops.push_back(std::move(h));
  return closed;
}

// The surface with u and v swapped (the same points, knots and weights read the other way).
Surface transposed(const Surface& s) {
  Surface t;
  t.degree_u = s.degree_v, t.degree_v = s.degree_u;
  t.count_u = s.count_v, t.count_v = s.count_u;
  t.knots_u = s.knots_v, t.knots_v = s.knots_u;
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      t.points.push_back(s.point(i, j));
      if (s.rational()) t.weights.push_back(s.weight(i, j));
    }
  return t;
}

// The clamped surface s (domain [u0, u1] in u, closed there) followed by a copy of itself moved by
// the period T = u1 - u0 in u: domain [u0, u1 + T], joined with continuity C0 at u1. Empty when the
// copy's first column is not the last one's (positions within `tolerance_3d`, weights in one ratio).
std::optional<Surface> doubled_along_u(const Surface& clamped, double tolerance_3d) {
  const Surface& s = clamped;
  const int p = s.degree_u, n = s.count_u;
  const double u0 = s.knots_u.front(), u1 = s.knots_u.back(), period = u1 - u0;
  double ratio = 0.0;  // weight of the last column over the first's, one value for every row
  for (int j = 0; j < s.count_v; ++j) {
    if (!(glm::length(s.point(n - 1, j) - s.point(0, j)) <= tolerance_3d)) return std::nullopt;
    const double r = s.weight(n - 1, j) / s.weight(0, j);
    if (j == 0) ratio = r;
    if (!(std::abs(r - ratio) <= 1e-9 * ratio)) return std::nullopt;
  }
  Surface d = s;
  d.count_u = 2 * n - 1;
  d.knots_u.assign(s.knots_u.begin(), s.knots_u.end() - 1);  // [u0]^(p+1) .. [u1]^p
  for (size_t k = size_t(p) + 1; k < s.knots_u.size(); ++k) d.knots_u.push_back(s.knots_u[k] + period);
  d.points.clear(), d.weights.clear();
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < d.count_u; ++i) {
      const bool copy = i >= n;
      const int c = copy ? i - n + 1 : i;
      d.points.push_back(s.point(c, j));
      if (s.rational()) d.weights.push_back(copy ? s.weight(c, j) * ratio : s.weight(c, j));
    }
  return d;
}

// The loop's extent in u, from 64 samples a curve.
Interval u_extent(const TrimLoop& loop) {
  Interval e{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Curve2& c : loop.curves) {
    const Interval cd = curve_domain(c);
    for (int k = 0; k <= 64; ++k) {
      const double u = curve_point(c, cd.min + cd.width() * k / 64.0).x;
      e.min = std::min(e.min, u), e.max = std::max(e.max, u);
    }
  }
  return e;
}

void shift_u(TrimLoop& loop, double shift) {
  if (shift == 0.0) return;
  for (Curve2& c : loop.curves)
    for (glm::dvec2& q : c.points) q.x += shift;
}

// Whether the loop goes once round a surface closed in u: its end one period along from its start.
bool goes_round(const TrimLoop& loop, double period, double min_gap) {
  const glm::dvec2 a = start_point(loop.curves.front()), b = end_point(loop.curves.back());
  return std::abs(std::abs(b.x - a.x) - period) <= min_gap && std::abs(b.y - a.y) <= min_gap;
}

// A loop going once round that runs past the domain's far side d.max: its curves cut where they
// cross u = d.max and the pieces beyond moved back by the period, so it runs from one side of the
// domain to the other with one seam jump, which close_loops_round_seam closes.
void cut_round_loop(TrimLoop& loop, const Interval& d) {
  const double period = d.width();
  std::vector<Curve2> pieces;
  for (const Curve2& c : loop.curves) {
    const Interval cd = curve_domain(c);
    const auto beyond = [&](double t) { return curve_point(c, t).x - d.max; };
    std::vector<double> cuts{cd.min};
    constexpr int kSamples = 64;
    for (int k = 0; k < kSamples; ++k) {
      double t0 = cd.min + cd.width() * k / kSamples, t1 = cd.min + cd.width() * (k + 1) / kSamples;
      const double f0 = beyond(t0), f1 = beyond(t1);
      if ((f0 < 0.0) == (f1 < 0.0)) continue;
      for (int i = 0; i < 60; ++i) {  // bisection to the crossing
        const double tm = 0.5 * (t0 + t1);
        ((beyond(tm) < 0.0) == (f0 < 0.0) ? t0 : t1) = tm;
      }
      const double tc = 0.5 * (t0 + t1);
      // A crossing at an end of the curve (within rounding of it) cuts nothing: the piece beyond
      // would be empty.
      const double eps = 1e-12 * cd.width();
      if (tc > cuts.back() + eps && tc < cd.max - eps) cuts.push_back(tc);
    }
    cuts.push_back(cd.max);
    for (size_t k = 0; k + 1 < cuts.size(); ++k)
      pieces.push_back(cuts.size() == 2 ? c : restrict_curve(c, cuts[k], cuts[k + 1]));
  }
  for (Curve2& c : pieces) {
    const Interval cd = curve_domain(c);
    if (curve_point(c, 0.5 * (cd.min + cd.max)).x > d.max)
      for (glm::dvec2& q : c.points) q.x -= period;
  }
  loop.curves = std::move(pieces);
}

// wrap_loops_into_domain along u (the caller transposes for v).
int wrap_along_u(TrimmedSurface& face, double tolerance_3d, double min_gap) {
  if (face.loops.empty() || !closed_along(face.surface, 0, tolerance_3d)) return 0;
  const Interval d = surface_domain_u(face.surface);
  const double period = d.width();
  int changed = 0;
  // Loops going once round (the circles bounding a band), each on its own: moved by whole periods
  // to start in the domain, and cut at its far side when they run past it.
  for (TrimLoop& l : face.loops) {
    if (!goes_round(l, period, min_gap)) continue;
    Interval e = u_extent(l);
    if (e.min >= d.min - min_gap && e.max <= d.max + min_gap) continue;
    const double shift = -period * std::floor((e.min - d.min + min_gap) / period);
    shift_u(l, shift);
    if (e.max + shift > d.max + min_gap) cut_round_loop(l, d);
    changed = 1;
  }
  // The rest together.
  Interval all{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const TrimLoop& l : face.loops) {
    const Interval e = u_extent(l);
    all.min = std::min(all.min, e.min), all.max = std::max(all.max, e.max);
  }
  if (!(all.min >= d.min - min_gap && all.max <= d.max + min_gap) && all.width() <= period + min_gap) {
    // Whole periods first: the loops start inside the domain.
    const double shift = -period * std::floor((all.min - d.min + min_gap) / period);
    for (TrimLoop& l : face.loops) shift_u(l, shift);
    if (all.max + shift <= d.max + min_gap) return 1;
    // Still across the far side: the surface one period longer.
    const Surface clamped = restrict_surface(face.surface, d, surface_domain_v(face.surface));
    if (std::optional<Surface> longer = doubled_along_u(clamped, tolerance_3d)) {
      face.surface = std::move(*longer);
      return 1;
    }
  }
  return changed;
}

}  // namespace

int wrap_loops_into_domain(TrimmedSurface& face, double tolerance_3d, double min_gap) {
  int wrapped = wrap_along_u(face, tolerance_3d, min_gap);
  TrimmedSurface t = face;
  t.surface = transposed(face.surface);
  for (TrimLoop& l : t.loops)
    for (Curve2& c : l.curves)
      for (glm::dvec2& q : c.points) std::swap(q.x, q.y);
  if (wrap_along_u(t, tolerance_3d, min_gap) == 0) return wrapped;
  face.surface = transposed(t.surface);
  for (size_t k = 0; k < face.loops.size(); ++k)
    for (size_t c = 0; c < face.loops[k].curves.size(); ++c) {
      face.loops[k].curves[c].points = t.loops[k].curves[c].points;
      for (glm::dvec2& q : face.loops[k].curves[c].points) std::swap(q.x, q.y);
    }
  return wrapped + 1;
}

int close_loops_round_seam(TrimmedSurface& face, double tolerance_3d, double min_gap) {
  return close_along(face, 0, tolerance_3d, min_gap) + close_along(face, 1, tolerance_3d, min_gap);
}

}  // namespace nurbs
