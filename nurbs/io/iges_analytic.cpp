// IGES 5.3 analytic surfaces (120, 122, 190-198) as exact rational NURBS: rational quadratic arcs
// in every angular direction (The NURBS Book §7.3) and surfaces of revolution as the tensor product
// of a profile and those arcs (§8.5).
#include "nurbs/io/iges_analytic.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>

#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/io/analytic_nurbs.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "nurbs/validate.h"

namespace nurbs::io {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// Loops are flattened within this fraction of their extent along each direction (see the header).
constexpr double kFlatten = 1e-7;

// Location, axis and reference direction of the entities 190-198.
struct Frame {
  glm::dvec3 origin, x, y, a;
};

glm::dvec3 read_point(IgesGeometry& g, const EntityParams& p, int i) {
  EntityParams q(g.file(), g.file().entry(g.expect(p, i, {116}, "a point")));
  return {q.real(1), q.real(2), q.real(3)};
}

glm::dvec3 read_direction(IgesGeometry& g, const EntityParams& p, int i) {
  EntityParams q(g.file(), g.file().entry(g.expect(p, i, {123}, "a direction")));
  const glm::dvec3 d(q.real(1), q.real(2), q.real(3));
  if (!(glm::length(d) > 0.0)) q.fail(1, "direction has zero length");
  return glm::normalize(d);
}

// Point at parameter 1, axis at `axis`, reference direction at `ref` when the form is 1.
Frame read_frame(IgesGeometry& g, const EntityParams& p, int axis, int ref) {
  Frame f;
  f.origin = read_point(g, p, 1);
  f.a = read_direction(g, p, axis);
  const int form = p.entry().form;
  if (form != 0 && form != 1) p.fail(0, fmt::format("form {} is not 0 or 1", form));
  const glm::dvec3 x = form == 1 ? read_direction(g, p, ref) : default_x(f.a);
  const glm::dvec3 xo = x - glm::dot(x, f.a) * f.a;
  if (glm::length(xo) < 1e-9) p.fail(ref, "reference direction is parallel to the axis");
  f.x = glm::normalize(xo);
  f.y = glm::cross(f.a, f.x);
  p.check_trailing(form == 1 ? ref : ref - 1);
  return f;
}

double positive(const EntityParams& p, int i, const char* what) {
  const double r = p.real(i);
  if (!(r > 0.0)) p.fail(i, fmt::format("{} is {}, must be > 0", what, r));
  return r;
}

// The only NURBS curve of a generatrix / directrix (composite curves of several pieces are not
// joined here).
Curve3 single_curve(IgesGeometry& g, const EntityParams& p, int i, const glm::dmat4& m) {
  const int de = g.expect(p, i, {100, 102, 104, 110, 126}, "a curve");
  std::vector<Curve3> pieces = g.curves(de, m);
  if (pieces.size() != 1) throw UnsupportedEntity{de, g.file().entry(de).type};
  return std::move(pieces.front());
}

// The start angle of the circular arc (100) that parameter i names, when it names one: IGES
// parametrises an arc by its angle from the start angle on, our NURBS of it from 0.
std::optional<double> arc_start_angle(IgesGeometry& g, const EntityParams& p, int i) {
  const int de = g.expect(p, i, {100, 102, 104, 110, 126}, "a curve");
  const IgesDirectoryEntry& e = g.file().entry(de);
  if (e.type != 100) return std::nullopt;
  EntityParams a(g.file(), e);
  return std::atan2(a.real(5) - a.real(3), a.real(4) - a.real(2));  // start - centre
}

void transform(Surface& s, const glm::dmat4& m) {
  for (glm::dvec3& q : s.points) q = glm::dvec3(m * glm::dvec4(q, 1.0));
}

}  // namespace

bool is_analytic_surface_type(int type) {
  return type == 120 || type == 122 || type == 190 || type == 192 || type == 194 || type == 196 || type == 198;
}

