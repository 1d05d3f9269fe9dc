// STEP geometry: points, directions, placements, B-spline curves and surfaces, conics, the
// analytic surfaces, the pieces of an edge with their PCURVEs (ISO 10303-42).
#include "nurbs/io/step_reader_detail.h"

namespace nurbs::io::step_detail {

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
    // Control points beyond the axis, on the far side of the profile's half-plane: the profile
    // may cross the axis (a full circle swept about a line through it: a spindle, a domed end).
    const glm::dvec3 side = std::cos(a.phi0) * a.f.x + std::sin(a.phi0) * a.f.y;
    for (const glm::dvec3& q : a.curve.points)
      a.profile_crosses_axis = a.profile_crosses_axis || glm::dot(q - a.f.o, side) < -1e-9 * best;
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

}  // namespace nurbs::io::step_detail
