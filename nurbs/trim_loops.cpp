#include "nurbs/trim_loops.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <set>

#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/knot_insertion.h"
#include "nurbs/knot_vector.h"
#include "nurbs/segment_distance.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "nurbs/validate.h"

namespace nurbs {
namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

/// Closed-segment intersection (touching counts), with the intersection or touching point.
bool segments_meet(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d, glm::dvec2& where) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    where = c + (d - c) * (d1 / (d1 - d2));  // d1, d2: c's and d's sides of the line ab
    return true;
  }
  auto on = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {  // r on segment pq, given collinear
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  if (d1 == 0 && on(a, b, c)) return where = c, true;
  if (d2 == 0 && on(a, b, d)) return where = d, true;
  if (d3 == 0 && on(c, d, a)) return where = a, true;
  if (d4 == 0 && on(c, d, b)) return where = b, true;
  return false;
}

struct Edge {
  glm::dvec2 a, b;
  size_t loop, index, loop_size;
  double xmin, xmax, ymin, ymax;
};

bool adjacent(const Edge& e, const Edge& f) {
  if (e.loop != f.loop) return false;
  const size_t n = e.loop_size;
  return (e.index + 1) % n == f.index || (f.index + 1) % n == e.index;
}

}  // namespace

namespace {

/// The loops' vertices lifted to space, on first use, and what the touch rule asks of them.
class Touches {
 public:
  Touches(const TrimmedSurface& face, const TrimPolygons& polys, double tolerance)
      : face_(face), polys_(polys), tolerance_(tolerance) {}
  /// Whether the meeting of edges e and f is a touch (check_trim_loops); `size` gets its span.
  bool touch(size_t loop_e, size_t index_e, size_t loop_f, size_t index_f, glm::dvec2 where, double& size) {
    if (!(tolerance_ > 0.0)) return false;
    size = 0.0;
    if (loop_e != loop_f) {
      if ((size = at_shared_vertex(loop_e, loop_f, where)) <= tolerance_) return true;
      size = 0.0;
      if (encloses_nothing(loop_e) || encloses_nothing(loop_f)) return true;
      const std::pair<size_t, size_t> key{std::min(loop_e, loop_f), std::max(loop_e, loop_f)};
      auto found = lens_.find(key);
      if (found == lens_.end()) {
        const double lens = std::max(beyond(loop_e, loop_f), beyond(loop_f, loop_e));
        found = lens_.emplace(key, lens).first;
      }
      size = found->second;
      return size <= tolerance_;
    }
    // The two parts of the loop between the passes: vertices (i, j] and (j, i] in loop order.
    const std::vector<glm::dvec3>& xyz = lifted(loop_e);
    const size_t n = xyz.size(), i = std::min(index_e, index_f), j = std::max(index_e, index_f);
    const glm::dvec3 at = surface_point(face_.surface, where.x, where.y);  // both parts run from it
    const auto span = [&](size_t from, size_t count) {
      glm::dvec3 lo = at, hi = at;
      for (size_t k = 1; k <= count; ++k) lo = glm::min(lo, xyz[(from + k) % n]), hi = glm::max(hi, xyz[(from + k) % n]);
      return glm::length(hi - lo);
    };
    const double span_i = span(i, j - i), span_j = span(j, n - (j - i));
    size = std::min(span_i, span_j);
    if (size <= tolerance_) return true;
    if ((size = at_shared_vertex(loop_e, loop_f, where)) <= tolerance_) return true;
    const bool first = span_i <= span_j;  // the lobe: the part of lesser extent
    size = first ? thin_part(xyz, i, j - i, at) : thin_part(xyz, j, n - (j - i), at);
    if (size <= tolerance_) return true;
    size = first ? hugging_part(xyz, i, j - i, at) : hugging_part(xyz, j, n - (j - i), at);
    return size <= tolerance_;
  }

