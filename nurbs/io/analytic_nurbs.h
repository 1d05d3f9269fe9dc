#pragma once
/// \file analytic_nurbs.h
/// Exact rational NURBS pieces of the analytic surfaces that IGES and STEP files describe by their
/// parameters (planes, cylinders, cones, spheres, tori, surfaces of revolution): circular arcs of
/// at most 90 degrees each as rational quadratics (The NURBS Book §7.5), surfaces of revolution as
/// the tensor product of a profile and such arcs (§8.5), and the exact map from an angle to the
/// parameter of those arcs. Internal to the readers.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "nurbs/curve.h"
#include "nurbs/surface.h"

namespace nurbs::io {

/// The map of one direction from a file's surface parameter x to the NURBS parameter. Linear:
/// offset + scale x. Angular: the angle a = scale x (radians) on rational quadratic arcs, `arcs`
/// equal arcs of `sweep` / arcs radians from `start`, knot k at start + k sweep / arcs: exact,
/// closed form (an arc with middle weight cos(h / 2), h its sweep, reaches the angle h / 2 +
/// 2 atan(sigma tan(h / 4)) at its parameter (sigma + 1) / 2, The NURBS Book §7.3).
struct ParameterAxis {
  bool angular = false;
  double scale = 1.0;
  double offset = 0.0;
  double start = 0.0;  ///< angular: first angle (radians) = first knot
  double sweep = 0.0;  ///< angular: total angle (radians) > 0
  int arcs = 0;        ///< angular: number of arcs, each at most 90 degrees
  [[nodiscard]] double operator()(double x) const;
  /// The file's parameter of the NURBS parameter s (the inverse map, closed form).
  [[nodiscard]] double inverse(double s) const;
};

/// An analytic surface as NURBS with its map (the file's u, v) -> (s, t), monotone in each direction.
struct AnalyticSurface {
  Surface surface;
  ParameterAxis u, v;
  [[nodiscard]] glm::dvec2 map(glm::dvec2 uv) const { return {u(uv.x), v(uv.y)}; }
};

/// The angular axis of the angles scale x for x in [x0, x1].
ParameterAxis angular_axis(double scale, double x0, double x1);

/// The arc of the circle centre + rho (cos a e1 + sin a e2), a in [a0, a0 + sweep] (radians); its
/// knots are the angle at the arc ends.
Curve3 circle_arc(glm::dvec3 centre, glm::dvec3 e1, glm::dvec3 e2, double rho, double a0, double sweep);

/// The plane patch origin + u x + v y over [lo.x, hi.x] x [lo.y, hi.y], its parameters (u, v).
Surface plane_patch(glm::dvec3 origin, glm::dvec3 x, glm::dvec3 y, glm::dvec2 lo, glm::dvec2 hi);

/// The curve swept along a line: S(u, v) = C(u) + d0 + (v - v0) / (v1 - v0) (d1 - d0), u the
/// curve's parameter, v in [v0, v1] (exact, weights kept).
Surface extrude(const Curve3& c, glm::dvec3 d0, glm::dvec3 d1, double v0, double v1);

/// Degree-1 segment from a to b on the parameter interval [t0, t1].
Curve3 segment(glm::dvec3 a, glm::dvec3 b, double t0, double t1);

/// The profile turned about the axis through `origin` along unit `dir` by the angles a0..a0 + sweep
/// (right-handed): exact for rational profiles (weights multiply). The angle runs along u when
/// `angle_in_u`, else along v.
Surface revolve(const Curve3& profile, glm::dvec3 origin, glm::dvec3 dir, double a0, double sweep, bool angle_in_u);

/// OpenCASCADE's gp_Ax2(P, V) choice of X for an axis without reference direction: one coordinate
/// zeroed, the smallest of |V|'s.
glm::dvec3 default_x(glm::dvec3 v);

}  // namespace nurbs::io
