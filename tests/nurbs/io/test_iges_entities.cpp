// Entities beyond what the writer emits: 124 chains, 100/104/110 arcs and lines in parameter
// space, 141/143 bounded surfaces, the 186/514/510/508/504/502 B-rep chain, skipped and
// unsupported types. Files are built by appending entities to a written one-surface file.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "iges_edit.h"
#include "nurbs/curve_eval.h"
#include "nurbs/io/conic_arcs.h"
#include "nurbs/io/curve_utils.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "sample_models.h"

using nurbs::io::test::IgesEdit;
using nurbs::io::test::s;

namespace {

// A file with one bare bicubic 128 (D1) over [0, 1]^2.
IgesEdit one_surface() {
  nurbs::Model m;
  m.bodies.push_back({"b", {}, glm::dmat4(1.0), ""});
  nurbs::TrimmedSurface f;
  f.surface = nurbs::io::test::bump();
  m.bodies[0].faces.push_back(f);
  return IgesEdit::parse(nurbs::io::write_iges_text(m));
}

// Maximum of |F(x, y)| of a conic over points sampled on the curve.
double conic_residual(const nurbs::Curve3& c, const std::array<double, 6>& k) {
  const nurbs::Curve2 c2 = nurbs::io::to_2d(c);
  double worst = 0.0;
  for (int i = 0; i <= 64; ++i) {
    const double t = c.knots.front() + (c.knots.back() - c.knots.front()) * i / 64.0;
    const glm::dvec2 p = nurbs::curve_point(c2, t);
    worst = std::max(worst,
                     std::abs(k[0] * p.x * p.x + k[1] * p.x * p.y + k[2] * p.y * p.y + k[3] * p.x + k[4] * p.y + k[5]));
  }
  return worst;
}

}  // namespace

TEST_CASE("conic arcs are exact rational quadratics") {
  struct Row {
    const char* name;
    std::array<double, 6> coef;  // A..F
    glm::dvec2 start, end;
    int form;
  };
  const Row rows[] = {
      {"unit circle as ellipse, 3/4 turn", {1, 0, 1, 0, 0, -1}, {1, 0}, {0, -1}, 1},
      {"rotated ellipse, full", {2, 1, 1, 0, 0, -1}, {1.0 / std::sqrt(2.0), 0}, {1.0 / std::sqrt(2.0), 0}, 1},
      {"hyperbola xy = 1", {0, 1, 0, 0, 0, -1}, {0.5, 2}, {4, 0.25}, 2},
      {"parabola y = x^2", {1, 0, 0, 0, -1, 0}, {-1, 1}, {2, 4}, 3},
  };
  for (const Row& r : rows) {
    CAPTURE(std::string(r.name));
    const nurbs::Curve3 c = nurbs::io::conic_arc(r.coef, r.start, r.end, 0.0, r.form);
    CHECK(glm::length(c.points.front() - glm::dvec3(r.start, 0.0)) < 1e-15);  // cos/sin of the start angle
    // Round-off of a few operations on O(1..16) values: 1e-12.
    CHECK(conic_residual(c, r.coef) < 1e-12);
  }
  // Circle (IGES 100): every point at the radius, quarter arcs exactly 90°.
  const nurbs::Curve3 arc = nurbs::io::circle_arc({1, 2}, {4, 2}, {1, 5}, 0.0);
  CHECK(arc.points.size() == 3);
  CHECK(conic_residual(arc, {1, 0, 1, -2, -4, 1 + 4 - 9}) < 1e-12);  // (x-1)² + (y-2)² = 9
}

