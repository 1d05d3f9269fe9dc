// STEP (Part 21) parser and B-rep reader: syntax, units, faces on planes and cylinders with their
// edges brought into (u, v), hostile input, damaged records the geometry does not reach, derived
// attributes (*), edges off their surface, what counts as skipped geometry, and the shared STEP
// files against their IGES twins.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <tuple>

#include "../../shared_models.h"
#include "nurbs/curve_eval.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/read_model.h"
#include "nurbs/io/step_file.h"
#include "nurbs/io/step_reader.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace {

using nurbs::io::ReadError;

std::string step_file(const std::string& data) {
  return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('test'),'2;1');\nFILE_NAME('t','',(''),(''),'','','');\n"
         "FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n" +
         data + "ENDSEC;\nEND-ISO-10303-21;\n";
}

// Units of a representation context: length `length` (an SI_UNIT or conversion-based unit), radians.
std::string context(const std::string& length) {
  return "#900=( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904)) "
         "GLOBAL_UNIT_ASSIGNED_CONTEXT((#901,#902,#903)) REPRESENTATION_CONTEXT('','') );\n" +
         length +
         "#902=( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );\n"
         "#903=( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() );\n"
         "#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-05),#901,'distance_accuracy_value','');\n";
}

const std::string kMillimetre = "#901=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n";

// The context and a frame #4 at the origin (#1, axes #2 = z, #3 = x) with the surface #5 on it.
std::string at_origin(const std::string& surface) {
  return context(kMillimetre) +
         "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',(1.,0.,0.));\n"
         "#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n#5=" +
         surface + ";\n";
}

// A square face of side 2 on the plane z = 1: four LINE edges, in a surface model. `placement`: the
// plane's AXIS2_PLACEMENT_3D #4 with its point #1 and directions #2, #3; `on_x`: the square on the
// plane x = 1 instead, (x, y, 1) written as (1, x, y).
const std::string kPlaneZ =
    "#1=CARTESIAN_POINT('',(0.,0.,1.));\n#2=DIRECTION('',(0.,0.,1.));\n"
    "#3=DIRECTION('',(1.,0.,0.));\n#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n";
std::string square_face(const std::string& length, const std::string& placement = kPlaneZ, bool on_x = false) {
  std::string d = context(length);
  d += placement + "#5=PLANE('',#4);\n";
  const auto xyz = [&](double x, double y, double z) {
    return on_x ? fmt::format("({},{},{})", z, x, y) : fmt::format("({},{},{})", x, y, z);
  };
  const double xy[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  for (int i = 0; i < 4; ++i)
    d += fmt::format("#{}=CARTESIAN_POINT('',{});\n#{}=VERTEX_POINT('',#{});\n", 10 + i, xyz(xy[i][0], xy[i][1], 1.0),
                     20 + i, 10 + i);
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    d += fmt::format("#{}=DIRECTION('',{});\n#{}=VECTOR('',#{},1.);\n#{}=LINE('',#{},#{});\n", 30 + i,
                     xyz(xy[j][0] - xy[i][0], xy[j][1] - xy[i][1], 0.0), 40 + i, 30 + i, 50 + i, 10 + i, 40 + i);
    d += fmt::format("#{}=EDGE_CURVE('',#{},#{},#{},.T.);\n#{}=ORIENTED_EDGE('',*,*,#{},.T.);\n", 60 + i, 20 + i,
                     20 + j, 50 + i, 70 + i, 60 + i);
  }
  d += "#80=EDGE_LOOP('',(#70,#71,#72,#73));\n#81=FACE_OUTER_BOUND('',#80,.T.);\n"
       "#82=ADVANCED_FACE('square',(#81),#5,.T.);\n#83=OPEN_SHELL('',(#82));\n"
       "#84=SHELL_BASED_SURFACE_MODEL('',(#83));\n"
       "#85=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#84),#900);\n";
  return step_file(d);
}

// The lateral face of a cylinder of radius 1 and height 3 about z: two full circles and a seam LINE
// used in both directions, as CAD writers give closed faces.
std::string cylinder_face() {
  std::string d = at_origin("CYLINDRICAL_SURFACE('',#4,1.)");
  d += "#6=CARTESIAN_POINT('',(0.,0.,3.));\n#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);\n"
       "#10=CARTESIAN_POINT('',(1.,0.,0.));\n#11=VERTEX_POINT('',#10);\n"
       "#12=CARTESIAN_POINT('',(1.,0.,3.));\n#13=VERTEX_POINT('',#12);\n"
       "#20=CIRCLE('',#4,1.);\n#21=CIRCLE('',#7,1.);\n#22=VECTOR('',#2,1.);\n#23=LINE('',#10,#22);\n"
       "#30=EDGE_CURVE('',#11,#11,#20,.T.);\n#31=EDGE_CURVE('',#13,#13,#21,.T.);\n"
       "#32=EDGE_CURVE('',#11,#13,#23,.T.);\n"
       "#40=ORIENTED_EDGE('',*,*,#30,.T.);\n#41=ORIENTED_EDGE('',*,*,#32,.T.);\n"
       "#42=ORIENTED_EDGE('',*,*,#31,.F.);\n#43=ORIENTED_EDGE('',*,*,#32,.F.);\n"
       "#50=EDGE_LOOP('',(#40,#41,#42,#43));\n#51=FACE_BOUND('',#50,.T.);\n"
       "#52=ADVANCED_FACE('',(#51),#5,.T.);\n#53=OPEN_SHELL('',(#52));\n#54=SHELL_BASED_SURFACE_MODEL('',(#53));\n"
       "#55=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#54),#900);\n";
  return step_file(d);
}

const nurbs::TrimmedSurface& only_face(const nurbs::Model& m) {
  REQUIRE(m.bodies.size() == 1);
  REQUIRE(m.bodies.front().faces.size() == 1);
  return m.bodies.front().faces.front();
}

// Lowest and highest z of the face's material points, by the winding rule on a 64 x 64 grid of its
// parameter box ({2, -2} when none is material).
std::pair<double, double> material_z_range(const nurbs::TrimmedSurface& f) {
  const nurbs::Interval u = nurbs::surface_domain_u(f.surface), v = nurbs::surface_domain_v(f.surface);
  double lowest = 2.0, highest = -2.0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const glm::dvec2 uv(u.min + u.width() * (i + 0.5) / 64, v.min + v.width() * (j + 0.5) / 64);
      if (!nurbs::is_material(f, uv, 1e-9)) continue;
      const double z = nurbs::surface_point(f.surface, uv.x, uv.y).z;
      lowest = std::min(lowest, z), highest = std::max(highest, z);
    }
  return {lowest, highest};
}

// Material share of a face's parameter box, by the winding rule on a grid of sample points.
double material_share(const nurbs::TrimmedSurface& f) {
  const nurbs::Interval u = nurbs::surface_domain_u(f.surface), v = nurbs::surface_domain_v(f.surface);
  const double tol = 1e-6 * std::max(u.width(), v.width());
  int in = 0, n = 0;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j, ++n)
      in += nurbs::is_material(f, {u.min + u.width() * (i + 0.5) / 100, v.min + v.width() * (j + 0.5) / 100}, tol) ? 1
                                                                                                                   : 0;
  return static_cast<double>(in) / n;
}

// Points of a 64 x 64 grid of the face's patch where the trim's classification differs from
// `expected` (material or not by the point's position; nullopt: too near an edge to say), and how
// many were expected to be material.
struct GridAgreement {
  int wrong = 0, material = 0;
};
GridAgreement grid_agreement(const nurbs::TrimmedSurface& f,
                             const std::function<std::optional<bool>(glm::dvec3)>& expected) {
  const nurbs::Interval u = nurbs::surface_domain_u(f.surface), v = nurbs::surface_domain_v(f.surface);
  GridAgreement out;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const glm::dvec2 uv(u.min + u.width() * (i + 0.5) / 64, v.min + v.width() * (j + 0.5) / 64);
      const std::optional<bool> e = expected(nurbs::surface_point(f.surface, uv.x, uv.y));
      if (!e) continue;
      out.wrong += nurbs::is_material(f, uv, 1e-9) != *e;
      out.material += *e;
    }
  return out;
}

// `d` (entities up to #29, the face's surface #5) completed by a loop of the three oriented edges
// `edges` started at edges[start], its face and a surface model, then read.
nurbs::Model read_three_edge_face(std::string d, const std::array<std::string, 3>& edges, int start) {
  d += fmt::format("#30=EDGE_LOOP('',({},{},{}));\n", edges[start], edges[(start + 1) % 3], edges[(start + 2) % 3]);
  d += "#31=FACE_OUTER_BOUND('',#30,.T.);\n#32=ADVANCED_FACE('',(#31),#5,.T.);\n#33=OPEN_SHELL('',(#32));\n"
       "#34=SHELL_BASED_SURFACE_MODEL('',(#33));\n#35=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#34),#900);\n";
  return nurbs::io::read_step_text(step_file(d), "face.stp");
}

// `d` (entities up to #11: the face's surface #5 and its one edge #11) completed by the loop of
// that edge used `edge_sense`, its face of `face_sense` and a surface model, then read.
nurbs::Model read_one_edge_face(std::string d, const std::string& edge_sense, const std::string& face_sense) {
  d += fmt::format("#12=ORIENTED_EDGE('',*,*,#11,{});\n#13=EDGE_LOOP('',(#12));\n", edge_sense);
  d += fmt::format("#14=FACE_OUTER_BOUND('',#13,.T.);\n#15=ADVANCED_FACE('',(#14),#5,{});\n", face_sense);
  d += "#16=OPEN_SHELL('',(#15));\n#17=SHELL_BASED_SURFACE_MODEL('',(#16));\n"
       "#18=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#17),#900);\n";
  return nurbs::io::read_step_text(step_file(d), "face.stp");
}

}  // namespace

