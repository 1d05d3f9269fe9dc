#include "models/paper_surfaces.h"

#include <cmath>
#include <numbers>

#include "models/exact_shapes.h"

namespace models {

std::vector<double> clamped_uniform_knots(int degree, int count) {
  std::vector<double> k;
  const int spans = count - degree;
  for (int i = 0; i <= degree; ++i) k.push_back(0.0);
  for (int i = 1; i < spans; ++i) k.push_back(static_cast<double>(i) / spans);
  for (int i = 0; i <= degree; ++i) k.push_back(1.0);
  return k;
}

nurbs::Surface wavy_surface(int count_u, int count_v, double size_u, double size_v, double amplitude, double wave_x,
                            double wave_y, double phase, double z_offset) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  nurbs::Surface s;
  s.degree_u = s.degree_v = 3;
  s.count_u = count_u;
  s.count_v = count_v;
  s.knots_u = clamped_uniform_knots(3, count_u);
  s.knots_v = clamped_uniform_knots(3, count_v);
  for (int j = 0; j < count_v; ++j) {
    for (int i = 0; i < count_u; ++i) {
      const double x = size_u * i / (count_u - 1), y = size_v * j / (count_v - 1);
      const double z = amplitude * std::sin(two_pi * x / wave_x + phase) * std::cos(two_pi * y / wave_y);
      s.points.emplace_back(x, y, z + z_offset);
    }
  }
  return s;
}

nurbs::Surface wavy_surface_199x33() { return wavy_surface(199, 33, 200.0, 40.0, 5.0, 50.0, 40.0, 0.0, 0.0); }

nurbs::Surface wavy_surface_100x105() {
  // cos = sin with a quarter-wave phase.
  return wavy_surface(100, 105, 100.0, 100.0, 4.0, 40.0, 30.0, std::numbers::pi / 2, 20.0);
}

nurbs::Curve2 trim_line(glm::dvec2 a, glm::dvec2 b) {
  nurbs::Curve2 c;
  c.degree = 1;
  c.knots = {0, 0, 1, 1};
  c.points = {a, b};
  return c;
}

nurbs::TrimmedSurface trimmed_wavy_surface_100x105() {
  nurbs::TrimmedSurface t;
  t.surface = wavy_surface_100x105();
  t.face_id = 1;
  t.name = "wavy_100x105_trimmed";
  const glm::dvec2 a(0.05, 0.05), b(0.95, 0.05), c(0.95, 0.95), d(0.05, 0.95);
  t.loops.push_back({{trim_line(a, b), trim_line(b, c), trim_line(c, d), trim_line(d, a)}, true});
  t.loops.push_back({{rational_circle_2d({0.3, 0.3}, 0.12, false)}, false});
  t.loops.push_back({{rational_circle_2d({0.7, 0.65}, 0.1, false)}, false});
  // A closed clamped cubic (first point = last point) tracing a rounded blob clockwise.
  nurbs::Curve2 blob;
  blob.degree = 3;
  blob.points = {{0.38, 0.72}, {0.38, 0.64}, {0.22, 0.64}, {0.20, 0.72}, {0.22, 0.80}, {0.38, 0.80}, {0.38, 0.72}};
  blob.knots = clamped_uniform_knots(3, static_cast<int>(blob.points.size()));
  t.loops.push_back({{blob}, false});
  return t;
}

}  // namespace models