 private:
  /// How far in space the vertices of loop a on its lesser side of loop b (inside b or outside,
  /// whichever holds fewer) lie from b's polygon: two loops that only touch (a hole tangent to the
  /// outline, both curves fitted within the tolerance) cross in a lens no wider than the fits'
  /// error; loops that overlap put a whole stretch of one on the wrong side.
  double beyond(size_t a, size_t b) {
    const std::vector<glm::dvec2>& pa = polys_.loops[a];
    std::vector<char> in(pa.size());
    size_t inside = 0;
    for (size_t i = 0; i < pa.size(); ++i) inside += in[i] = winding_number(polys_.loops[b], pa[i]) != 0;
    const bool lesser = 2 * inside < pa.size();  // the side with fewer vertices: inside when true
    const std::vector<glm::dvec3>& xa = lifted(a);
    const std::vector<glm::dvec3>& xb = lifted(b);
    double worst = 0.0;
    for (size_t i = 0; i < pa.size(); ++i) {
      if (bool(in[i]) != lesser) continue;
      double nearest = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < xb.size(); ++k)
        nearest = std::min(nearest, segment_distance(xa[i], xb[k], xb[(k + 1) % xb.size()]));
      worst = std::max(worst, nearest);
      if (worst > tolerance_) break;
    }
    return worst;
  }
  /// The largest distance in space from points[lo..hi] to the polyline line[first..last] (its
  /// segments); stops once past the tolerance.
  double farthest(const std::vector<glm::dvec3>& points, size_t lo, size_t hi, const std::vector<glm::dvec3>& line,
                  size_t first, size_t last) const {
    double worst = 0.0;
    for (size_t k = lo; k <= hi && worst <= tolerance_; ++k) {
      double nearest = std::numeric_limits<double>::infinity();
      for (size_t m = first; m < last; ++m)
        nearest = std::min(nearest, segment_distance(points[k], line[m], line[m + 1]));
      worst = std::max(worst, nearest);
    }
    return worst;
  }
  /// The part of a loop between its two passes through `at`, vertices from + 1 .. from + count:
  /// split at its vertex farthest from `at` into two sides running from `at` to it, how far in
  /// space the vertices of each side lie from the other side. A sliver face whose two long edges,
  /// as fitted, cross near its tip leaves a lobe beyond the crossing no wider than that (a lens,
  /// as beyond() measures between two loops); a loop that truly crosses itself leaves a wide one.
  /// Stops once past the tolerance.
  double thin_part(const std::vector<glm::dvec3>& xyz, size_t from, size_t count, const glm::dvec3& at) const {
    std::vector<glm::dvec3> part{at};
    for (size_t k = 1; k <= count; ++k) part.push_back(xyz[(from + k) % xyz.size()]);
    part.push_back(at);
    size_t apex = 0;
    for (size_t k = 1; k < part.size(); ++k)
      if (glm::length(part[k] - at) > glm::length(part[apex] - at)) apex = k;
    const size_t end = part.size() - 1;
    const double one = farthest(part, 0, apex, part, apex, end);
    return one > tolerance_ ? one : std::max(one, farthest(part, apex, end, part, 0, apex));
  }
  /// How far in space the vertices from + 1 .. from + count of a loop lie from the rest of it (the
  /// other part, through `at`): a lobe that runs along the loop beyond the crossing, within that of
  /// it (a pcurve running out and back along a side, as fitted). Stops once past the tolerance.
  double hugging_part(const std::vector<glm::dvec3>& xyz, size_t from, size_t count, const glm::dvec3& at) const {
    const size_t n = xyz.size();
    std::vector<glm::dvec3> lobe, rest{at};
    for (size_t k = 1; k <= count; ++k) lobe.push_back(xyz[(from + k) % n]);
    for (size_t k = from + count + 1; k <= from + n; ++k) rest.push_back(xyz[k % n]);
    rest.push_back(at);
    return lobe.empty() ? 0.0 : farthest(lobe, 0, lobe.size() - 1, rest, 0, rest.size() - 1);
  }
  /// Where the loops meet at `where` in a vertex they both pass through, two of loop e's when
  /// e = f (curve ends, in space within the tolerance): a hole whose vertex lies on the outline, a
  /// loop through one vertex twice (BRepCheck takes meetings at a vertex as valid), how far in
  /// space the meeting lies from those vertices; else infinity.
  double at_shared_vertex(size_t loop_e, size_t loop_f, glm::dvec2 where) {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (loop_e >= face_.loops.size() || loop_f >= face_.loops.size()) return kNone;
    const glm::dvec3 at = surface_point(face_.surface, where.x, where.y);
    double far = 0.0;
    const auto near = [&](size_t loop) {
      size_t n = 0;
      for (const glm::dvec3& v : vertices(loop))
        if (const double d = glm::length(v - at); d <= tolerance_) ++n, far = std::max(far, d);
      return n;
    };
    const bool shared = loop_e == loop_f ? near(loop_e) >= 2 : near(loop_e) >= 1 && near(loop_f) >= 1;
    return shared ? far : kNone;
  }
  const std::vector<glm::dvec3>& vertices(size_t loop) {
    if (vertices_.empty()) vertices_.resize(face_.loops.size());
    std::vector<glm::dvec3>& out = vertices_[loop];
    if (out.empty())
      for (const Curve2& c : face_.loops[loop].curves) {
        const glm::dvec2 p = start_point(c);
        out.push_back(surface_point(face_.surface, p.x, p.y));
      }
    return out;
  }
  const std::vector<glm::dvec3>& lifted(size_t loop) {
    if (xyz_.empty()) xyz_.resize(polys_.loops.size());
    std::vector<glm::dvec3>& out = xyz_[loop];
    if (out.empty())
      for (const glm::dvec2& p : polys_.loops[loop]) out.push_back(surface_point(face_.surface, p.x, p.y));
    return out;
  }
  bool encloses_nothing(size_t loop) const { return nurbs::encloses_nothing(polys_.loops[loop]); }
  const TrimmedSurface& face_;
  const TrimPolygons& polys_;
  double tolerance_;
  std::vector<std::vector<glm::dvec3>> xyz_, vertices_;
  std::map<std::pair<size_t, size_t>, double> lens_;  ///< beyond() both ways, per pair of loops
};