TEST_CASE("STEP parser: simple and complex instances, strings, comments, typed and omitted values") {
  const nurbs::io::StepFile f =
      nurbs::io::parse_step_file(step_file("/* a comment */ #1 = PRODUCT('it''s', 'name', '', (#2)) ;\n"
                                           "#2=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n"
                                           "#3=MEASURE(LENGTH_MEASURE(25.4),$,-1.5E+2,2.);\n"),
                                 "mem.stp");
  REQUIRE(f.entities.size() == 3);
  CHECK(f.schemas == std::vector<std::string>{"AUTOMOTIVE_DESIGN"});
  const nurbs::io::StepEntity& p = *f.find(1);
  CHECK(p.type_name() == "PRODUCT");
  CHECK(p.records.front().params[0].text == "it's");
  CHECK(p.records.front().params[3].items.front().ref == 2);
  const nurbs::io::StepEntity& u = *f.find(2);
  CHECK(u.type_name() == "(LENGTH_UNIT NAMED_UNIT SI_UNIT)");
  REQUIRE(u.record("SI_UNIT"));
  CHECK(u.record("SI_UNIT")->params[0].text == "MILLI");
  const auto& m = f.find(3)->records.front().params;
  CHECK(m[0].kind == nurbs::io::StepValue::Kind::Typed);
  CHECK(m[0].items.front().number == doctest::Approx(25.4));
  CHECK(m[1].kind == nurbs::io::StepValue::Kind::Null);
  CHECK(m[2].number == doctest::Approx(-150.0));
  CHECK(m[3].number == doctest::Approx(2.0));
}

TEST_CASE("STEP parser: malformed text is refused naming the line") {
  auto message = [](const std::string& data) {
    try {
      (void)nurbs::io::parse_step_file(step_file(data), "bad.stp");
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message("#1=PRODUCT('open string);\n").find("bad.stp: line 8") != std::string::npos);
  CHECK(message("#1=PRODUCT('a');\n#1=PRODUCT('b');\n").find("#1 is defined twice") != std::string::npos);
  CHECK(message("#1=PRODUCT('a')\n").find("expected ';'") != std::string::npos);
  CHECK(message("#1=PRODUCT(" + std::string(200, '(') + std::string(200, ')') + ");\n").find("nested deeper") !=
        std::string::npos);
  CHECK(message("#1=PRODUCT(\x01);\n").find("\\x01") != std::string::npos);
  CHECK_THROWS_AS((void)nurbs::io::parse_step_file("ISO-10303-21;\nDATA;\n#1=A();\n", "cut.stp"), ReadError);
  CHECK_THROWS_AS((void)nurbs::io::parse_step_file("not step", "x.stp"), ReadError);
}

TEST_CASE("STEP reader: a plane face, its edges mapped exactly, and length units") {
  const nurbs::Model mm = nurbs::io::read_step_text(square_face(kMillimetre), "square.stp");
  const nurbs::TrimmedSurface& f = only_face(mm);
  CHECK(mm.unit_scale_to_mm == 1.0);
  CHECK(mm.resolution == doctest::Approx(1e-5));
  CHECK(f.name == "square");
  CHECK_FALSE(f.reversed);
  REQUIRE(f.loops.size() == 1);
  CHECK(f.loops.front().outer);
  CHECK(f.loops.front().curves.size() == 4);
  // The plane patch is the square's box grown by 1 % each way: the square is 1 / 1.02^2 of it; the
  // patch lies on z = 1.
  CHECK(material_share(f) == doctest::Approx(1.0 / (1.02 * 1.02)).epsilon(0.01));
  const glm::dvec3 corner =
      nurbs::surface_point(f.surface, nurbs::surface_domain_u(f.surface).max, nurbs::surface_domain_v(f.surface).max);
  CHECK(corner.x == doctest::Approx(2.02));
  CHECK(corner.y == doctest::Approx(2.02));
  CHECK(corner.z == doctest::Approx(1.0));
  // Edges are numbered model-wide, one number per EDGE_CURVE.
  std::set<int> edges;
  for (const nurbs::Curve2& c : f.loops.front().curves) edges.insert(c.edge);
  CHECK(edges.size() == 4);

  const std::string inch =
      "#901=( CONVERSION_BASED_UNIT('INCH',#905) LENGTH_UNIT() NAMED_UNIT(#906) );\n"
      "#905=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#907);\n"
      "#906=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n"
      "#907=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n";
  CHECK(nurbs::io::read_step_text(square_face(inch), "inch.stp").unit_scale_to_mm == doctest::Approx(25.4));
  const std::string metre = "#901=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) );\n";
  CHECK(nurbs::io::read_step_text(square_face(metre), "m.stp").unit_scale_to_mm == doctest::Approx(1000.0));
}

TEST_CASE("STEP reader: a placement without a usable reference direction takes ISO 10303-42's default") {
  // Axis -x without a reference direction: the default first axis is (0, 1, 0) (the standard's
  // (1, 0, 0) is parallel to it).
  const std::string minus_x =
      "#1=CARTESIAN_POINT('',(1.,0.,0.));\n#2=DIRECTION('',(-1.,0.,0.));\n"
      "#4=AXIS2_PLACEMENT_3D('',#1,#2,$);\n";
  const nurbs::Model a = nurbs::io::read_step_text(square_face(kMillimetre, minus_x, true), "minus_x.stp");
  CHECK(a.read_warnings.empty());
  CHECK(material_share(only_face(a)) == doctest::Approx(1.0 / (1.02 * 1.02)).epsilon(0.01));
  // A reference direction along the axis leaves the frame undefined: the default, with a warning
  // naming the line of the placement.
  std::string along = kPlaneZ;
  along.replace(along.find("(1.,0.,0.)"), 10, "(0.,0.,2.)");
  const nurbs::Model b = nurbs::io::read_step_text(square_face(kMillimetre, along), "along.stp");
  REQUIRE(b.read_warnings.size() == 1);
  CHECK(b.read_warnings[0].find("#4 (AXIS2_PLACEMENT_3D): its reference direction is parallel to its axis") !=
        std::string::npos);
  CHECK(b.read_warnings[0].rfind("line ", 0) == 0);
  CHECK(material_share(only_face(b)) == doctest::Approx(1.0 / (1.02 * 1.02)).epsilon(0.01));
}

TEST_CASE("STEP reader: a cylinder's lateral face over its seam is one full turn, on the cylinder") {
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_step_text(cylinder_face(), "cyl.stp", &log);
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(log.trim_problems.empty());
  REQUIRE(f.loops.size() == 1);
  // The loop bounds the whole turn and the heights 0..3: the NURBS is the cylinder (radius 1) all
  // round, 1 % higher and lower than the face (a margin for edges bulging between samples), and
  // its material is the 3 / 3.06 of the parameter rectangle between the circles.
  CHECK(material_share(f) == doctest::Approx(3.0 / 3.06).epsilon(0.01));
  const nurbs::Interval u = nurbs::surface_domain_u(f.surface), v = nurbs::surface_domain_v(f.surface);
  double worst = 0.0, zmin = 1e9, zmax = -1e9;
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 4; ++j) {
      const glm::dvec3 p = nurbs::surface_point(f.surface, u.min + u.width() * i / 16, v.min + v.width() * j / 4);
      worst = std::max(worst, std::abs(std::hypot(p.x, p.y) - 1.0));
      zmin = std::min(zmin, p.z), zmax = std::max(zmax, p.z);
    }
  CHECK(worst < 1e-12);
  CHECK(zmin == doctest::Approx(-0.03));
  CHECK(zmax == doctest::Approx(3.03));
  // The seam edge is used twice, once on each side of the parameter rectangle.
  std::map<int, int> uses;
  for (const nurbs::Curve2& c : f.loops.front().curves) ++uses[c.edge];
  CHECK(uses.size() == 3);
}

TEST_CASE("STEP reader: a spherical cap bounded by one circle reaches its pole") {
  // Sphere of radius 1 about the origin; the face's one edge is the circle at z = 0.5, counter-
  // clockwise seen from +z: the face is the cap above it (area pi), which no edge reaches.
  const nurbs::Model m = read_one_edge_face(
      at_origin("SPHERICAL_SURFACE('',#4,1.)") +
          "#6=CARTESIAN_POINT('',(0.,0.,0.5));\n#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);\n"
          "#8=CIRCLE('',#7,0.8660254037844386);\n#9=CARTESIAN_POINT('',(0.8660254037844386,0.,0.5));\n"
          "#10=VERTEX_POINT('',#9);\n#11=EDGE_CURVE('',#10,#10,#8,.T.);\n",
      ".T.", ".T.");
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(f.trim_problem.empty());
  // Material points all on the cap, and some within 0.01 of the pole.
  const auto [lowest, highest] = material_z_range(f);
  CHECK(lowest > 0.5 - 1e-9);
  CHECK(highest > 0.99);
}

TEST_CASE("STEP reader: a sphere octant whose meridians meet at a pole reaches the pole, on the patch") {
  // The rounded corner of a box (KiCad's and FreeCAD's chip bodies): an eighth of the unit sphere
  // bounded by three quarter circles, two of them meridians meeting at a pole, where the angle is
  // undefined. Every octant, each loop started at each of its three vertices (one of them the pole).
  for (const int sx : {1, -1})
    for (const int sy : {1, -1})
      for (const int sz : {1, -1})
        for (int start = 0; start < 3; ++start) {
          CAPTURE(sx);
          CAPTURE(sy);
          CAPTURE(sz);
          CAPTURE(start);
          const glm::dvec3 a(sx, 0, 0), b(0, sy, 0), c(0, 0, sz);
          // Counter-clockwise seen from outside: a, b, c when (b - a) x (c - a) points outwards.
          std::vector<glm::dvec3> v = sx * sy * sz > 0 ? std::vector{a, b, c} : std::vector{a, c, b};
          std::rotate(v.begin(), v.begin() + start, v.end());
          std::string d = at_origin("SPHERICAL_SURFACE('',#4,1.)");
          auto vec = [](glm::dvec3 q) { return fmt::format("({},{},{})", q.x, q.y, q.z); };
          for (int i = 0; i < 3; ++i)
            d += fmt::format("#{}=CARTESIAN_POINT('',{});\n#{}=VERTEX_POINT('',#{});\n", 10 + 2 * i, vec(v[i]),
                             11 + 2 * i, 10 + 2 * i);
          std::string edges;
          for (int i = 0; i < 3; ++i) {
            // The arc from v[i] to v[i + 1]: a circle about the centre with axis v[i] x v[i + 1] and
            // reference direction v[i], so that it runs from v[i] towards v[i + 1].
            const int j = (i + 1) % 3, id = 20 + 10 * i;
            d += fmt::format("#{}=DIRECTION('',{});\n#{}=DIRECTION('',{});\n#{}=AXIS2_PLACEMENT_3D('',#1,#{},#{});\n",
                             id, vec(glm::cross(v[i], v[j])), id + 1, vec(v[i]), id + 2, id, id + 1);
            d += fmt::format(
                "#{}=CIRCLE('',#{},1.);\n#{}=EDGE_CURVE('',#{},#{},#{},.T.);\n#{}=ORIENTED_EDGE('',*,*,#{},.T.);\n",
                id + 3, id + 2, id + 4, 11 + 2 * i, 11 + 2 * j, id + 3, id + 5, id + 4);
            edges += fmt::format("{}#{}", i ? "," : "", id + 5);
          }
          d += "#60=EDGE_LOOP('',(" + edges +
               "));\n#61=FACE_OUTER_BOUND('',#60,.T.);\n"
               "#62=ADVANCED_FACE('corner',(#61),#5,.T.);\n#63=OPEN_SHELL('',(#62));\n"
               "#64=SHELL_BASED_SURFACE_MODEL('',(#63));\n#65=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#64),#900);\n";
          const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "corner.stp");
          const nurbs::TrimmedSurface& f = only_face(m);
          CHECK(f.trim_problem.empty());
          CHECK(f.edge_gap == 0.0);
          // Material on the octant's side of z = 0 only, from the equator (within the 64 x 64 grid's
          // spacing) up to within 0.01 of the pole.
          const auto [lowest, highest] = material_z_range(f);
          CHECK(sz * lowest >= -1e-9);
          CHECK(sz * highest <= 1.0 + 1e-9);
          CHECK(std::max(sz * lowest, sz * highest) > 0.99);
          CHECK(std::min(sz * lowest, sz * highest) < 0.05);
        }
}