TEST_CASE("IGES: chained 124 transforms act on the surface") {
  IgesEdit e = one_surface();
  const int inner =
      e.append(124, {"0.", "-1.", "0.", "1.", "1.", "0.", "0.", "0.", "0.", "0.", "1.", "0."});  // +90° about z, +1 x
  const int outer = e.append(124, {"1.", "0.", "0.", "0.", "0.", "1.", "0.", "0.", "0.", "0.", "1.", "10."});  // +10 z
  e.set_de_field(1, 7, inner);
  e.set_de_field(inner, 7, outer);
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "xf.igs");
  const auto& p = m.bodies.at(0).faces.at(0).surface.points;
  // Point (1, 0, 0) -> rotate (0, 1, 0) -> +1 x (1, 1, 0) -> +10 z (1, 1, 10); exact in doubles.
  CHECK(p[1] == glm::dvec3(1.0, 1.0, 10.0));
}

TEST_CASE("IGES: subfigure instances (408) place copies of their definition (308)") {
  IgesEdit e = one_surface();
  const int def = e.append(308, {"0", "4Hpart", "1", "1"});
  e.append(408, {std::to_string(def), "10.", "0.", "0.", "1."});  // moved
  const int twice = e.append(408, {std::to_string(def), "0.", "0.", "5.", "2."});  // scaled by 2, then moved
  const int up = e.append(124, {"1.", "0.", "0.", "0.", "0.", "1.", "0.", "0.", "0.", "0.", "1.", "100."});
  e.set_de_field(twice, 7, up);  // the instance's own matrix acts last
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "sub.igs", {}, &log);
  CHECK(m.faces_in_file == 2);  // as placed: the definition's face is not one of its own
  REQUIRE(m.bodies.size() == 2);
  CHECK(m.skipped_entities.empty());
  const glm::dvec3 q = nurbs::io::test::bump().points[1];
  CHECK(m.bodies[0].faces.at(0).surface.points[1] == q + glm::dvec3(10, 0, 0));
  CHECK(m.bodies[1].faces.at(0).surface.points[1] == 2.0 * q + glm::dvec3(0, 0, 105));
  CHECK(m.bodies[0].name == "part D" + std::to_string(def + 2) + "/faces");
  // A definition that holds an instance of itself is refused, naming the instance.
  IgesEdit loop = one_surface();
  const int self = loop.append(308, {"1", "4Hloop", "2", "1", "5"});
  loop.append(408, {std::to_string(self), "0.", "0.", "0.", "1."});
  loop.set_de_field(5, 9, 10000);  // the inner instance: physically dependent, placed by the definition
  CHECK_THROWS_WITH(nurbs::io::read_iges_text(loop.text(), "loop.igs"), doctest::Contains("nest deeper than 16"));
}

