#pragma once
/// \file step_reader_detail.h
/// The STEP reader's parts (step_reader.h is its interface): the analytic surfaces by their STEP
/// parameters, the charts that bring edges into a face's parameters, and the reader class, whose
/// members live in three files: step_geometry.cpp (points, curves, surfaces, edges and their
/// PCURVEs), step_faces.cpp (loops, faces and their trims, shells) and step_reader.cpp (units,
/// representations, assemblies, the model).
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
#include "nurbs/io/step_reader.h"

namespace nurbs::io::step_detail {

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

inline double control_box_diagonal(const Curve3& c) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec3& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return glm::length(hi - lo);
}

inline glm::dmat4 frame_matrix(const Frame& f) {
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(f.x, 0.0);
  m[1] = glm::dvec4(f.y, 0.0);
  m[2] = glm::dvec4(f.z, 0.0);
  m[3] = glm::dvec4(f.o, 1.0);
  return m;
}

inline double wrap_near(double a, double ref) { return a + 2 * kPi * std::round((ref - a) / (2 * kPi)); }

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
  bool profile_crosses_axis = false;  // revolution: the profile has points on both sides of the axis
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
        // A spindle torus (minor radius above the major) holds points on its inner part at angle u
        // + pi, where r + r2 cos v < 0: the side whose tube circle passes nearer is p's.
        uv = std::abs(std::hypot(rho + r, z) - r2) < std::abs(std::hypot(rho - r, z) - r2)
                 ? glm::dvec2(std::atan2(-y, -x), std::atan2(z, -rho - r))
                 : glm::dvec2(std::atan2(y, x), std::atan2(z, rho - r));
        break;
      case Revolution: {
        // Turn p back by u into the profile's half-plane, then the nearest profile point. A profile
        // that crosses the axis sweeps p's circle from either side: at u or at u + pi, from the
        // opposite half-plane; the side whose profile point lies nearer is p's.
        const glm::dvec3 along = z * f.z, rr = d - along;
        auto on_side = [&](double u) {
          const glm::dvec3 back = f.o + along + std::cos(-u) * rr + std::sin(-u) * glm::cross(f.z, rr);
          const double t = line ? line_t(curve, back)
                                : nearest_t(curve, back, t_range, prev ? std::optional(prev->y) : std::nullopt, accept);
          return std::pair{glm::dvec2(u, t), glm::length(curve_at(t) - back)};
        };
        const auto [near_uv, near_d] = on_side(std::atan2(y, x) - phi0);
        uv = near_uv;
        if (profile_crosses_axis && near_d > accept) {  // the near side does not hold p
          const auto [far_uv, far_d] = on_side(std::atan2(-y, -x) - phi0);
          if (far_d < near_d) uv = far_uv;
        }
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


// A B-spline surface is periodic along a direction whose two boundary curves coincide; `accept`:
// a point this near the surface is on it (step_faces.cpp).
Chart bspline_chart(const Surface& s, double accept);

// The outer loop's natural (u, v) samples turned, run by run between its points on the axis, to run
// counter-clockwise within one turn (step_faces.cpp).
void choose_branches_across_axis(std::vector<glm::dvec2>& loop);

// A loop's (u, v) points made continuous between its points on the axis, the run ending the loop
// ending where it starts (step_faces.cpp).
void unwrap_across_axis(std::vector<std::vector<glm::dvec2>>& loop, double period);

struct Box2 {
  glm::dvec2 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
  void add(glm::dvec2 q) { lo = glm::min(lo, q), hi = glm::max(hi, q); }
  [[nodiscard]] glm::dvec2 centre() const { return 0.5 * (lo + hi); }
};


// Marks the loop enclosing the largest area as the outer one (step_faces.cpp).
void mark_outer(TrimmedSurface& f);

// Samples of an edge at which the gap between it and its face's trim is measured (besides the
// samples the trim's construction takes): ends, middle and every 1/32 of its parameter range.
constexpr int kGapSamples = 32;

// Largest distance from the surface points of the parameter-space curve `pc` (in s's (u, v), z = 0)
// to its 3D edge `c`, at kGapSamples + 1 points (step_faces.cpp).
double trim_gap(const Curve3& pc, const Curve3& c, const Surface& s);

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
    std::vector<int> uses;  // per ORIENTED_EDGE of the loop, its edge (a seam's twice)
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
  /// Edges of a solid's faces that bound one face only (a closed shell has none): how many, and
  /// the lowest such EDGE_CURVE with a face it bounds.
  struct UnpairedEdges {
    int count = 0;
    long edge = -1, face = -1;
  };
  UnpairedEdges unpaired_edges(const std::vector<FaceJob>& jobs) const;
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


}  // namespace nurbs::io::step_detail