/// check_trim_loops with the flattening done on demand (after the curves are known valid) when
/// `given` is null.
std::vector<std::string> check_loops(const TrimmedSurface& face, double gap_tolerance, const TrimPolygons* given,
                                     double flatten_tolerance, double touch_tolerance = 0.0,
                                     double* touch_size = nullptr) {
  std::vector<std::string> out;
  const int id = face.face_id;
  bool curves_valid = true;
  for (size_t k = 0; k < face.loops.size(); ++k) {
    const auto& loop = face.loops[k];
    if (loop.curves.empty()) out.push_back(fmt::format("face {}: loop {} has no curves", id, k));
    for (size_t c = 0; c < loop.curves.size(); ++c) {
      for (const auto& p : validate(loop.curves[c])) {
        out.push_back(fmt::format("face {}: loop {} curve {}: {}", id, k, c, p));
        curves_valid = false;
      }
    }
  }
  if (!curves_valid) return out;  // evaluation below assumes valid curves
  for (size_t k = 0; k < face.loops.size(); ++k) {
    const auto& curves = face.loops[k].curves;
    for (size_t c = 0; c < curves.size(); ++c) {
      const size_t next = (c + 1) % curves.size();
      const double gap = glm::length(end_point(curves[c]) - start_point(curves[next]));
      if (gap > gap_tolerance) {
        out.push_back(
            fmt::format("face {}: loop {} does not close: curve {} ends {:.3g} from the start of curve {} "
                        "(tolerance {:.3g})",
                        id, k, c, gap, next, gap_tolerance));
      }
    }
  }
  TrimPolygons flattened;
  if (given == nullptr) flattened = flatten_trim(face, flatten_tolerance);
  const TrimPolygons& polys = given != nullptr ? *given : flattened;
  std::vector<Edge> edges;
  for (size_t k = 0; k < polys.loops.size(); ++k) {
    const auto& poly = polys.loops[k];
    for (size_t i = 0; i < poly.size() && poly.size() >= 2; ++i) {
      const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
      edges.push_back(
          {a, b, k, i, poly.size(), std::min(a.x, b.x), std::max(a.x, b.x), std::min(a.y, b.y), std::max(a.y, b.y)});
    }
  }
  // Sweep in x: only edges whose x ranges overlap are candidates; their y ranges must overlap too
  // (edges along a constant-u line share x ranges, so x alone lets O(E^2) pairs through).
  // Loops lying on top of each other make every pair of their edges a candidate: the work stops at
  // kMaxCandidatePairs (a fraction of a second), said in the report, so that no file makes this run for minutes.
  // n copies of one loop cross in n^2 / 2 pairs: at most kMaxCrossingReports messages, the rest summed up.
  // Where the sweep in x would pass more candidates than that (loops running along the domain's
  // sides u = u0 and u = u1 in thousands of edges each), it runs in y instead when that passes fewer.
  constexpr long long kMaxCandidatePairs = 30'000'000;
  constexpr size_t kMaxCrossingReports = 1000;
  long long candidates = 0;
  const auto sweep_pairs = [&](auto lo, auto hi) {  // pairs whose [lo, hi] ranges overlap, counted by sorting
    std::vector<double> starts;
    starts.reserve(edges.size());
    for (const Edge& e : edges) starts.push_back(lo(e));
    std::sort(starts.begin(), starts.end());
    long long pairs = 0;
    for (const Edge& e : edges)
      pairs += static_cast<long long>(std::upper_bound(starts.begin(), starts.end(), hi(e)) -
                                      std::lower_bound(starts.begin(), starts.end(), lo(e))) - 1;
    return pairs;
  };
  const auto x_lo = [](const Edge& e) { return e.xmin; };
  const auto x_hi = [](const Edge& e) { return e.xmax; };
  const auto y_lo = [](const Edge& e) { return e.ymin; };
  const auto y_hi = [](const Edge& e) { return e.ymax; };
  if (sweep_pairs(x_lo, x_hi) > kMaxCandidatePairs && sweep_pairs(y_lo, y_hi) < sweep_pairs(x_lo, x_hi))
    for (Edge& e : edges) std::swap(e.xmin, e.ymin), std::swap(e.xmax, e.ymax);  // the sweep's axis only
  std::sort(edges.begin(), edges.end(), [](const Edge& e, const Edge& f) { return e.xmin < f.xmin; });
  std::set<std::pair<size_t, size_t>> reported;  // loop pairs already reported (one message each)
  Touches touches(face, polys, touch_tolerance);
  if (touch_size) *touch_size = 0.0;
  for (size_t i = 0; i < edges.size(); ++i) {
    for (size_t j = i + 1; j < edges.size() && edges[j].xmin <= edges[i].xmax; ++j) {
      if (++candidates > kMaxCandidatePairs) {
        out.push_back(
            fmt::format("face {}: crossing check stopped after {} candidate edge pairs (loops overlapping "
                        "over long stretches?); further crossings are not reported",
                        id, kMaxCandidatePairs));
        return out;
      }
      const Edge &e = edges[i], &f = edges[j];
      if (f.ymin > e.ymax || e.ymin > f.ymax || adjacent(e, f)) continue;
      const std::pair<size_t, size_t> key{std::min(e.loop, f.loop), std::max(e.loop, f.loop)};
      if (reported.count(key) != 0) continue;
      glm::dvec2 where;
      if (!segments_meet(e.a, e.b, f.a, f.b, where)) continue;
      if (double size = 0.0; touches.touch(e.loop, e.index, f.loop, f.index, where, size)) {
        if (touch_size) *touch_size = std::max(*touch_size, size);
        continue;
      }
      if (reported.size() == kMaxCrossingReports) {
        out.push_back(
            fmt::format("face {}: more than {} crossing loop pairs; the rest are not listed", id, kMaxCrossingReports));
        return out;
      }
      reported.insert(key);
      if (e.loop == f.loop) {
        out.push_back(fmt::format("face {}: loop {} crosses itself near (u, v) = ({:.6g}, {:.6g})", id, e.loop, where.x,
                                  where.y));
      } else {
        out.push_back(fmt::format("face {}: loops {} and {} cross near (u, v) = ({:.6g}, {:.6g})", id, key.first,
                                  key.second, where.x, where.y));
      }
    }
  }
  return out;
}

}  // namespace

