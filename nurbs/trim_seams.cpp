#include "nurbs/trim_seams.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <vector>

#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/surface_eval.h"

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

int close_along(TrimmedSurface& face, int axis, double tolerance_3d, double min_gap) {
  if (!closed_along(face.surface, axis, tolerance_3d)) return 0;
  const Interval d = domain(face.surface, axis), across = domain(face.surface, 1 - axis);
  std::vector<size_t> open;      // loops with one seam jump, rotated to start right after it
  std::vector<TrimLoop> halves;  // second halves of loops that cross the seam twice
  int closed = 0;
  for (size_t k = 0; k < face.loops.size(); ++k) {
    TrimLoop& loop = face.loops[k];
    const std::vector<size_t> at_jump = jumps(loop, d, axis, min_gap);
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
  std::vector<size_t> merged_away;
  for (size_t i = 0; i + 1 < open.size(); i += 2) {  // pairs: the two boundaries of a band
    TrimLoop &a = face.loops[open[i]], &b = face.loops[open[i + 1]];
    const double a_end = end_point(a.curves.back())[axis];
    if (std::abs(start_point(b.curves.front())[axis] - a_end) > min_gap) {  // both run the same way
      turn_round(b);
    }
    const glm::dvec2 a0 = start_point(a.curves.front()), a1 = end_point(a.curves.back());
    const glm::dvec2 b0 = start_point(b.curves.front()), b1 = end_point(b.curves.back());
    a.curves.push_back(segment_curve(a1, b0));  // along the seam side where a ends
    for (Curve2& c : b.curves) a.curves.push_back(std::move(c));
    a.curves.push_back(segment_curve(b1, a0));
    a.outer = a.outer || b.outer;
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
    ++closed;
  }
  std::sort(merged_away.rbegin(), merged_away.rend());
  for (size_t k : merged_away) face.loops.erase(face.loops.begin() + static_cast<std::ptrdiff_t>(k));
  for (TrimLoop& h : halves) face.loops.push_back(std::move(h));
  return closed;
}

}  // namespace

int close_loops_round_seam(TrimmedSurface& face, double tolerance_3d, double min_gap) {
  return close_along(face, 0, tolerance_3d, min_gap) + close_along(face, 1, tolerance_3d, min_gap);
}

}  // namespace nurbs