TEST_CASE("STEP reader: a ball whose seam edge runs down to the pole and up again keeps all below its circle") {
  // A BGA ball (KiCad): the unit sphere below the circle z = 0.5, bounded by the circle and by the
  // seam meridian from the pole up to it, used down and up. The sphere's reference direction puts
  // its seam at angle 0 or (turned) at pi; each loop starts at each of its three edges.
  const double r0 = std::sqrt(0.75);
  for (const char* ref : {"(1.,0.,0.)", "(-1.,0.,0.)"})
    for (int start = 0; start < 3; ++start) {
      CAPTURE(ref);
      CAPTURE(start);
      std::string d = context(kMillimetre);
      d += fmt::format(
          "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',{});\n"
          "#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n#5=SPHERICAL_SURFACE('',#4,1.);\n"
          "#6=DIRECTION('',(1.,0.,0.));\n#7=CARTESIAN_POINT('',(0.,0.,0.5));\n#8=AXIS2_PLACEMENT_3D('',#7,#2,#6);\n"
          "#9=CIRCLE('',#8,{});\n#10=CARTESIAN_POINT('',({},0.,0.5));\n#11=VERTEX_POINT('',#10);\n"
          "#12=EDGE_CURVE('',#11,#11,#9,.T.);\n#13=CARTESIAN_POINT('',(0.,0.,-1.));\n#14=VERTEX_POINT('',#13);\n"
          "#15=DIRECTION('',(0.,-1.,0.));\n#16=AXIS2_PLACEMENT_3D('',#1,#15,#6);\n#17=CIRCLE('',#16,1.);\n"
          "#18=EDGE_CURVE('',#14,#11,#17,.T.);\n#20=ORIENTED_EDGE('',*,*,#12,.F.);\n"
          "#21=ORIENTED_EDGE('',*,*,#18,.F.);\n#22=ORIENTED_EDGE('',*,*,#18,.T.);\n",
          ref, r0, r0);
      const nurbs::Model m = read_three_edge_face(d, {"#20", "#21", "#22"}, start);
      const nurbs::TrimmedSurface& f = only_face(m);
      CHECK(f.trim_problem.empty());
      CHECK(f.edge_gap == 0.0);
      // Every grid point away from the circle is material exactly when it lies below it.
      const GridAgreement g = grid_agreement(f, [](glm::dvec3 q) -> std::optional<bool> {
        if (std::abs(q.z - 0.5) < 0.01) return std::nullopt;
        return q.z < 0.5;
      });
      CHECK(g.wrong == 0);
    }
}

TEST_CASE("STEP reader: a closed shell's seam used twice in a row bounds its face on both sides") {
  // A ball as one face whose loop is its seam, the meridian from pole to pole through (1, 0, 0), run
  // down and back up (as OpenCASCADE writes a sphere): each edge of the shell has two uses, so the
  // solid stays closed, and its face is the whole sphere, its trim valid. The same with the seam
  // through (-1, 0, 0), the sphere's own seam (as Fusion 360 writes it). The same solid with a
  // second meridian used once is open, and says so.
  const std::string solid = "#17=FACE_OUTER_BOUND('',#16,.T.);\n#18=ADVANCED_FACE('',(#17),#5,.T.);\n"
                            "#19=CLOSED_SHELL('',(#18));\n#20=MANIFOLD_SOLID_BREP('ball',#19);\n"
                            "#21=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#20),#900);\n";
  const auto seam_ball = [](const char* axis, const char* ref) {
    return at_origin("SPHERICAL_SURFACE('',#4,1.)") +
           fmt::format("#6=DIRECTION('',{});\n#22=DIRECTION('',{});\n#7=AXIS2_PLACEMENT_3D('',#1,#6,#22);\n",
                       axis, ref) +
           "#8=CIRCLE('',#7,1.);\n#9=CARTESIAN_POINT('',(0.,0.,1.));\n#10=VERTEX_POINT('',#9);\n"
           "#11=CARTESIAN_POINT('',(0.,0.,-1.));\n#12=VERTEX_POINT('',#11);\n#13=EDGE_CURVE('',#10,#12,#8,.T.);\n"
           "#14=ORIENTED_EDGE('',*,*,#13,.T.);\n#15=ORIENTED_EDGE('',*,*,#13,.F.);\n";
  };
  for (const auto& [axis, ref] : {std::pair{"(0.,1.,0.)", "(1.,0.,0.)"}, std::pair{"(0.,-1.,0.)", "(-1.,0.,0.)"}}) {
    const std::string seam_ref = ref;
    CAPTURE(seam_ref);
    const nurbs::Model closed = nurbs::io::read_step_text(
        step_file(seam_ball(axis, ref) + "#16=EDGE_LOOP('',(#14,#15));\n" + solid), "ball.stp");
    REQUIRE(closed.bodies.size() == 1);
    CHECK(closed.bodies[0].closed);
    CHECK(closed.bodies[0].not_closed.empty());
    CHECK(closed.read_warnings.empty());
    const nurbs::TrimmedSurface& f = only_face(closed);
    CHECK(f.trim_problem.empty());
    const GridAgreement g = grid_agreement(f, [](glm::dvec3) -> std::optional<bool> { return true; });
    CHECK(g.wrong == 0);
  }
  const std::string ball = seam_ball("(0.,1.,0.)", "(1.,0.,0.)");
  // A second meridian through (-1, 0, 0), down from the north pole: the loop goes round the ball
  // by two different edges, each used once.
  const std::string other = "#30=DIRECTION('',(-1.,0.,0.));\n#31=AXIS2_PLACEMENT_3D('',#1,#6,#30);\n"
                            "#32=CIRCLE('',#31,1.);\n#33=EDGE_CURVE('',#12,#10,#32,.F.);\n"
                            "#34=ORIENTED_EDGE('',*,*,#33,.T.);\n";
  const nurbs::Model open =
      nurbs::io::read_step_text(step_file(ball + other + "#16=EDGE_LOOP('',(#14,#34));\n" + solid), "ball.stp");
  REQUIRE(open.bodies.size() == 1);
  CHECK_FALSE(open.bodies[0].closed);
  CHECK(open.bodies[0].not_closed == "2 of its edges bound one face only (edge #13 of face #18)");
  // The ball's surface of radius 2 under its seam of radius 1: the edges lie 1 off it, the face is
  // dropped, and the solid, which lost a face, is read as open.
  std::string far = ball;
  far.replace(far.find("SPHERICAL_SURFACE('',#4,1.)"), 27, "SPHERICAL_SURFACE('',#4,2.)");
  const nurbs::Model lost =
      nurbs::io::read_step_text(step_file(far + "#16=EDGE_LOOP('',(#14,#15));\n" + solid), "ball.stp");
  REQUIRE(lost.dropped_faces.size() == 1);
  REQUIRE(lost.bodies.size() == 1);
  CHECK_FALSE(lost.bodies[0].closed);
  CHECK(lost.bodies[0].not_closed == "1 of its faces were dropped");
}

TEST_CASE("STEP reader: a sphere face bounded only by a vertex loop is the whole sphere") {
  std::string d = at_origin("SPHERICAL_SURFACE('',#4,1.)");
  d += "#9=CARTESIAN_POINT('',(0.,0.,1.));\n#10=VERTEX_POINT('',#9);\n#13=VERTEX_LOOP('',#10);\n"
       "#14=FACE_BOUND('',#13,.T.);\n#15=ADVANCED_FACE('ball',(#14),#5,.T.);\n"
       "#16=OPEN_SHELL('',(#15));\n#17=SHELL_BASED_SURFACE_MODEL('',(#16));\n"
       "#18=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#17),#900);\n";
  const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "ball.stp");
  CHECK(m.dropped_faces.empty());
  const nurbs::TrimmedSurface& f = only_face(m);
  const auto [lowest, highest] = material_z_range(f);
  CHECK(lowest < -0.99);
  CHECK(highest > 0.99);
}

