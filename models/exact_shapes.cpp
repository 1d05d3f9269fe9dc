#include "models/exact_shapes.h"

#include <cmath>
#include <vector>

namespace models {
namespace {

const double kHalfSqrt2 = std::sqrt(0.5);

/// Unit 9-point circle control polygon: points on the square of half-side 1, corner weights sqrt(2)/2.
struct Circle9 {
  std::vector<glm::dvec2> points;
  std::vector<double> weights;
};

Circle9 unit_circle9() {
  Circle9 c;
  const double xs[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1};
  const double ys[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
  for (int i = 0; i < 9; ++i) {
    c.points.emplace_back(xs[i], ys[i]);
    c.weights.push_back(i % 2 == 1 ? kHalfSqrt2 : 1.0);
  }
  return c;
}

const std::vector<double> kCircleKnots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};

/// Surface of revolution about z of a rational profile (r_j, z_j, w_j): P_ij = (r_j x_i, r_j y_i, z_j),
/// w_ij = w_i w_j (tensor product of the circle and the profile, §8.5).
nurbs::Surface revolve(const std::vector<glm::dvec2>& profile, const std::vector<double>& profile_weights,
                       const std::vector<double>& profile_knots, int profile_degree, glm::dvec3 centre) {
  const Circle9 c = unit_circle9();
  nurbs::Surface s;
  s.degree_u = 2;
  s.degree_v = profile_degree;
  s.count_u = 9;
  s.count_v = static_cast<int>(profile.size());
  s.knots_u = kCircleKnots;
  s.knots_v = profile_knots;
  for (size_t j = 0; j < profile.size(); ++j) {
    for (int i = 0; i < 9; ++i) {
      const glm::dvec2 q = c.points[static_cast<size_t>(i)];
      s.points.push_back(centre + glm::dvec3(profile[j].x * q.x, profile[j].x * q.y, profile[j].y));
      s.weights.push_back(c.weights[static_cast<size_t>(i)] * profile_weights[j]);
    }
  }
  return s;
}

}  // namespace

nurbs::Curve2 rational_circle_2d(glm::dvec2 centre, double radius, bool ccw) {
  const Circle9 c = unit_circle9();
  nurbs::Curve2 curve;
  curve.degree = 2;
  curve.knots = kCircleKnots;
  for (int i = 0; i < 9; ++i) {
    glm::dvec2 q = c.points[static_cast<size_t>(i)];
    if (!ccw) q.y = -q.y;  // mirror: same start point, opposite sense
    curve.points.push_back(centre + radius * q);
  }
  curve.weights = c.weights;
  return curve;
}

nurbs::Curve3 rational_quarter_circle(double radius) {
  nurbs::Curve3 c;
  c.degree = 2;
  c.knots = {0, 0, 0, 1, 1, 1};
  c.points = {{radius, 0, 0}, {radius, radius, 0}, {0, radius, 0}};
  c.weights = {1.0, kHalfSqrt2, 1.0};
  return c;
}

nurbs::Surface rational_sphere(double radius, glm::dvec3 centre) {
  const double r = radius;
  return revolve({{0, -r}, {r, -r}, {r, 0}, {r, r}, {0, r}}, {1, kHalfSqrt2, 1, kHalfSqrt2, 1},
                 {0, 0, 0, 0.5, 0.5, 1, 1, 1}, 2, centre);
}

nurbs::Surface rational_torus(double major, double minor, glm::dvec3 centre) {
  const Circle9 c = unit_circle9();
  std::vector<glm::dvec2> profile;
  for (const auto& q : c.points) profile.push_back(glm::dvec2(major, 0.0) + minor * q);
  return revolve(profile, c.weights, kCircleKnots, 2, centre);
}

nurbs::Surface bilinear_square(double side) {
  nurbs::Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, side, side};
  s.points = {{0, 0, 0}, {side, 0, 0}, {0, side, 0}, {side, side, 0}};
  return s;
}

nurbs::Surface bilinear_patch(const std::array<glm::dvec3, 4>& corners) {
  nurbs::Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points.assign(corners.begin(), corners.end());
  return s;
}

nurbs::Surface rational_cylinder(double radius, double height, glm::dvec3 base) {
  return revolve({{radius, 0}, {radius, height}}, {1, 1}, {0, 0, 1, 1}, 1, base);
}

nurbs::TrimmedSurface cubic_square_with_hole(double hole) {
  nurbs::TrimmedSurface square;
  square.surface.degree_u = square.surface.degree_v = 3;
  square.surface.count_u = square.surface.count_v = 4;
  square.surface.knots_u = square.surface.knots_v = {0, 0, 0, 0, 2, 2, 2, 2};
  const double f[4] = {0.0, 0.3, 1.7, 2.0};
  for (double y : f)
    for (double x : f) square.surface.points.emplace_back(x, y, 0.0);
  square.loops.push_back({{rational_circle_2d({1.0, 1.0}, hole, false)}, false});
  return square;
}

nurbs::LoadedModel loaded_sphere(double radius, double unit_scale_to_mm) {
  nurbs::LoadedModel m;
  nurbs::Body body;
  body.name = "ball";
  body.closed = true;
  nurbs::TrimmedSurface face;
  face.surface = rational_sphere(radius);
  body.faces.push_back(std::move(face));
  m.model.bodies.push_back(std::move(body));
  m.model.unit_scale_to_mm = unit_scale_to_mm;
  m.report = nurbs::model_report(m.model);
  return m;
}

}  // namespace models