bool encloses_nothing(const std::vector<glm::dvec2>& poly) {
  if (poly.size() < 3) return true;
  glm::dvec2 lo = poly.front(), hi = lo;
  for (const glm::dvec2& p : poly) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return std::abs(2.0 * signed_area(poly)) <= 1e-9 * (hi.x - lo.x) * (hi.y - lo.y);
}

std::vector<std::string> check_trim_loops(const TrimmedSurface& face, double gap_tolerance, double flatten_tolerance) {
  return check_loops(face, gap_tolerance, nullptr, flatten_tolerance);
}

std::vector<std::string> check_trim_loops(const TrimmedSurface& face, double gap_tolerance,
                                          const TrimPolygons& polygons, double touch_tolerance, double* touch_size) {
  return check_loops(face, gap_tolerance, &polygons, 0.0, touch_tolerance, touch_size);
}

int repair_trim_gaps(TrimmedSurface& face, double tolerance, double min_gap) {
  int repairs = 0;
  for (auto& loop : face.loops) {
    for (size_t c = 0; c < loop.curves.size(); ++c) {
      Curve2& cur = loop.curves[c];
      const glm::dvec2 target = start_point(loop.curves[(c + 1) % loop.curves.size()]);
      const double gap = glm::length(end_point(cur) - target);
      if (!(gap > min_gap && gap <= tolerance)) continue;
      if (!is_clamped(cur.knots, cur.degree)) {
        const int edge = cur.edge;
        cur = from_homogeneous<2>(clamp_curve(to_homogeneous(cur)), cur.rational());
        cur.edge = edge;
      }
      cur.points.back() = target;  // clamped: the curve ends at its last control point
      ++repairs;
    }
  }
  return repairs;
}