AnalyticSurface analytic_surface(IgesGeometry& g, int de, const glm::dmat4& parent, glm::dvec2 lo, glm::dvec2 hi) {
  const IgesDirectoryEntry& e = g.file().entry(de);
  const glm::dmat4 m = parent * g.transform(de);
  EntityParams p(g.file(), e);
  AnalyticSurface out;
  const double du = hi.x - lo.x, dv = hi.y - lo.y;
  switch (e.type) {
    case 190: {  // LOCATION, NORMAL, [REFDIR]
      const Frame f = read_frame(g, p, 2, 3);
      out.surface = plane_patch(f.origin, f.x, f.y, lo, hi);
      break;
    }
    case 192:    // LOCATION, AXIS, RADIUS, [REFDIR]
    case 194: {  // LOCATION, AXIS, RADIUS, SANGLE (degrees), [REFDIR]
      const bool cone = e.type == 194;
      const Frame f = read_frame(g, p, 2, cone ? 5 : 4);
      const double r = cone ? p.real(3) : positive(p, 3, "radius");
      if (cone && !(r >= 0.0)) p.fail(3, fmt::format("radius is {}, must be >= 0", r));
      const double angle = cone ? p.real(4) * kDegree : 0.0;
      if (cone && !(angle > 0.0 && angle < std::numbers::pi / 2))
        p.fail(4, fmt::format("semi-angle {} is not in (0, 90) degrees", p.real(4)));
      auto at = [&](double v) { return f.origin + (r + v * std::sin(angle)) * f.x + v * std::cos(angle) * f.a; };
      out.surface = revolve(segment(at(lo.y), at(hi.y), lo.y, hi.y), f.origin, f.a, lo.x * kDegree, du * kDegree, true);
      out.u = angular_axis(kDegree, lo.x, hi.x);
      break;
    }
    case 196: {  // CENTER, RADIUS, AXIS, [REFDIR]
      const Frame f = read_frame(g, p, 3, 4);
      const double r = positive(p, 2, "radius");
      const Curve3 meridian = circle_arc(f.origin, f.x, f.a, r, lo.y * kDegree, dv * kDegree);
      out.surface = revolve(meridian, f.origin, f.a, lo.x * kDegree, du * kDegree, true);
      out.u = angular_axis(kDegree, lo.x, hi.x);
      out.v = angular_axis(kDegree, lo.y, hi.y);
      break;
    }
    case 198: {  // CENTER, AXIS, MAJOR, MINOR, [REFDIR]
      const Frame f = read_frame(g, p, 2, 5);
      const double big = positive(p, 3, "major radius"), small = positive(p, 4, "minor radius");
      const Curve3 minor = circle_arc(f.origin + big * f.x, f.x, f.a, small, lo.x * kDegree, du * kDegree);
      // v turns clockwise about A (cos v X - sin v Y): right-handed about -A.
      out.surface = revolve(minor, f.origin, -f.a, lo.y * kDegree, dv * kDegree, false);
      out.u = angular_axis(kDegree, lo.x, hi.x);
      out.v = angular_axis(kDegree, lo.y, hi.y);
      break;
    }
    case 120: {  // L (axis line), C (generatrix), SA, TA (radians)
      // Turned in the entity's own space, then placed: a placing transform that mirrors (a 124 of
      // form 1, determinant -1) mirrors the turn's sense with it.
      const Curve3 axis = single_curve(g, p, 1, glm::dmat4(1.0));
      Curve3 generatrix = single_curve(g, p, 2, glm::dmat4(1.0));
      const double sa = p.real(3), ta = p.real(4);
      if (!(sa < ta)) p.fail(3, fmt::format("start angle {} is not less than terminate angle {}", sa, ta));
      p.check_trailing(4);
      // An arc generatrix: u is its angle (the file's pcurves run over [start, end angle]).
      if (const std::optional<double> a0 = arc_start_angle(g, p, 2)) {
        const Interval gu = curve_domain(generatrix);
        for (double& k : generatrix.knots) k += *a0;
        out.u = angular_axis(1.0, *a0, *a0 + gu.width());
      }
      const glm::dvec3 o = axis.points.front(), d = glm::normalize(axis.points.back() - o);
      out.surface = revolve(generatrix, o, d, lo.y, dv, false);
      out.v = angular_axis(1.0, lo.y, hi.y);
      break;
    }
    case 122: {  // DE (directrix), LX, LY, LZ (the generatrix end)
      const Curve3 c = single_curve(g, p, 1, m);
      const glm::dvec3 end = glm::dvec3(m * glm::dvec4(p.real(2), p.real(3), p.real(4), 1.0));
      p.check_trailing(4);
      const Interval t = curve_domain(c);
      const glm::dvec3 shift = end - curve_point(c, t.min);
      out.surface = extrude(c, glm::dvec3(0.0), shift, 0.0, 1.0);
      out.u.offset = t.min;
      out.u.scale = t.width();
      return out;
    }
    default:
      g.fail(de, "is not an analytic surface (120, 122, 190-198)");
  }
  transform(out.surface, m);
  return out;
}

