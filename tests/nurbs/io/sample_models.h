#pragma once
// Small exact models shared by the I/O tests: the base of the malformed-IGES corpus and of the
// writer round trips.
#include <cmath>

#include "nurbs/homogeneous.h"
#include "nurbs/io/conic_arcs.h"
#include "nurbs/io/curve_utils.h"
#include "nurbs/model.h"

namespace nurbs::io::test {

// Quarter cylinder of radius 2 around the y axis, rational biquadratic (u: arc, v: straight).
inline Surface quarter_cylinder() {
  Surface s;
  s.degree_u = s.degree_v = 2;
  s.count_u = s.count_v = 3;
  s.knots_u = s.knots_v = {0, 0, 0, 1, 1, 1};
  const double h = std::sqrt(0.5);
  for (int j = 0; j < 3; ++j) {
    const double y = 1.5 * j;
    s.points.insert(s.points.end(), {{2, y, 0}, {2, y, 2}, {0, y, 2}});
    s.weights.insert(s.weights.end(), {1.0, h, 1.0});
  }
  return s;
}

// Bicubic Bézier patch, polynomial, over [0, 1]^2: a gentle bump.
inline Surface bump() {
  Surface s;
  s.degree_u = s.degree_v = 3;
  s.count_u = s.count_v = 4;
  s.knots_u = s.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) s.points.push_back({i, j, (i == 1 || i == 2) && (j == 1 || j == 2) ? 1.0 : 0.0});
  return s;
}

// Outer loop: the parameter square as four lines, counter-clockwise.
inline TrimLoop square_loop(double lo, double hi) {
  TrimLoop l;
  const glm::dvec3 c[4] = {{lo, lo, 0}, {hi, lo, 0}, {hi, hi, 0}, {lo, hi, 0}};
  for (int i = 0; i < 4; ++i) l.curves.push_back(to_2d(line_segment(c[i], c[(i + 1) % 4])));
  return l;
}

// Hole: full circle of radius r around (0.5, 0.5), clockwise when `clockwise`.
inline TrimLoop circle_hole(double r, bool clockwise) {
  TrimLoop l;
  l.outer = false;
  Curve2 c = to_2d(circle_arc({0.5, 0.5}, {0.5 + r, 0.5}, {0.5 + r, 0.5}, 0.0));
  l.curves.push_back(clockwise ? reversed(c) : c);
  return l;
}

// One trimmed rational face (square outer loop + circular hole) and one untrimmed bicubic face.
inline Model small_model() {
  Model m;
  m.source = "small";
  Body b{"faces", {}, glm::dmat4(1.0), ""};
  TrimmedSurface f1;
  f1.surface = quarter_cylinder();
  f1.loops = {square_loop(0.0, 1.0), circle_hole(0.2, true)};
  TrimmedSurface f2;
  f2.surface = bump();
  b.faces = {f1, f2};
  m.bodies.push_back(b);
  return m;
}

}  // namespace nurbs::io::test