int reorder_trim_curves(TrimmedSurface& face, double tolerance) {
  int rebuilt = 0;
  for (TrimLoop& loop : face.loops) {
    const size_t n = loop.curves.size();
    bool chained = true;
    for (size_t c = 0; c < n && chained; ++c)
      chained = glm::length(end_point(loop.curves[c]) - start_point(loop.curves[(c + 1) % n])) <= tolerance;
    if (chained || n < 2) continue;
    std::vector<Curve2> chain{loop.curves.front()};
    std::vector<char> used(n, 0);
    used[0] = 1;
    bool ok = true;
    while (chain.size() < n && ok) {
      const glm::dvec2 at = end_point(chain.back());
      size_t best = n;
      bool flip = false;
      double nearest = tolerance;
      for (size_t c = 1; c < n; ++c) {
        if (used[c]) continue;
        const double to_start = glm::length(start_point(loop.curves[c]) - at);
        const double to_end = glm::length(end_point(loop.curves[c]) - at);
        if (to_start <= nearest) nearest = to_start, best = c, flip = false;
        if (to_end < nearest) nearest = to_end, best = c, flip = true;
      }
      if (best == n) {
        ok = false;
        break;
      }
      used[best] = 1;
      chain.push_back(flip ? reversed(loop.curves[best]) : loop.curves[best]);
    }
    if (!ok || glm::length(end_point(chain.back()) - start_point(chain.front())) > tolerance) continue;
    loop.curves = std::move(chain);
    ++rebuilt;
  }
  return rebuilt;
}

namespace {

/// Whether most vertices of `inner` (all but a tenth: loops may touch) lie inside `outer`.
bool mostly_inside(const std::vector<glm::dvec2>& inner, const std::vector<glm::dvec2>& outer) {
  if (inner.empty() || outer.size() < 3) return false;
  size_t in = 0;
  for (const glm::dvec2& p : inner) in += winding_number(outer, p) != 0;
  return 10 * in >= 9 * inner.size();
}

}  // namespace

int fix_outer_loop(TrimmedSurface& face, TrimPolygons& polys) {
  size_t declared = face.loops.size();
  for (size_t k = 0; k < face.loops.size(); ++k)
    if (face.loops[k].outer) {
      if (declared != face.loops.size()) return 0;  // several outer loops: not this case
      declared = k;
    }
  if (declared == face.loops.size() || face.loops.size() < 2) return 0;
  for (size_t c = 0; c < face.loops.size(); ++c) {
    if (c == declared || !mostly_inside(polys.loops[declared], polys.loops[c])) continue;
    bool holds_all = true;
    for (size_t k = 0; k < face.loops.size() && holds_all; ++k)
      holds_all = k == c || mostly_inside(polys.loops[k], polys.loops[c]);
    if (!holds_all) continue;
    face.loops[c].outer = polys.outer[c] = true;
    face.loops[declared].outer = polys.outer[declared] = false;
    return 1;
  }
  return 0;
}

int orient_trim_loops(TrimmedSurface& face, double flatten_tolerance) {
  return orient_trim_loops(face, flatten_trim(face, flatten_tolerance));
}

int orient_trim_loops(TrimmedSurface& face, const TrimPolygons& polys) {
  int reversed_loops = 0;
  for (size_t k = 0; k < face.loops.size(); ++k) {
    const double area = signed_area(polys.loops[k]);
    auto& loop = face.loops[k];
    if ((loop.outer && area < 0) || (!loop.outer && area > 0)) {
      std::reverse(loop.curves.begin(), loop.curves.end());
      for (auto& c : loop.curves) c = reversed(c);
      ++reversed_loops;
    }
  }
  return reversed_loops;
}

}  // namespace nurbs