TrimLoop plane_loop(IgesGeometry& g, int plane_de, const glm::dmat4& parent, int loop_de, bool outer,
                    double* off_plane) {
  const glm::dmat4 m = parent * g.transform(plane_de);
  EntityParams plane(g.file(), g.file().entry(plane_de));
  const Frame f = read_frame(g, plane, 2, 3);
  // Model-space frame of the plane: (u, v) = ((P - o) . x, (P - o) . y) / |x|^2, |x| = |y| for
  // the similarities of 124 (rigid motions and uniform scales).
  const glm::dvec3 o(m * glm::dvec4(f.origin, 1.0)), x(m * glm::dvec4(f.x, 0.0)), y(m * glm::dvec4(f.y, 0.0));
  const double x2 = glm::dot(x, x);
  const glm::dvec3 normal = glm::normalize(glm::cross(x, y));
  TrimLoop loop;
  loop.outer = outer;
  const auto list_size = [&g](int list) {
    EntityParams edges(g.file(), g.file().entry(list));
    return edges.integer(1, 1, std::max(1, edges.size()), "number of list entries N");
  };
  for (const LoopEdgeUse& use : loop_edge_uses(g, loop_de, list_size)) {
    if (use.type != 0) continue;
    EntityParams edges(g.file(), g.file().entry(use.list));
    const int curve = g.expect(edges, 2 + 5 * (use.ndx - 1), {100, 102, 104, 110, 126}, "a curve");
    std::vector<Curve2> piece;
    for (const Curve3& c3 : g.curves(curve, parent)) {
      if (off_plane)
        for (const glm::dvec3& q : c3.points) *off_plane = std::max(*off_plane, std::abs(glm::dot(q - o, normal)));
      Curve2 c2;
      c2.degree = c3.degree;
      c2.knots = c3.knots;
      c2.weights = c3.weights;
      for (const glm::dvec3& q : c3.points) c2.points.emplace_back(glm::dot(q - o, x) / x2, glm::dot(q - o, y) / x2);
      c2.edge = g.edge_id(use.list, use.ndx);
      piece.push_back(std::move(c2));
    }
    if (use.of == 0) {
      std::reverse(piece.begin(), piece.end());
      for (Curve2& c2 : piece) c2 = reversed(c2);
    }
    for (Curve2& c2 : piece) loop.curves.push_back(std::move(c2));
  }
  return loop;
}

std::vector<LoopEdgeUse> loop_edge_uses(IgesGeometry& g, int de, const std::function<int(int)>& list_size) {
  EntityParams p(g.file(), g.file().entry(de));
  const int n = p.integer(1, 1, std::max(1, p.size()), "number of edges N");
  std::vector<LoopEdgeUse> out;
  int i = 2;
  for (int c = 0; c < n; ++c) {
    LoopEdgeUse use;
    use.type = p.integer(i, 0, 1, "edge type");
    use.list = use.type == 0 ? g.expect(p, i + 1, {504}, "an edge list") : g.expect(p, i + 1, {502}, "a vertex list");
    use.ndx = p.integer(i + 2, 1, list_size(use.list), "list index NDX");
    use.of = p.integer(i + 3, 0, 1, "orientation flag OF");
    const int k = p.integer(i + 4, 0, std::max(0, (p.size() - i - 4) / 2), "number of parameter curves K");
    for (int j = 0; j < k; ++j) {
      p.integer(i + 5 + 2 * j);  // ISOP
      use.pcurves.push_back(g.expect(p, i + 6 + 2 * j, {100, 102, 104, 110, 126}, "a curve"));
    }
    out.push_back(std::move(use));
    i += 5 + 2 * k;
  }
  p.check_trailing(i - 1);
  return out;
}

std::optional<std::pair<glm::dvec2, glm::dvec2>> analytic_range(IgesGeometry& g, int de) {
  const IgesDirectoryEntry& e = g.file().entry(de);
  if (e.type == 122) return std::pair{glm::dvec2(0.0), glm::dvec2(1.0)};
  if (e.type != 120) return std::nullopt;
  EntityParams p(g.file(), e);
  const Interval u = curve_domain(single_curve(g, p, 2, glm::dmat4(1.0)));
  const double a0 = arc_start_angle(g, p, 2).value_or(0.0);  // the file's u of an arc: its angle
  return std::pair{glm::dvec2(a0 + u.min, p.real(3)), glm::dvec2(a0 + u.max, p.real(4))};
}