TEST_CASE("STEP reader: a surface of revolution whose profile crosses the axis keeps its edges' side") {
  // A domed end: the circle of radius 30 about (-20, 0, 0) in the plane y = 0 swept about the z
  // axis. It crosses the axis, so each circle about it at height z below the top (22.36) lies on
  // the surface twice: swept from the profile's near side (x > 0) and from its far side. The face is
  // the dome above its edge, the circle of radius 2 at z = sqrt(416), which the near side sweeps;
  // the far side reaches radius 2 at z = 24 only. Its edge lies on the face read (no edge gap).
  std::string d = at_origin("SURFACE_OF_REVOLUTION('',#43,#44)");
  d += "#40=CARTESIAN_POINT('',(-20.,0.,0.));\n#41=DIRECTION('',(0.,1.,0.));\n#42=AXIS2_PLACEMENT_3D('',#40,#41,#3);\n"
       "#43=CIRCLE('',#42,30.);\n#44=AXIS1_PLACEMENT('',#1,#2);\n"
       "#6=CARTESIAN_POINT('',(0.,0.,20.396078054371138));\n#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);\n"
       "#8=CIRCLE('',#7,2.);\n#9=CARTESIAN_POINT('',(2.,0.,20.396078054371138));\n#10=VERTEX_POINT('',#9);\n"
       "#11=EDGE_CURVE('',#10,#10,#8,.T.);\n";
  // A ball of radius 0.0125 as a circle swept about an axis through its centre, placed off the
  // origin with a normal 2.5e-5 off x (as FreeCAD writes a chip's rounded corner): both sides sweep
  // every point, and each point keeps the near side's parameters (the far side, equal up to
  // rounding, would throw the loop's points half a turn apart).
  std::string ball = at_origin("SURFACE_OF_REVOLUTION('',#43,#44)");
  ball += "#40=CARTESIAN_POINT('',(1.414072886352,-0.60407288634,1.007499999982));\n"
          "#41=DIRECTION('',(-0.99999999969,2.489943571616E-005,5.528825243E-021));\n"
          "#45=DIRECTION('',(-2.489943571616E-005,-0.99999999969,-2.220446048E-016));\n"
          "#42=AXIS2_PLACEMENT_3D('',#40,#41,#45);\n#43=CIRCLE('',#42,1.250000000054E-002);\n"
          "#46=CARTESIAN_POINT('',(1.414072886352,-0.60407288634,2.007499999978));\n#44=AXIS1_PLACEMENT('',#46,#2);\n"
          "#6=CARTESIAN_POINT('',(1.414072886352,-0.60407288634,1.013749999982));\n"
          "#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);\n"
          "#8=CIRCLE('',#7,0.010825317547);\n#9=CARTESIAN_POINT('',(1.424898203899,-0.60407288634,1.013749999982));\n"
          "#10=VERTEX_POINT('',#9);\n#11=EDGE_CURVE('',#10,#10,#8,.T.);\n";
  for (const std::string& text : {d, ball})
    for (const char* edge_sense : {".T.", ".F."}) {
      CAPTURE(edge_sense);
      const nurbs::Model m = read_one_edge_face(text, edge_sense, ".T.");
      CHECK(m.dropped_faces.empty());
      const nurbs::TrimmedSurface& f = only_face(m);
      CHECK(f.edge_gap < 1e-9);
    }
}

TEST_CASE("STEP reader: a cone face bounded by one circle reaches its apex") {
  // Cone of radius 1 at z = 0 and semi-angle 45 degrees, narrowing towards -z (apex at z = -1),
  // bounded by the circle at z = 0 only, used clockwise seen from +z: the material, left of the
  // loop seen from outside, is the part below the circle, down to the apex and not past it. The
  // same face with its normal turned inwards (same_sense false) has its circle run the other way.
  for (const auto& [edge_sense, same_sense] : {std::pair{".F.", ".T."}, std::pair{".T.", ".F."}}) {
    const std::string face_sense = same_sense;
    CAPTURE(face_sense);
    std::string d = at_origin("CONICAL_SURFACE('',#4,1.,0.7853981633974483)");
    d += "#8=CIRCLE('',#4,1.);\n#9=CARTESIAN_POINT('',(1.,0.,0.));\n#10=VERTEX_POINT('',#9);\n"
         "#11=EDGE_CURVE('',#10,#10,#8,.T.);\n";
    const nurbs::Model m = read_one_edge_face(d, edge_sense, same_sense);
    const nurbs::TrimmedSurface& f = only_face(m);
    CHECK(f.trim_problem.empty());
    const auto [lowest, highest] = material_z_range(f);
    CHECK(lowest < -0.98);
    CHECK(lowest >= -1.0 - 1e-9);
    CHECK(highest <= 1e-9);
  }
}

TEST_CASE("STEP reader: a hemisphere bounded by the meridian circle through its poles keeps its half") {
  // The unit sphere about z; the face's one edge is the great circle in the plane y = 0 from the
  // north pole through -x, the south pole and +x (axis -y, reference +z). Used forwards on a face of
  // the sphere's normal, the material (on the left seen from outside) is the half y < 0; the edge
  // used backwards, or the face's normal turned inwards (same_sense .F., NIST FTC 06), takes the
  // half y > 0; both, y < 0 again. Between the poles either side of the seam could hold the
  // second meridian: only the loop's direction tells.
  for (const auto& [edge_sense, face_sense, below] :
       {std::tuple{".T.", ".T.", true}, std::tuple{".F.", ".T.", false}, std::tuple{".T.", ".F.", false},
        std::tuple{".F.", ".F.", true}}) {
    const std::string senses = fmt::format("edge {}, face {}", edge_sense, face_sense);
    CAPTURE(senses);
    const nurbs::Model m = read_one_edge_face(
        at_origin("SPHERICAL_SURFACE('',#4,1.)") +
            "#6=DIRECTION('',(0.,-1.,0.));\n#7=AXIS2_PLACEMENT_3D('',#1,#6,#2);\n#8=CIRCLE('',#7,1.);\n"
            "#9=CARTESIAN_POINT('',(0.,0.,1.));\n#10=VERTEX_POINT('',#9);\n#11=EDGE_CURVE('',#10,#10,#8,.T.);\n",
        edge_sense, face_sense);
    CHECK(only_face(m).trim_problem.empty());
    const GridAgreement g = grid_agreement(only_face(m), [below](glm::dvec3 q) -> std::optional<bool> {
      if (std::abs(q.y) < 0.01) return std::nullopt;
      return below == (q.y < 0);
    });
    CHECK(g.wrong == 0);
    CHECK(g.material > 100);
  }
}

TEST_CASE("STEP reader: a half cone from its apex, reached along lines from other points, keeps its half") {
  // CATIA's cone sectors (NIST CTC 04): a cone of radius 0 placed at its apex c, axis +z, semi-angle
  // 45 degrees; the face is its half y >= c.y below the circle one unit above the apex, bounded by
  // that half circle and two LINE edges whose points lie `along` away from the apex, so that the
  // apex, evaluated along them, lies 1e-15 to 1e-13 off the axis, where atan2 gives any angle. Each
  // loop starts at each of its edges.
  const double h = 0.7071067811865476;
  for (const glm::dvec3 c : {glm::dvec3(10, 20, 30), glm::dvec3(-95.3, 116.48, -36.81)})
    for (const double along : {0.37, 1.3, 3.7})
      for (int start = 0; start < 3; ++start) {
        CAPTURE(c.x);
        CAPTURE(along);
        CAPTURE(start);
        auto pt = [](glm::dvec3 q) { return fmt::format("CARTESIAN_POINT('',({},{},{}))", q.x, q.y, q.z); };
        std::string d = context(kMillimetre);
        d += "#1=" + pt(c) + ";\n#2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',(1.,0.,0.));\n";
        d += "#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n#5=CONICAL_SURFACE('',#4,0.,0.7853981633974483);\n";
        d += "#6=VERTEX_POINT('',#1);\n#7=" + pt(c + glm::dvec3(1, 0, 1)) + ";\n#8=VERTEX_POINT('',#7);\n";
        d += "#9=" + pt(c + glm::dvec3(-1, 0, 1)) + ";\n#10=VERTEX_POINT('',#9);\n";
        d += "#11=" + pt(c + along * glm::dvec3(h, 0, h)) + ";\n";
        d += fmt::format("#12=DIRECTION('',({},0.,{}));\n", h, h);
        d += "#13=VECTOR('',#12,1.);\n#14=LINE('',#11,#13);\n#15=EDGE_CURVE('',#6,#8,#14,.T.);\n";
        d += "#16=" + pt(c + along * glm::dvec3(-h, 0, h)) + ";\n";
        d += fmt::format("#17=DIRECTION('',({},0.,{}));\n", h, -h);
        d += "#18=VECTOR('',#17,1.);\n#19=LINE('',#16,#18);\n#20=EDGE_CURVE('',#10,#6,#19,.T.);\n";
        d +=
            "#21=" + pt(c + glm::dvec3(0, 0, 1)) + ";\n#22=AXIS2_PLACEMENT_3D('',#21,#2,#3);\n#23=CIRCLE('',#22,1.);\n";
        d += "#24=EDGE_CURVE('',#8,#10,#23,.T.);\n#25=ORIENTED_EDGE('',*,*,#20,.F.);\n"
             "#26=ORIENTED_EDGE('',*,*,#24,.F.);\n#27=ORIENTED_EDGE('',*,*,#15,.F.);\n";
        const nurbs::Model m = read_three_edge_face(d, {"#25", "#26", "#27"}, start);
        const nurbs::TrimmedSurface& f = only_face(m);
        CHECK(f.trim_problem.empty());
        CHECK(f.edge_gap == 0.0);
        // Every grid point away from the edges is material exactly when it lies on the half.
        const GridAgreement g = grid_agreement(f, [c](glm::dvec3 q) -> std::optional<bool> {
          q -= c;
          if (std::abs(q.y) < 0.01 || std::abs(q.z - 1) < 0.01) return std::nullopt;
          return q.y > 0 && q.z < 1;
        });
        CHECK(g.wrong == 0);
        CHECK(g.material > 100);
      }
}