TEST_CASE("IGES: 143 with arcs and lines, B-rep solid, skipped and unsupported types") {
  IgesEdit e = one_surface();
  auto line = [&](double x0, double y0, double x1, double y1) {
    return e.append(110, {std::to_string(x0), std::to_string(y0), "0.", std::to_string(x1), std::to_string(y1), "0."});
  };
  const int l1 = line(0, 0, 1, 0), l2 = line(1, 0, 1, 1), l3 = line(1, 1, 0, 1), l4 = line(0, 1, 0, 0);
  const int square = e.append(102, {"4", s(l1), s(l2), s(l3), s(l4)});
  const int circle = e.append(100, {"0.", "0.5", "0.5", "0.7", "0.5", "0.7", "0.5"});  // CCW: must be reversed
  const int ellipse = e.append(104, {"4.", "0.", "1.", "0.", "0.", "-0.04", "0.", "0.1", "0.", "0.1", "0."}, 1);
  const int b_out = e.append(141, {"1", "1", "1", "1", "0", "1", "1", s(square)});
  const int b_in = e.append(141, {"1", "1", "1", "1", "0", "2", "1", s(circle)});  // SENSE 2: reversed
  e.append(143, {"1", "1", "2", s(b_out), s(b_in)});
  // B-rep: vertex list, edge list, loop of the four lines, face, shell, solid.
  const int vl = e.append(502, {"1", "0.", "0.", "0."}, 1);
  const int el = e.append(504, {"1", s(l1), s(vl), "1", s(vl), "1"}, 1);
  std::vector<std::string> lp{"4"};
  for (int l : {l1, l2, l3, l4}) lp.insert(lp.end(), {"0", s(el), "1", "1", "1", "0", s(l)});
  const int loop = e.append(508, lp, 1);
  const int loop_e = e.append(508, {"1", "0", s(el), "1", "1", "1", "0", s(ellipse)}, 1);
  const int face = e.append(510, {"1", "2", "1", s(loop), s(loop_e)}, 1);
  const int shell = e.append(514, {"1", s(face), "1"}, 1);
  e.append(186, {s(shell), "1", "0"});
  e.append(116, {"0.", "0.", "0.", "0"});          // point: skipped and counted
  e.append(406, {"1", "4HNAME"}, 15);              // property: ignored
  const int rev = e.append(118, {"1", "1", "0"});  // ruled surface: unsupported
  e.append(144, {s(rev), "0", "0", "0"});

  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "brep.igs", {}, &log);
  CHECK(m.skipped_entities == std::map<int, int>{{116, 1}, {118, 1}});
  REQUIRE(log.warnings.size() == 1);
  CHECK(log.warnings[0].find("needs D" + s(rev) + " of unsupported type 118") != std::string::npos);
  REQUIRE(m.bodies.size() == 2);  // the solid, then loose faces (the 143); the 128 is used by both
  CHECK(m.bodies[0].name == "solid D" + s(e.find(186)));
  CHECK(m.bodies[0].closed);  // a 186 states a solid; loose faces do not
  CHECK_FALSE(m.bodies[1].closed);
  REQUIRE(m.bodies[0].faces.size() == 1);
  REQUIRE(m.bodies[1].faces.size() == 1);
  const auto& solid_face = m.bodies[0].faces[0];
  REQUIRE(solid_face.loops.size() == 2);
  CHECK(solid_face.loops[0].curves.size() == 4);
  CHECK_FALSE(solid_face.loops[1].outer);
  const auto& bounded = m.bodies[1].faces[0];
  REQUIRE(bounded.loops.size() == 2);
  CHECK(bounded.loops[0].outer);
  REQUIRE(bounded.loops[1].curves.size() == 1);
  CHECK(bounded.loops[1].curves[0].points.size() == 9);  // full circle: four 90° segments
  // SENSE 2 made the CCW circle clockwise already, so nothing was reoriented, except the
  // ellipse (CCW from the file) that is an inner loop of the 510.
  CHECK(log.reoriented_loops == 1);
  // The circle is centred at (0.5, 0.5) with radius 0.2 in (u, v); round-off 1e-12.
  const nurbs::Curve2& q = bounded.loops[1].curves[0];
  CHECK(std::abs(glm::length(nurbs::curve_point(q, 0.5 * (q.knots.front() + q.knots.back())) - glm::dvec2(0.5)) - 0.2) <
        1e-12);

  // The same solid as the one entity of a subfigure definition placed twice: two solids of one
  // face each, and its shell and face are not read a third time where the definition holds them.
  const int solid = e.find(186);
  e.set_de_field(solid, 9, 10000);  // physically dependent: the definition places it
  const int def = e.append(308, {"0", "5Hsolid", "1", s(solid)});
  e.append(408, {s(def), "0.", "0.", "0.", "1."});
  e.append(408, {s(def), "0.", "0.", "10.", "1."});
  const nurbs::Model placed = nurbs::io::read_iges_text(e.text(), "placed.igs");
  REQUIRE(placed.bodies.size() == 3);  // the two placed solids, then the loose faces (the 143)
  CHECK(placed.faces_in_file == 4);    // the 510 twice, the 143, the 144 on the 118 (dropped)
  CHECK(placed.bodies[0].closed);
  CHECK(placed.bodies[1].closed);
  REQUIRE(placed.bodies[1].faces.size() == 1);
  CHECK(placed.bodies[1].faces[0].surface.points[0].z == doctest::Approx(placed.bodies[0].faces[0].surface.points[0].z + 10));
  CHECK(placed.bodies[2].faces.size() == 1);
}