void set_analytic_surface(IgesGeometry& g, int de, const glm::dmat4& parent, TrimmedSurface& f,
                          const std::optional<std::pair<glm::dvec2, glm::dvec2>>& range) {
  // Extent of the control points (which bound the curves): each direction is flattened in its own
  // units, so a face 360 degrees round and 0.01 mm high keeps its height.
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const TrimLoop& loop : f.loops)
    for (const Curve2& c : loop.curves)
      for (const glm::dvec2& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const glm::dvec2 extent = hi - lo;
  const bool no_curves = lo.x > hi.x;
  if (!(no_curves && range) && (!(extent.x > 0.0 && extent.y > 0.0) || !std::isfinite(extent.x + extent.y)))
    g.fail(de, "its face's trim curves span no area of its parameter plane");
  std::vector<std::vector<std::vector<glm::dvec2>>> polylines(f.loops.size());
  glm::dvec2 box_lo(std::numeric_limits<double>::max()), box_hi(std::numeric_limits<double>::lowest());
  if (range) box_lo = range->first, box_hi = range->second;
  for (size_t l = 0; l < f.loops.size(); ++l)
    for (Curve2 c : f.loops[l].curves) {
      for (glm::dvec2& q : c.points) q = (q - lo) / extent;  // affine: exact for rational curves
      std::vector<glm::dvec2> line = flatten_curve(c, kFlatten);
      if (line.size() == 1) line.push_back(line.front());  // a curve collapsed to a point
      for (glm::dvec2& q : line) q = lo + q * extent, box_lo = glm::min(box_lo, q), box_hi = glm::max(box_hi, q);
      polylines[l].push_back(std::move(line));
    }
  const AnalyticSurface a = analytic_surface(g, de, parent, box_lo, box_hi);
  f.surface = a.surface;
  const bool exact = !a.u.angular && !a.v.angular;
  const Interval su = surface_domain_u(f.surface), sv = surface_domain_v(f.surface);
  // Rounding may put a mapped point a hair outside the domain (and some writers' trims reach 1e-8
  // beyond a 122's [0, 1]): clamp within 1e-6 of the domain, leave larger excursions to the checks.
  auto clamp = [](double x, Interval d) {
    const double eps = 1e-6 * d.width();
    return x < d.min && x > d.min - eps ? d.min : x > d.max && x < d.max + eps ? d.max : x;
  };
  auto map = [&](glm::dvec2 q) {
    const glm::dvec2 st = a.map(q);
    return glm::dvec2(clamp(st.x, su), clamp(st.y, sv));
  };
  for (size_t l = 0; l < f.loops.size(); ++l)
    for (size_t k = 0; k < f.loops[l].curves.size(); ++k) {
      Curve2& c = f.loops[l].curves[k];
      if (exact) {
        for (glm::dvec2& q : c.points) q = map(q);
        continue;
      }
      // A polyline within the flattening tolerance of the exact image of the curve.
      const std::vector<glm::dvec2>& line = polylines[l][k];
      const int edge = c.edge;
      c = Curve2{};
      c.edge = edge;
      c.degree = 1;
      c.knots.push_back(0.0);
      for (size_t i = 0; i < line.size(); ++i) {
        c.points.push_back(map(line[i]));
        c.knots.push_back(static_cast<double>(i));
      }
      c.knots.push_back(static_cast<double>(line.size() - 1));
    }
}

TrimmedSurface bounded_plane_face(IgesGeometry& g, int de, const glm::dmat4& parent) {
  const IgesDirectoryEntry& e = g.file().entry(de);
  if (e.form != 1) g.fail(de, fmt::format("form {} of a plane is not a bounded plane face (form 1)", e.form));
  EntityParams p(g.file(), e);
  p.require(5);
  const glm::dvec3 abc(p.real(1), p.real(2), p.real(3));
  const double d = p.real(4);
  if (!(glm::length(abc) > 0)) p.fail(1, "the plane's normal (A, B, C) is zero");
  const int boundary = p.pointer(5);
  const glm::dmat4 m = parent * g.transform(de);
  // Plane point and normal in model space (normals map by the inverse transpose).
  const glm::dvec3 o = glm::dvec3(m * glm::dvec4(d * abc / glm::dot(abc, abc), 1.0));
  const glm::dvec3 n = glm::normalize(glm::transpose(glm::inverse(glm::dmat3(m))) * abc);
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 e1 = glm::normalize(glm::cross(helper, n)), e2 = glm::cross(n, e1);
  TrimLoop loop;
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  double size = 0.0, off = 0.0;
  for (const Curve3& c : g.curves(boundary, m)) {
    Curve2 c2{c.degree, c.knots, {}, c.weights};
    for (const glm::dvec3& q : c.points) {
      const glm::dvec2 st(glm::dot(q - o, e1), glm::dot(q - o, e2));
      c2.points.push_back(st);
      lo = glm::min(lo, st);
      hi = glm::max(hi, st);
      off = std::max(off, std::abs(glm::dot(q - o, n)));
    }
    loop.curves.push_back(std::move(c2));
  }
  size = glm::length(hi - lo);
  if (loop.curves.empty() || !(size > 0)) p.fail(5, "the boundary curve is empty or a point");
  if (off > 1e-6 * size)
    p.fail(5, fmt::format("the boundary's control points lie up to {:.3g} off the plane (size {:.3g})", off, size));
  TrimmedSurface f;
  f.surface = plane_patch(o, e1, e2, lo, hi);
  loop.outer = true;
  f.loops.push_back(std::move(loop));
  return f;
}

}  // namespace nurbs::io