TEST_CASE("STEP reader: hyperbola and parabola edges are exact conic arcs between their vertices") {
  // On the plane z = 0: the arc of the conic from vertex (x0, -y0) to (x0, y0) through its apex,
  // closed by the line x = x0. Hyperbola x^2 - y^2 = 1 (semi-axes 1) between t = -1 and 1;
  // parabola y^2 = x (focal distance 1/4) between t = -1 and 1.
  struct Case {
    const char* curve;
    double x0, y0, inside_x, outside_x;
    double (*residual)(double x, double y);
  };
  const Case cases[] = {
      {"HYPERBOLA('',#7,1.,1.)", std::cosh(1.0), std::sinh(1.0), 1.3, 1.05,
       [](double x, double y) { return x * x - y * y - 1; }},
      {"PARABOLA('',#7,0.25)", 0.25, 0.5, 0.1, 0.02, [](double x, double y) { return y * y - x; }},
  };
  for (const Case& k : cases) {
    const std::string curve = k.curve;
    CAPTURE(curve);
    std::string d = at_origin("PLANE('',#4)");
    d += "#7=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n";
    d += fmt::format("#8={};\n", k.curve);
    d += fmt::format("#9=CARTESIAN_POINT('',({:.17g},{:.17g},0.));\n#10=VERTEX_POINT('',#9);\n", k.x0, -k.y0);
    d += fmt::format("#11=CARTESIAN_POINT('',({:.17g},{:.17g},0.));\n#12=VERTEX_POINT('',#11);\n", k.x0, k.y0);
    d += "#13=EDGE_CURVE('',#10,#12,#8,.T.);\n#14=DIRECTION('',(0.,-1.,0.));\n#15=VECTOR('',#14,1.);\n"
         "#16=LINE('',#11,#15);\n#17=EDGE_CURVE('',#12,#10,#16,.T.);\n"
         "#18=ORIENTED_EDGE('',*,*,#13,.T.);\n#19=ORIENTED_EDGE('',*,*,#17,.T.);\n"
         "#20=EDGE_LOOP('',(#18,#19));\n#21=FACE_OUTER_BOUND('',#20,.T.);\n#22=ADVANCED_FACE('',(#21),#5,.T.);\n"
         "#23=OPEN_SHELL('',(#22));\n#24=SHELL_BASED_SURFACE_MODEL('',(#23));\n"
         "#25=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#24),#900);\n";
    const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "conic.stp");
    const nurbs::TrimmedSurface& f = only_face(m);
    CHECK(f.trim_problem.empty());
    REQUIRE(f.loops.size() == 1);
    // One of the loop's two curves (the other is the line) lies on the conic.
    double best = 1e300;
    for (const nurbs::Curve2& c : f.loops[0].curves) {
      const nurbs::Interval t = nurbs::curve_domain(c);
      double worst = 0.0;
      for (int i = 0; i <= 32; ++i) {
        const glm::dvec2 uv = nurbs::curve_point(c, t.min + t.width() * i / 32);
        const glm::dvec3 p = nurbs::surface_point(f.surface, uv.x, uv.y);
        worst = std::max(worst, std::abs(k.residual(p.x, p.y)));
      }
      best = std::min(best, worst);
    }
    CHECK(best < 1e-12);
    CHECK(nurbs::is_material(f, {k.inside_x, 0.0}, 1e-9));
    CHECK_FALSE(nurbs::is_material(f, {k.outside_x, 0.9 * k.y0}, 1e-9));
  }
}

TEST_CASE("STEP reader: quasi-uniform and Bezier B-splines take the knots the standard implies") {
  // The square [0, 2]^2 at z = 1 as a bilinear QUASI_UNIFORM_SURFACE (complex instance, no knots),
  // its edges degree-1 QUASI_UNIFORM_CURVEs and one quadratic BEZIER_CURVE of 5 points (two pieces)
  // along the bottom edge.
  std::string d = context(kMillimetre);
  const double xy[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  for (int i = 0; i < 4; ++i)
    d += fmt::format("#{}=CARTESIAN_POINT('',({},{},1.));\n#{}=VERTEX_POINT('',#{});\n", 10 + i, xy[i][0], xy[i][1],
                     20 + i, 10 + i);
  d += "#5=( BOUNDED_SURFACE() B_SPLINE_SURFACE(1,1,((#10,#13),(#11,#12)),.UNSPECIFIED.,.F.,.F.,.F.) "
       "GEOMETRIC_REPRESENTATION_ITEM() QUASI_UNIFORM_SURFACE() REPRESENTATION_ITEM('') SURFACE() );\n";
  d += "#30=CARTESIAN_POINT('',(0.5,0.,1.));\n#31=CARTESIAN_POINT('',(1.,0.,1.));\n"
       "#32=CARTESIAN_POINT('',(1.5,0.,1.));\n#50=BEZIER_CURVE('',2,(#10,#30,#31,#32,#11),.UNSPECIFIED.,.F.,.F.);\n";
  for (int i = 1; i < 4; ++i)
    d += fmt::format("#{}=QUASI_UNIFORM_CURVE('',1,(#{},#{}),.UNSPECIFIED.,.F.,.U.);\n", 50 + i, 10 + i,
                     10 + (i + 1) % 4);
  for (int i = 0; i < 4; ++i)
    d += fmt::format("#{}=EDGE_CURVE('',#{},#{},#{},.T.);\n#{}=ORIENTED_EDGE('',*,*,#{},.T.);\n", 60 + i, 20 + i,
                     20 + (i + 1) % 4, 50 + i, 70 + i, 60 + i);
  d += "#80=EDGE_LOOP('',(#70,#71,#72,#73));\n#81=FACE_OUTER_BOUND('',#80,.T.);\n"
       "#82=ADVANCED_FACE('',(#81),#5,.T.);\n#83=OPEN_SHELL('',(#82));\n"
       "#84=SHELL_BASED_SURFACE_MODEL('',(#83));\n#85=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#84),#900);\n";
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "quasi.stp", &log);
  CHECK(m.dropped_faces.empty());
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(f.trim_problem.empty());
  CHECK(f.surface.knots_u == std::vector<double>{0, 0, 1, 1});
  CHECK(f.edge_gap == 0.0);
  CHECK(material_share(f) == doctest::Approx(1.0).epsilon(0.02));
  // The surface spans the square: its corner (u, v) = (1, 1) is (2, 2, 1).
  CHECK(nurbs::surface_point(f.surface, 1.0, 1.0) == glm::dvec3(2, 2, 1));
}

TEST_CASE("STEP reader: a cone placed at its apex keeps a face on the nappe behind its axis") {
  // CATIA places drill points as cones of radius 0 at the apex, the axis pointing away from the
  // face: radius 0, semi-angle 45 degrees, axis +z, and the band between the circles at z = -1
  // (radius 1) and z = -2 (radius 2), where r + v tan(angle) < 0.
  std::string d = at_origin("CONICAL_SURFACE('',#4,0.,0.7853981633974483)");
  d += "#6=CARTESIAN_POINT('',(0.,0.,-1.));\n#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);\n#8=CIRCLE('',#7,1.);\n"
       "#9=CARTESIAN_POINT('',(0.,0.,-2.));\n#10=AXIS2_PLACEMENT_3D('',#9,#2,#3);\n#11=CIRCLE('',#10,2.);\n"
       "#12=CARTESIAN_POINT('',(1.,0.,-1.));\n#13=VERTEX_POINT('',#12);\n"
       "#14=CARTESIAN_POINT('',(2.,0.,-2.));\n#15=VERTEX_POINT('',#14);\n"
       "#16=EDGE_CURVE('',#13,#13,#8,.T.);\n#17=EDGE_CURVE('',#15,#15,#11,.T.);\n"
       "#18=ORIENTED_EDGE('',*,*,#16,.T.);\n#19=ORIENTED_EDGE('',*,*,#17,.F.);\n"
       "#20=EDGE_LOOP('',(#18));\n#21=EDGE_LOOP('',(#19));\n#22=FACE_BOUND('',#20,.T.);\n"
       "#23=FACE_BOUND('',#21,.T.);\n#24=ADVANCED_FACE('',(#22,#23),#5,.T.);\n"
       "#25=OPEN_SHELL('',(#24));\n#26=SHELL_BASED_SURFACE_MODEL('',(#25));\n"
       "#27=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#26),#900);\n";
  const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "apex.stp");
  CHECK(m.dropped_faces.empty());
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(f.edge_gap == 0.0);
  CHECK(f.trim_problem.empty());
  const auto [lowest, highest] = material_z_range(f);
  CHECK(lowest < -1.9);
  CHECK(highest > -1.1);
  CHECK(highest < -1.0 + 1e-9);
}

TEST_CASE("STEP reader: a plane given as a LINE extruded, its edges beyond the line's unit vector") {
  // The square of side 2 on z = 1 again, on the line through (0, 0, 1) along x (vector of length 1)
  // swept along y: its edges reach the line's parameter 2.
  std::string text = square_face(kMillimetre);
  text.replace(text.find("#5=PLANE('',#4);"), 16,
               "#5=SURFACE_OF_LINEAR_EXTRUSION('',#6,#8);\n#6=LINE('',#1,#7);\n#7=VECTOR('',#3,1.);\n"
               "#8=VECTOR('',#9,1.);\n#9=DIRECTION('',(0.,1.,0.));");
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_step_text(text, "extruded.stp", &log);
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(log.trim_problems.empty());
  // The patch is the square's box grown by 1 % each way, as for a PLANE.
  CHECK(material_share(f) == doctest::Approx(1.0 / (1.02 * 1.02)).epsilon(0.01));
  const nurbs::Box box = nurbs::sampled_box(f.surface);
  CHECK(box.min.x == doctest::Approx(-0.02));
  CHECK(box.max.x == doctest::Approx(2.02));
  CHECK(box.max.z == doctest::Approx(1.0));
}

TEST_CASE("STEP reader: bad references, cycles and unsupported geometry are named") {
  auto message = [](const std::string& text) {
    try {
      (void)nurbs::io::read_step_text(text, "bad.stp");
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string missing = square_face(kMillimetre);
  const std::string face = "#82=ADVANCED_FACE('square',(#81),#5";
  missing.replace(missing.find(face), face.size(), "#82=ADVANCED_FACE('square',(#81),#99");
  CHECK(message(missing).find("#82 (ADVANCED_FACE): refers to #99, which is not defined") != std::string::npos);

  std::string cycle = square_face(kMillimetre);
  cycle.replace(cycle.find("#50=LINE('',#10,#40)"), 20, "#50=TRIMMED_CURVE('',#50,(),(),.T.,.UNSPECIFIED.)");
  CHECK(message(cycle).find("nest deeper") != std::string::npos);

  std::string wrong = square_face(kMillimetre);
  wrong.replace(wrong.find("#81=FACE_OUTER_BOUND('',#80"), 27, "#81=FACE_OUTER_BOUND('',#5");
  CHECK(message(wrong).find("#5 (PLANE): is not a EDGE_LOOP") != std::string::npos);

  // A face on a surface type that is not read is dropped with a warning naming it.
  std::string other = square_face(kMillimetre);
  other.replace(other.find("#5=PLANE('',#4)"), 15, "#5=OFFSET_SURFACE('',#4,1.,.F.)");
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_step_text(other, "offset.stp", &log);
  CHECK(m.bodies.front().faces.empty());
  REQUIRE(log.warnings.size() == 1);
  CHECK(log.warnings.front().find("OFFSET_SURFACE") != std::string::npos);
}

TEST_CASE("STEP reader: assembly placements, their cycles and their blow-up are bounded") {
  auto with = [](const std::string& extra) {
    std::string text = square_face(kMillimetre);
    text.insert(text.find("ENDSEC;\nEND-ISO"), extra);
    return text;
  };
  auto place = [](int id, int child, int parent, int transform) {
    return fmt::format(
        "#{}=( REPRESENTATION_RELATIONSHIP('','',#{},#{}) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{}) "
        "SHAPE_REPRESENTATION_RELATIONSHIP() );\n",
        id, child, parent, transform);
  };
  // The square placed twice in an assembly, moved by (10, 0, 0) the second time.
  const std::string frames =
      "#300=CARTESIAN_POINT('',(10.,0.,0.));\n#301=AXIS2_PLACEMENT_3D('',#300,#2,#3);\n"
      "#302=ITEM_DEFINED_TRANSFORMATION('','',#4,#4);\n#303=ITEM_DEFINED_TRANSFORMATION('','',#4,#301);\n";
  const nurbs::Model two = nurbs::io::read_step_text(
      with(frames + "#310=SHAPE_REPRESENTATION('',(#4),#900);\n" + place(311, 85, 310, 302) + place(312, 85, 310, 303)),
      "two.stp");
  REQUIRE(two.bodies.size() == 2);
  const nurbs::Box b0 = nurbs::sampled_box(two.bodies[0].faces.front().surface);
  const nurbs::Box b1 = nurbs::sampled_box(two.bodies[1].faces.front().surface);
  CHECK(b1.min.x - b0.min.x == doctest::Approx(10.0));
  CHECK(b1.min.y == doctest::Approx(b0.min.y));

  auto message = [](const std::string& text) {
    try {
      (void)nurbs::io::read_step_text(text, "bad.stp");
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Each representation placed in the other: a cycle.
  CHECK(message(with(frames + "#310=SHAPE_REPRESENTATION('',(#4),#900);\n" + place(311, 85, 310, 302) +
                     place(312, 310, 85, 302)))
            .find("nest deeper than") != std::string::npos);
  // 30 levels of assemblies each holding the one below twice: 2^30 placements, refused at once.
  std::string levels = frames;
  for (int k = 0; k < 30; ++k) {
    const int rep = 400 + 3 * k, below = k == 0 ? 85 : 400 + 3 * (k - 1);
    levels += fmt::format("#{}=SHAPE_REPRESENTATION('',(#4),#900);\n", rep);
    levels += place(rep + 1, below, rep, 302) + place(rep + 2, below, rep, 303);
  }
  const std::string blown = message(with(levels));
  CHECK((blown.find("placed more than") != std::string::npos ||
         blown.find("control points in all") != std::string::npos));
}

TEST_CASE("shared STEP files read as OpenCASCADE does and as their IGES twins" * test::needs_shared_models()) {
  struct Case {
    const char* step;
    const char* iges;      // the twin, empty when there is none
    size_t bodies, faces;  // OpenCASCADE 7.6 (occt_reference.txt): solids or shells, faces
  };
  const Case cases[] = {{"step/gmsh_component8.step", "generated/gmsh_component8_brep.igs", 1, 21},
                        {"step/pythonocc_Ventilator.stp", "generated/pythonocc_Ventilator_brep.igs", 1, 305},
                        {"generated/vase_shell_t2.step", "generated/vase_shell_t2_brep.igs", 1, 6},
                        {"generated/teapot_bezier32.step", "generated/teapot_bezier32_brep.igs", 4, 32},
                        {"assembly/gmsh_as1-tu-203.stp", "", 18, 160}};
  for (const Case& c : cases) {
    CAPTURE(c.step);
    nurbs::io::IgesReadLog log;
    const nurbs::Model m = nurbs::io::read_step(test::shared_models_dir() / c.step, &log);
    size_t faces = 0;
    for (const nurbs::Body& b : m.bodies) faces += b.faces.size();
    CHECK(m.bodies.size() == c.bodies);
    CHECK(faces == c.faces);
    CHECK(log.trim_problems.empty());
    CHECK(log.warnings.empty());
    if (*c.iges) {
      const nurbs::Model twin = nurbs::io::read_iges(test::shared_models_dir() / c.iges);
      const nurbs::Box a = nurbs::model_box(m), b = nurbs::model_box(twin);
      // The faces' surfaces may extend differently beyond their trims; the boxes of the untrimmed
      // surfaces still agree where both files keep the same surfaces.
      CHECK(glm::length(a.min - b.min) <= 0.5 * a.diagonal());
      CHECK(glm::length(a.max - b.max) <= 0.5 * a.diagonal());
    }
  }
}

TEST_CASE("shared STEP assembly: instances placed as OpenCASCADE places them" * test::needs_shared_models()) {
  const nurbs::Model m = nurbs::io::read_step(test::shared_models_dir() / "assembly/gmsh_as1-tu-203.stp");
  // OpenCASCADE 7.6: bbox [-10 0 -4] - [190 150 80] (the planar faces reach the box). The surfaces'
  // box holds it and exceeds it by at most the planes' 1 % margins: a part placed wrongly would
  // move it by tens of millimetres.
  const nurbs::Box box = nurbs::model_box(m);
  const glm::dvec3 lo(-10, 0, -4), hi(190, 150, 80);
  for (int k = 0; k < 3; ++k) {
    CHECK(box.min[k] <= lo[k] + 1e-6);
    CHECK(box.max[k] >= hi[k] - 1e-6);
    CHECK(box.min[k] >= lo[k] - 0.011 * (hi[k] - lo[k]));
    CHECK(box.max[k] <= hi[k] + 0.011 * (hi[k] - lo[k]));
  }
  int nuts = 0;
  for (const nurbs::Body& b : m.bodies) {
    CHECK_FALSE(b.instance.empty());
    nuts += b.name.rfind("nut", 0) == 0 ? 1 : 0;
  }
  CHECK(nuts == 8);
}

namespace {

// `text` with `record` added at the end of its DATA section, and the line it lands on.
std::pair<std::string, int> with_record(std::string text, const std::string& record) {
  const size_t at = text.find("ENDSEC;\nEND-ISO");
  text.insert(at, record);
  return {text, static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1};
}

// The square of square_face() on a bilinear B-spline surface over [-1, 3]^2 at height z (the edges
// lie at z = 1).
std::string square_on_bspline(double z) {
  std::string text = square_face(kMillimetre);
  std::string s =
      "#5=B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#600,#601),(#602,#603)),.UNSPECIFIED.,.F.,.F.,.F.,"
      "(2,2),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.);";
  const double xy[4][2] = {{-1, -1}, {-1, 3}, {3, -1}, {3, 3}};
  for (int i = 0; i < 4; ++i) s += fmt::format("\n#{}=CARTESIAN_POINT('',({},{},{}));", 600 + i, xy[i][0], xy[i][1], z);
  text.replace(text.find("#5=PLANE('',#4);"), 16, s);
  return text;
}

std::string read_message(const std::string& text) {
  try {
    (void)nurbs::io::read_step_text(text, "bad.stp");
  } catch (const ReadError& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

}  // namespace

TEST_CASE("STEP reader: derived attributes (*) of oriented shells and faces, voids of a solid") {
  // Fusion 360 writes the void of a BREP_WITH_VOIDS as ORIENTED_CLOSED_SHELL('',*,#shell,.F.): its
  // faces (cfs_faces) are derived, written *. Each void here holds the square's face through an
  // ORIENTED_FACE('',*,#82,o) (bounds derived): .T. keeps it as the void turns it round, .F. turns it back.
  std::string text = square_face(kMillimetre);
  const std::string shells = "#83=OPEN_SHELL('',(#82));\n#84=SHELL_BASED_SURFACE_MODEL('',(#83));";
  text.replace(text.find(shells), shells.size(),
               "#83=CLOSED_SHELL('',(#82));\n#84=BREP_WITH_VOIDS('',#83,(#87,#88));\n"
               "#87=ORIENTED_CLOSED_SHELL('',*,#89,.F.);\n#88=ORIENTED_CLOSED_SHELL('',*,#90,.F.);\n"
               "#89=CLOSED_SHELL('',(#91));\n#90=CLOSED_SHELL('',(#92));\n"
               "#91=ORIENTED_FACE('',*,#82,.T.);\n#92=ORIENTED_FACE('',*,#82,.F.);");
  const nurbs::Model m = nurbs::io::read_step_text(text, "voids.stp");
  REQUIRE(m.bodies.size() == 1);
  const auto& faces = m.bodies.front().faces;
  REQUIRE(faces.size() == 3);
  CHECK_FALSE(faces[0].reversed);
  CHECK(faces[1].reversed);
  CHECK_FALSE(faces[2].reversed);
  CHECK(m.faces_in_file == 3);
  // An orientation where the schema has one is still checked.
  text.replace(text.find("#87=ORIENTED_CLOSED_SHELL('',*,#89,.F.)"), 39, "#87=ORIENTED_CLOSED_SHELL('',*,#89,*)");
  CHECK(read_message(text).find("#87 (ORIENTED_CLOSED_SHELL): orientation is not .T. or .F.") != std::string::npos);
}

TEST_CASE("STEP reader: a damaged record fails the read only where the geometry reaches it") {
  // SolidWorks 2024 writes a reference beyond any instance number in PERSON_AND_ORGANIZATION.
  const auto [text, line] = with_record(square_face(kMillimetre),
                                        "#500=PERSON_AND_ORGANIZATION(#18446744073709551615,#2);\n"
                                        "#501=MEASURE_WITH_UNIT(1.2.3,#901);\n");
  const nurbs::io::StepFile f = nurbs::io::parse_step_file(text, "sw.stp");
  REQUIRE(f.find(500));
  CHECK(f.find(500)->damage == "reference #18446744073709551615 out of range");
  CHECK(f.find(500)->records.front().params[0].kind == nurbs::io::StepValue::Kind::Null);
  CHECK(f.find(500)->records.front().params[1].ref == 2);
  CHECK(f.find(2)->damage.empty());

  const nurbs::Model m = nurbs::io::read_step_text(text, "sw.stp");
  CHECK(only_face(m).name == "square");
  REQUIRE(m.read_warnings.size() == 2);
  CHECK(m.read_warnings[0] == fmt::format("line {}: #500 (PERSON_AND_ORGANIZATION): reference "
                                          "#18446744073709551615 out of range; the record is not used by the geometry",
                                          line));
  CHECK(m.read_warnings[1] == fmt::format("line {}: #501 (MEASURE_WITH_UNIT): bad number '1.2.3'; the record is not "
                                          "used by the geometry",
                                          line + 1));

  // The same damage in the face's plane: the read fails naming file, line and entity.
  std::string reached = square_face(kMillimetre);
  reached.replace(reached.find("#5=PLANE('',#4);"), 16, "#5=PLANE('',#18446744073709551615);");
  const int plane_line = static_cast<int>(std::count(
                             reached.begin(), reached.begin() + static_cast<long>(reached.find("#5=PLANE")), '\n')) +
                         1;
  CHECK(read_message(reached) ==
        fmt::format("bad.stp: line {}: #5 (PLANE): reference #18446744073709551615 out of range", plane_line));
  // Damage that is not lexical still refuses the file.
  CHECK(read_message(with_record(square_face(kMillimetre), "#502=PRODUCT('open);\n").first).find("not closed") !=
        std::string::npos);
}

TEST_CASE("STEP reader: a face whose edges lie off its surface is kept with the gap") {
  // The square's edges lie 1e-3 above the B-spline surface, the plane: over 1e-4 of the face's size
  // (2.83) and 10 times the file's uncertainty (1e-5), under 5 % of it. OpenCASCADE keeps such
  // faces, growing the edges' tolerance.
  for (const bool bspline : {true, false}) {
    CAPTURE(bspline);
    std::string text = square_on_bspline(1.0 - 1e-3);
    if (!bspline) {
      text = square_face(kMillimetre);
      text.replace(text.find("#1=CARTESIAN_POINT('',(0.,0.,1.));"), 34, "#1=CARTESIAN_POINT('',(0.,0.,0.999));");
    }
    const nurbs::Model m = nurbs::io::read_step_text(text, "off.stp");
    const nurbs::TrimmedSurface& f = only_face(m);
    CHECK(m.dropped_faces.empty());
    // The edges are straight and level: every sample lies 1e-3 off (up to Newton's convergence).
    CHECK(f.edge_gap == doctest::Approx(1e-3).epsilon(0.01));
    CHECK(material_share(f) > 0.2);
  }
  // Edges on the surface (within the tolerance) leave the gap 0.
  CHECK(only_face(nurbs::io::read_step_text(square_on_bspline(1.0 - 1e-6), "on.stp")).edge_gap == 0.0);
  // 0.5 off a face of size 2.83 (beyond 15 %): the edges bound nothing on the surface.
  nurbs::io::IgesReadLog log;
  const nurbs::Model far = nurbs::io::read_step_text(square_on_bspline(0.5), "far.stp", &log);
  CHECK(far.bodies.front().faces.empty());
  REQUIRE(far.dropped_faces.size() == 1);
  CHECK(far.dropped_faces.front().reason.find("its edges lie up to 0.5 from its surface") != std::string::npos);
}

namespace {

// `text` (square_face() or square_on_bspline()) with each edge's curve a SURFACE_CURVE that carries a
// PCURVE on the surface #5, its (u, v) = ((x + shift) / scale, (y + shift) / scale): 2D LINEs under
// the 3D LINEs (a unit vector in 3D: the same parameter t runs over the side's length 2), or degree-1
// B-splines under both.
std::string with_pcurves(std::string text, bool spline, double shift, double scale) {
  const double xy[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  std::string add =
      "#910=( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() "
      "REPRESENTATION_CONTEXT('2D SPACE','') );\n";
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const std::string edge = fmt::format(",#{},.T.);", 50 + i);
    text.replace(text.find(edge, text.find(fmt::format("#{}=EDGE_CURVE", 60 + i))), edge.size(),
                 fmt::format(",#{},.T.);", 100 + i));
    if (spline) {
      const std::string line = fmt::format("#{}=LINE('',#{},#{});", 50 + i, 10 + i, 40 + i);
      text.replace(text.find(line), line.size(),
                   fmt::format("#{}=B_SPLINE_CURVE_WITH_KNOTS('',1,(#{},#{}),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),"
                               ".UNSPECIFIED.);",
                               50 + i, 10 + i, 10 + j));
    }
    add += fmt::format("#{}=SURFACE_CURVE('',#{},(#{}),.CURVE_3D.);\n#{}=PCURVE('',#5,#{});\n", 100 + i, 50 + i,
                       110 + i, 110 + i, 120 + i);
    add += fmt::format("#{}=DEFINITIONAL_REPRESENTATION('',(#{}),#910);\n", 120 + i, 130 + i);
    const double u0 = (xy[i][0] + shift) / scale, v0 = (xy[i][1] + shift) / scale;
    const double u1 = (xy[j][0] + shift) / scale, v1 = (xy[j][1] + shift) / scale;
    add += fmt::format("#{}=CARTESIAN_POINT('',({},{}));\n#{}=CARTESIAN_POINT('',({},{}));\n", 140 + i, u0, v0, 150 + i,
                       u1, v1);
    if (spline)
      add += fmt::format(
          "#{}=B_SPLINE_CURVE_WITH_KNOTS('',1,(#{},#{}),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),"
          ".UNSPECIFIED.);\n",
          130 + i, 140 + i, 150 + i);
    else
      add += fmt::format("#{}=LINE('',#{},#{});\n#{}=VECTOR('',#{},{});\n#{}=DIRECTION('',({},{}));\n", 130 + i,
                         140 + i, 160 + i, 160 + i, 170 + i, 1 / scale, 170 + i, u1 - u0, v1 - v0);
  }
  return with_record(text, add).first;
}

}  // namespace

TEST_CASE("STEP reader: supplemental geometry is said and left out of the shape") {
  // The square's face in the part's surface model, and again in a surface model of a
  // CONSTRUCTIVE_GEOMETRY_REPRESENTATION (CATIA's and NX's reference planes beside the part).
  const auto [text, line] =
      with_record(square_face(kMillimetre),
                  "#86=OPEN_SHELL('',(#82));\n#87=SHELL_BASED_SURFACE_MODEL('',(#86));\n"
                  "#88=CONSTRUCTIVE_GEOMETRY_REPRESENTATION('supplemental geometry',(#87),#900);\n");
  const nurbs::Model m = nurbs::io::read_step_text(text, "supplemental.stp");
  REQUIRE(m.bodies.size() == 1);
  CHECK(m.bodies.front().faces.size() == 1);
  CHECK(m.faces_in_file == 1);
  CHECK(m.skipped_types ==
        std::map<std::string, int>{{"supplemental geometry (CONSTRUCTIVE_GEOMETRY_REPRESENTATION) faces", 1}});
  REQUIRE(m.read_warnings.size() == 1);
  CHECK(m.read_warnings.front().find("#87 (1 face(s)): supplemental geometry of #88") != std::string::npos);
}

TEST_CASE("STEP reader: the PCURVEs of read edges are not counted as skipped geometry") {
  // LINE edges with 2D LINE PCURVEs (the reader flattens lines itself, it reads none of them).
  const nurbs::Model plane =
      nurbs::io::read_step_text(with_pcurves(square_face(kMillimetre), false, 0.0, 1.0), "pc.stp");
  CHECK(only_face(plane).loops.front().curves.size() == 4);
  CHECK(plane.skipped_types.empty());
  // B-spline edges whose PCURVEs are the trims.
  const nurbs::Model spline = nurbs::io::read_step_text(with_pcurves(square_on_bspline(1.0), true, 1.0, 4.0), "pc.stp");
  CHECK(only_face(spline).edge_gap == 0.0);
  CHECK(spline.skipped_types.empty());
  // Geometry no face reaches is counted: a loose circle, a surface only a PCURVE lies on.
  auto [loose, line] = with_record(with_pcurves(square_face(kMillimetre), false, 0.0, 1.0),
                                   "#700=CIRCLE('',#4,5.);\n#701=CYLINDRICAL_SURFACE('',#4,1.);\n");
  loose.replace(loose.find("#110=PCURVE('',#5,"), 18, "#110=PCURVE('',#701,");
  const nurbs::Model counted = nurbs::io::read_step_text(loose, "loose.stp");
  CHECK(counted.skipped_types == std::map<std::string, int>{{"CIRCLE", 1}, {"CYLINDRICAL_SURFACE", 1}});
}

TEST_CASE("STEP reader: a face whose PCURVEs lie off its edges keeps them, with the gap") {
  // Edges 1e-3 above the B-spline surface, their PCURVEs on it: neither the PCURVEs nor the
  // projection lie within the tolerance; the PCURVEs are the face's boundary, as OpenCASCADE takes
  // them. B-spline edges with B-spline PCURVEs, and LINE edges with 2D LINE PCURVEs (a line's
  // PCURVE is taken over the line's own parameter range between the vertices, as a B-spline's).
  for (const bool spline : {true, false}) {
    CAPTURE(spline);
    const nurbs::Model m =
        nurbs::io::read_step_text(with_pcurves(square_on_bspline(1.0 - 1e-3), spline, 1.0, 4.0), "pc.stp");
    const nurbs::TrimmedSurface& f = only_face(m);
    CHECK(f.edge_gap == doctest::Approx(1e-3).epsilon(0.01));
    // The first trim is the first PCURVE: from (0.25, 0.25) to (0.75, 0.25).
    const nurbs::Curve2& c = f.loops.front().curves.front();
    CHECK(c.points.size() == 2);
    CHECK(c.points.front().x == doctest::Approx(0.25));
    CHECK(c.points.back().x == doctest::Approx(0.75));
    CHECK(c.points.back().y == doctest::Approx(0.25));
  }
}

TEST_CASE("STEP reader: a circle edge's PCURVE on a B-spline surface is its trim, over the circle's angles") {
  // A disk of radius 1 about (1, 1, 1) on a bilinear B-spline plane z = 1 over [-1, 3]^2 ((u, v) =
  // ((x + 1) / 4, (y + 1) / 4)): one CIRCLE edge whose SURFACE_CURVE carries the circle in (u, v)
  // as a rational quadratic B-spline parametrised by the angle (knots 0, pi/2, ..., 2 pi). The trim
  // is that curve (without the PCURVEs of conics: a cubic through points projected onto the plane).
  std::string d = context(kMillimetre);
  d +=
      "#5=B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#600,#601),(#602,#603)),.UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,2),"
      "(0.,1.),(0.,1.),.UNSPECIFIED.);\n#600=CARTESIAN_POINT('',(-1.,-1.,1.));\n#601=CARTESIAN_POINT('',(-1.,3.,1.));\n"
      "#602=CARTESIAN_POINT('',(3.,-1.,1.));\n#603=CARTESIAN_POINT('',(3.,3.,1.));\n";
  const double h = std::sqrt(0.5);
  const double pc[9][2] = {{0.75, 0.5},  {0.75, 0.75}, {0.5, 0.75},  {0.25, 0.75}, {0.25, 0.5},
                           {0.25, 0.25}, {0.5, 0.25},  {0.75, 0.25}, {0.75, 0.5}};
  std::string points, weights;
  for (int i = 0; i < 9; ++i) {
    d += fmt::format("#{}=CARTESIAN_POINT('',({},{}));\n", 140 + i, pc[i][0], pc[i][1]);
    points += fmt::format("{}#{}", i ? "," : "", 140 + i);
    weights += fmt::format("{}{}", i ? "," : "", i % 2 ? h : 1.0);
  }
  d += "#910=( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() "
       "REPRESENTATION_CONTEXT('2D SPACE','') );\n";
  d += fmt::format(
      "#130=( BOUNDED_CURVE() B_SPLINE_CURVE(2,({}),.CIRCULAR_ARC.,.T.,.F.) B_SPLINE_CURVE_WITH_KNOTS((3,2,2,2,3),"
      "(0.,1.5707963267948966,3.141592653589793,4.71238898038469,6.283185307179586),.UNSPECIFIED.) CURVE() "
      "GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) REPRESENTATION_ITEM('') );\n",
      points, weights);
  d += "#120=DEFINITIONAL_REPRESENTATION('',(#130),#910);\n#110=PCURVE('',#5,#120);\n"
       "#30=CARTESIAN_POINT('',(1.,1.,1.));\n#31=DIRECTION('',(0.,0.,1.));\n#32=DIRECTION('',(1.,0.,0.));\n"
       "#33=AXIS2_PLACEMENT_3D('',#30,#31,#32);\n#34=CIRCLE('',#33,1.);\n"
       "#100=SURFACE_CURVE('',#34,(#110),.CURVE_3D.);\n#35=CARTESIAN_POINT('',(2.,1.,1.));\n"
       "#36=VERTEX_POINT('',#35);\n#11=EDGE_CURVE('',#36,#36,#100,.T.);\n";
  const nurbs::Model m = read_one_edge_face(d, ".T.", ".T.");
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(f.trim_problem.empty());
  CHECK(f.edge_gap == 0.0);
  REQUIRE(f.loops.size() == 1);
  REQUIRE(f.loops.front().curves.size() == 1);
  const nurbs::Curve2& c = f.loops.front().curves.front();
  CHECK(c.degree == 2);
  CHECK(c.weights.size() == 9);
  CHECK(glm::length(c.points.front() - glm::dvec2(0.75, 0.5)) < 1e-12);
}

TEST_CASE("STEP reader: edges off their plane by less than the file's stated uncertainty keep their gap") {
  // The square's edges at z = 1 on the plane z = 1 - 1e-3, in a file stating an uncertainty of 0.01
  // (Fusion 360 writes it): an answer near the edge may be off by the gap, far beyond its bound,
  // whatever the writer's tolerance says.
  std::string text = square_face(kMillimetre);
  text.replace(text.find("#1=CARTESIAN_POINT('',(0.,0.,1.));"), 34, "#1=CARTESIAN_POINT('',(0.,0.,0.999));");
  text.replace(text.find("LENGTH_MEASURE(1.E-05)"), 22, "LENGTH_MEASURE(1.E-02)");
  const nurbs::Model m = nurbs::io::read_step_text(text, "gap.stp");
  CHECK(m.resolution == 1e-2);
  CHECK(only_face(m).edge_gap == doctest::Approx(1e-3).epsilon(1e-6));
}

TEST_CASE("STEP reader: of two FACE_BOUNDs without an outer one, the loop enclosing more area is outer") {
  // A washer on z = 0: circles of radius 0.278 and 0.255 about the origin, the smaller one's
  // placement turned 45 degrees (its control points' box 0.36 wide against the larger one's 0.278).
  std::string d = at_origin("PLANE('',#4)");
  d += "#6=DIRECTION('',(0.70710678118654752,0.70710678118654752,0.));\n#7=AXIS2_PLACEMENT_3D('',#1,#2,#6);\n"
       "#10=CIRCLE('',#4,0.278);\n#11=CARTESIAN_POINT('',(0.278,0.,0.));\n#12=VERTEX_POINT('',#11);\n"
       "#13=EDGE_CURVE('',#12,#12,#10,.T.);\n#14=ORIENTED_EDGE('',*,*,#13,.T.);\n#15=EDGE_LOOP('',(#14));\n"
       "#16=FACE_BOUND('',#15,.T.);\n"
       "#20=CIRCLE('',#7,0.255);\n#21=CARTESIAN_POINT('',(0.18031222920256964,0.18031222920256964,0.));\n"
       "#22=VERTEX_POINT('',#21);\n#23=EDGE_CURVE('',#22,#22,#20,.T.);\n#24=ORIENTED_EDGE('',*,*,#23,.F.);\n"
       "#25=EDGE_LOOP('',(#24));\n#26=FACE_BOUND('',#25,.T.);\n"
       "#30=ADVANCED_FACE('washer',(#26,#16),#5,.T.);\n#31=OPEN_SHELL('',(#30));\n"
       "#32=SHELL_BASED_SURFACE_MODEL('',(#31));\n#33=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#32),#900);\n";
  const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "washer.stp");
  REQUIRE(m.bodies.size() == 1);
  REQUIRE(m.bodies[0].faces.size() == 1);
  const nurbs::TrimmedSurface& f = m.bodies[0].faces[0];
  // Material on the ring between the circles, none inside the smaller one: find the (u, v) of
  // points of the plane by sampling its domain.
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(f, 1e-9);
  int ring = 0, ring_material = 0, hole = 0, hole_material = 0;
  const nurbs::Interval du = nurbs::surface_domain_u(f.surface), dv = nurbs::surface_domain_v(f.surface);
  for (int j = 0; j <= 80; ++j)
    for (int i = 0; i <= 80; ++i) {
      const glm::dvec2 uv(du.min + du.width() * i / 80, dv.min + dv.width() * j / 80);
      const double r = glm::length(nurbs::surface_point(f.surface, uv.x, uv.y));
      if (r > 0.258 && r < 0.275) ++ring, ring_material += nurbs::is_material(trim, uv);
      if (r < 0.25) ++hole, hole_material += nurbs::is_material(trim, uv);
    }
  CHECK(ring > 0);
  CHECK(ring_material == ring);
  CHECK(hole > 0);
  CHECK(hole_material == 0);
}

TEST_CASE("model format by content: STEP and IGES starts are told apart, anything else is neither") {
  using nurbs::io::ModelFormat;
  using nurbs::io::sniff_model_format;
  CHECK(sniff_model_format("ISO-10303-21;\nHEADER;\n") == ModelFormat::Step);
  CHECK(sniff_model_format("  \r\n ISO-10303-21;") == ModelFormat::Step);
  const std::string start(72, ' ');
  CHECK(sniff_model_format(start + "S      1\n") == ModelFormat::Iges);
  CHECK(sniff_model_format(start + "S      1\r\n") == ModelFormat::Iges);
  CHECK(sniff_model_format(start + "G      1\n") == ModelFormat::Iges);  // an empty Start section
  CHECK(sniff_model_format(start + "D      1\n") == ModelFormat::Unknown);
  CHECK(sniff_model_format(start + "S       \n") == ModelFormat::Unknown);  // no sequence number
  CHECK(sniff_model_format(start + "S  1 x  \n") == ModelFormat::Unknown);
  CHECK(sniff_model_format(start.substr(0, 60) + "S      1\n") == ModelFormat::Unknown);  // column 61, not 73
  CHECK(sniff_model_format("solid cube\n  facet normal 0 0 1\n") == ModelFormat::Unknown);
  CHECK(sniff_model_format("") == ModelFormat::Unknown);
}

TEST_CASE("STEP reader: a face on a spindle torus's inner part lies on it") {
  // TOROIDAL_SURFACE of major radius 1 and minor radius 3 (a screw head's dome, EUCLID): its inner
  // part, where 1 + 3 cos v < 0, holds each point at angle u + pi. The band of it between the circles
  // v = 2.5 and v = 2 pi - 2.5: radius rho = -(1 + 3 cos 2.5) at heights z = +-3 sin 2.5.
  const double rho = -(1 + 3 * std::cos(2.5)), z = 3 * std::sin(2.5);
  std::string d = at_origin("TOROIDAL_SURFACE('',#4,1.,3.)");
  for (const auto& [k, h] : {std::pair{0, z}, std::pair{1, -z}}) {
    const int n = 6 + 10 * k;
    d += fmt::format(
        "#{}=CARTESIAN_POINT('',(0.,0.,{}));\n#{}=AXIS2_PLACEMENT_3D('',#{},#2,#3);\n#{}=CIRCLE('',#{},{});\n"
        "#{}=CARTESIAN_POINT('',({},0.,{}));\n#{}=VERTEX_POINT('',#{});\n#{}=EDGE_CURVE('',#{},#{},#{},.T.);\n"
        "#{}=ORIENTED_EDGE('',*,*,#{},.T.);\n#{}=EDGE_LOOP('',(#{}));\n#{}=FACE_BOUND('',#{},{});\n",
        n, h, n + 1, n, n + 2, n + 1, rho, n + 3, rho, h, n + 4, n + 3, n + 5, n + 4, n + 4, n + 2, n + 6, n + 5,
        n + 7, n + 6, n + 8, n + 7, k == 0 ? ".T." : ".F.");
  }
  d += "#30=ADVANCED_FACE('',(#14,#24),#5,.T.);\n#31=OPEN_SHELL('',(#30));\n"
       "#32=SHELL_BASED_SURFACE_MODEL('',(#31));\n#33=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#32),#900);\n";
  const nurbs::Model m = nurbs::io::read_step_text(step_file(d), "spindle.stp");
  CHECK(m.dropped_faces.empty());
  const nurbs::TrimmedSurface& f = only_face(m);
  CHECK(f.trim_problem.empty());
  CHECK(f.edge_gap < 1e-9);
  // Every point of the patch lies on the inner part: distance rho' from the axis with
  // (rho' + 1)^2 + z^2 = 9, within the band and the margin the patch takes beyond its edges.
  const nurbs::Interval u = nurbs::surface_domain_u(f.surface), v = nurbs::surface_domain_v(f.surface);
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      const glm::dvec3 p = nurbs::surface_point(f.surface, u.min + u.width() * i / 8, v.min + v.width() * j / 8);
      CHECK(std::abs(std::hypot(std::hypot(p.x, p.y) + 1, p.z) - 3) < 1e-9);
      CHECK(std::abs(p.z) < z + 0.1);
    }
}
