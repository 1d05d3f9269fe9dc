// IGES analytic surfaces (iges_analytic.h): for each entity type, a small B-rep file (one 510 face
// on the surface, a triangle loop of 110 lines in IGES (u, v)) is read back; the NURBS must lie on
// the exact shape, S(map(u, v)) must equal the entity's parametrisation at random (u, v), and the
// face's mapped loop must reach the corners. Plus the shared Ventilator: every face read.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <array>
#include <functional>
#include <glm/geometric.hpp>
#include <numbers>
#include <random>
#include <sstream>

#include "iges_edit.h"
#include "nurbs/curve_eval.h"
#include "nurbs/io/iges_analytic.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "sample_models.h"
#include "shared_models.h"

using nurbs::io::test::IgesEdit;
using nurbs::io::test::s;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
std::string r(double v) { return fmt::format("{:.17g}", v); }

// The frame of every case: location L, axis A (written unnormalised), reference X, Y = A x X.
const glm::dvec3 kL(1, 2, 3);
const glm::dvec3 kA = glm::normalize(glm::dvec3(1, 1, 1));
const glm::dvec3 kX = glm::normalize(glm::dvec3(1, -1, 0));
const glm::dvec3 kY = glm::cross(kA, kX);
const glm::dvec3 kUp(0, 0, 1);  // axis of the form-0 plane, whose X is then (1, 0, 0)

glm::dvec3 radial(glm::dvec3 p) { return p - kL - glm::dot(p - kL, kA) * kA; }

// Rotation of p about the axis through kL along kA by angle a (Rodrigues).
glm::dvec3 turn(glm::dvec3 p, double a) {
  const glm::dvec3 d = p - kL, along = glm::dot(d, kA) * kA, rr = d - along;
  return kL + along + std::cos(a) * rr + std::sin(a) * glm::cross(kA, rr);
}

// A rational quadratic quarter circle of radius 2 about kL from kL + 2 e1 to kL + 2 e2, on the
// parameter interval [-1, 2], as a NURBS curve and as the fields of a 126 entity.
nurbs::Curve3 quarter(glm::dvec3 e1, glm::dvec3 e2) {
  nurbs::Curve3 c;
  c.degree = 2;
  c.knots = {-1, -1, -1, 2, 2, 2};
  c.points = {kL + 2.0 * e1, kL + 2.0 * (e1 + e2), kL + 2.0 * e2};
  c.weights = {1, std::sqrt(0.5), 1};
  return c;
}

std::vector<std::string> fields_126(const nurbs::Curve3& c) {
  std::vector<std::string> f{"2", "2", "0", "0", "0", "0"};
  for (double k : c.knots) f.push_back(r(k));
  for (double w : c.weights) f.push_back(r(w));
  for (const glm::dvec3& q : c.points) f.insert(f.end(), {r(q.x), r(q.y), r(q.z)});
  f.insert(f.end(), {"-1.", "2.", "0.", "0.", "0."});
  return f;
}

struct Case {
  const char* name;
  int type;
  int form;
  glm::dvec2 lo, hi;                                        // IGES (u, v) box of the triangle loop
  std::function<glm::dvec3(double, double)> formula;        // the entity's parametrisation S(u, v)
  std::function<double(glm::dvec3)> distance;               // to the exact shape
  std::function<std::vector<std::string>(IgesEdit&)> make;  // appends sub-entities, returns the fields
};

const nurbs::Curve3 kMeridian = quarter(kX, kA);   // generatrix of the 120: a sphere zone
const nurbs::Curve3 kDirectrix = quarter(kX, kY);  // directrix of the 122: a cylinder piece
const glm::dvec3 kShift = 3.0 * kA + 0.5 * kX;     // 122: generatrix end - directrix start

std::vector<Case> cases() {
  auto point = [](IgesEdit& e, glm::dvec3 p) { return s(e.append(116, {r(p.x), r(p.y), r(p.z)})); };
  auto dir = [](IgesEdit& e, glm::dvec3 d) { return s(e.append(123, {r(d.x), r(d.y), r(d.z)})); };
  const double sa = std::sin(30 * kDeg), ca = std::cos(30 * kDeg);
  return {
      {"190 plane, form 1",
       190,
       1,
       {-2, -1},
       {3, 4},
       [](double u, double v) { return kL + u * kX + v * kY; },
       [](glm::dvec3 p) { return std::abs(glm::dot(p - kL, kA)); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), dir(e, 3.0 * kA), dir(e, kX)};
       }},
      {"190 plane, form 0 (OpenCASCADE's X)",
       190,
       0,
       {-2, -1},
       {3, 4},
       [](double u, double v) { return kL + glm::dvec3(u, v, 0); },
       [](glm::dvec3 p) { return std::abs(p.z - kL.z); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), dir(e, kUp)};
       }},
      {"192 cylinder",
       192,
       1,
       {10, -1},
       {300, 2},
       [](double u, double v) { return kL + 2.5 * (std::cos(u * kDeg) * kX + std::sin(u * kDeg) * kY) + v * kA; },
       [](glm::dvec3 p) { return std::abs(glm::length(radial(p)) - 2.5); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), dir(e, kA), "2.5", dir(e, kX)};
       }},
      {"194 cone",
       194,
       1,
       {-45, 0},
       {200, 3},
       [=](double u, double v) {
         return kL + (2 + v * sa) * (std::cos(u * kDeg) * kX + std::sin(u * kDeg) * kY) + v * ca * kA;
       },
       [=](glm::dvec3 p) { return std::abs((glm::length(radial(p)) - 2) * ca - glm::dot(p - kL, kA) * sa); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), dir(e, kA), "2.", "30.", dir(e, kX)};
       }},
      {"196 sphere",
       196,
       1,
       {0, -80},
       {360, 60},
       [](double u, double v) {
         return kL + 3 * std::cos(v * kDeg) * (std::cos(u * kDeg) * kX + std::sin(u * kDeg) * kY) +
                3 * std::sin(v * kDeg) * kA;
       },
       [](glm::dvec3 p) { return std::abs(glm::length(p - kL) - 3); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), "3.", dir(e, kA), dir(e, kX)};
       }},
      {"198 torus",
       198,
       1,
       {-90, 30},
       {180, 330},
       [](double u, double v) {
         return kL + (5 + std::cos(u * kDeg)) * (std::cos(v * kDeg) * kX - std::sin(v * kDeg) * kY) +
                std::sin(u * kDeg) * kA;
       },
       [](glm::dvec3 p) { return std::abs(std::hypot(glm::length(radial(p)) - 5, glm::dot(p - kL, kA)) - 1); },
       [=](IgesEdit& e) {
         return std::vector<std::string>{point(e, kL), dir(e, kA), "5.", "1.", dir(e, kX)};
       }},
      {"120 surface of revolution",
       120,
       0,
       {-1, 0.3},
       {2, 4.0},
       [](double u, double v) { return turn(nurbs::curve_point(kMeridian, u), v); },
       [](glm::dvec3 p) { return std::abs(glm::length(p - kL) - 2); },
       [=](IgesEdit& e) {
         const glm::dvec3 b = kL + 4.0 * kA;
         const int axis = e.append(110, {r(kL.x), r(kL.y), r(kL.z), r(b.x), r(b.y), r(b.z)});
         return std::vector<std::string>{s(axis), s(e.append(126, fields_126(kMeridian))), "0.", "6.2831853071795862"};
       }},
      {"122 tabulated cylinder",
       122,
       0,
       {0, 0},
       {1, 1},
       [](double u, double v) { return nurbs::curve_point(kDirectrix, -1 + 3 * u) + v * kShift; },
       [](glm::dvec3 p) {
         const glm::dvec3 d = p - kL, h = glm::dot(d, kA) / glm::dot(kShift, kA) * kShift;
         return std::abs(glm::length(d - h) - 2);
       },
       [=](IgesEdit& e) {
         const glm::dvec3 g = kDirectrix.points.front() + kShift;
         return std::vector<std::string>{s(e.append(126, fields_126(kDirectrix))), r(g.x), r(g.y), r(g.z)};
       }},
  };
}

// A one-face B-rep file: the case's surface, a triangle loop (u0, v0) -> (u1, v0) -> (u1, v1) ->
// (u0, v0) of 110 lines in IGES (u, v), its 502 vertices and 504 edges at the formula's corners.
struct Built {
  std::string text;
  int surface = 0, face = 0;
};

Built build(const Case& c) {
  nurbs::Model base;  // a loose 128 first (the writer's file frame), then the B-rep
  base.bodies.push_back({"b", {}, glm::dmat4(1.0), ""});
  nurbs::TrimmedSurface bump;
  bump.surface = nurbs::io::test::bump();
  base.bodies[0].faces.push_back(bump);
  IgesEdit e = IgesEdit::parse(nurbs::io::write_iges_text(base));
  const std::vector<std::string> fields = c.make(e);
  Built b;
  b.surface = e.append(c.type, fields, c.form);
  const glm::dvec2 uv[3] = {c.lo, {c.hi.x, c.lo.y}, c.hi};
  std::vector<std::string> vertices{"3"}, edges{"3"}, loop{"3"};
  for (const glm::dvec2& q : uv) {
    const glm::dvec3 p = c.formula(q.x, q.y);
    vertices.insert(vertices.end(), {r(p.x), r(p.y), r(p.z)});
  }
  const int vl = e.append(502, vertices, 1);
  std::vector<int> pcurves;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = uv[k], z = uv[(k + 1) % 3];
    const glm::dvec3 pa = c.formula(a.x, a.y), pz = c.formula(z.x, z.y);
    const int line3 = e.append(110, {r(pa.x), r(pa.y), r(pa.z), r(pz.x), r(pz.y), r(pz.z)});
    edges.insert(edges.end(), {s(line3), s(vl), s(k + 1), s(vl), s((k + 1) % 3 + 1)});
    pcurves.push_back(e.append(110, {r(a.x), r(a.y), "0.", r(z.x), r(z.y), "0."}));
  }
  const int el = e.append(504, edges, 1);
  for (int k = 0; k < 3; ++k) loop.insert(loop.end(), {"0", s(el), s(k + 1), "1", "1", "0", s(pcurves[k])});
  const int lp = e.append(508, loop, 1);
  b.face = e.append(510, {s(b.surface), "1", "1", s(lp)}, 1);
  e.append(514, {"1", s(b.face), "1"}, 1);
  b.text = e.text();
  return b;
}

}  // namespace

TEST_CASE("IGES analytic surfaces: exact NURBS, the map (u, v) -> (s, t), 510 faces on them") {
  std::mt19937 rng(7);
  for (const Case& c : cases()) {
    CAPTURE(std::string(c.name));
    const Built b = build(c);
    const nurbs::io::IgesFile file = nurbs::io::parse_iges_file(b.text, "analytic.igs");
    nurbs::io::IgesGeometry g(file);
    const nurbs::io::AnalyticSurface a = nurbs::io::analytic_surface(g, b.surface, glm::dmat4(1.0), c.lo, c.hi);
    const double size = 10.0;  // every case lies within 10 of the origin
    // The NURBS lies on the shape: a few rounding errors of O(10) coordinates, 1e-12 x size.
    const nurbs::Interval su = nurbs::surface_domain_u(a.surface), sv = nurbs::surface_domain_v(a.surface);
    double off = 0.0;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j)
        off = std::max(off, c.distance(nurbs::surface_point(a.surface, su.min + su.width() * i / 40,
                                                            sv.min + sv.width() * j / 40)));
    CHECK(off < 1e-12 * size);
    // S(map(u, v)) is the entity's own S(u, v) at random (u, v) of the box: same bound.
    std::uniform_real_distribution<double> ru(c.lo.x, c.hi.x), rv(c.lo.y, c.hi.y);
    double err = 0.0;
    for (int i = 0; i < 200; ++i) {
      const double u = ru(rng), v = rv(rng);
      const glm::dvec2 st = a.map({u, v});
      err = std::max(err, glm::length(nurbs::surface_point(a.surface, st.x, st.y) - c.formula(u, v)));
    }
    CHECK(err < 1e-12 * size);

    // Through the reader: the 510 face is read, its loop mapped onto the corners.
    nurbs::io::IgesReadLog log;
    const nurbs::Model m = nurbs::io::read_iges_text(b.text, "analytic.igs", {}, &log);
    CHECK(log.warnings.empty());
    CHECK(log.trim_problems.empty());
    if (c.type >= 190) CHECK(m.skipped_entities.count(c.type) == 0);  // 120/122 are read only under faces
    const nurbs::TrimmedSurface* face = nullptr;
    for (const nurbs::Body& body : m.bodies)
      for (const nurbs::TrimmedSurface& f : body.faces)
        if (f.face_id == b.face) face = &f;
    REQUIRE(face != nullptr);
    REQUIRE(face->loops.size() == 1);
    const glm::dvec2 corners[3] = {c.lo, {c.hi.x, c.lo.y}, c.hi};
    for (const glm::dvec2& q : corners) {
      double nearest = 1e300;
      for (const nurbs::Curve2& k : face->loops[0].curves) {
        const glm::dvec2 st = nurbs::curve_point(k, nurbs::curve_domain(k).min);
        nearest = std::min(nearest, glm::length(nurbs::surface_point(face->surface, st.x, st.y) - c.formula(q.x, q.y)));
      }
      CHECK(nearest < 1e-12 * size);
    }
    // Every vertex of the mapped loop (the diagonal is a polyline where an angle changes) on the shape.
    for (const nurbs::Curve2& k : face->loops[0].curves)
      for (const glm::dvec2& q : k.points)
        CHECK(c.distance(nurbs::surface_point(face->surface, q.x, q.y)) < 1e-12 * size);
  }
}

TEST_CASE("IGES analytic surfaces: the angle map is monotone and exact at the knots") {
  const nurbs::io::ParameterAxis axis{true, kDeg, 0.0, 10 * kDeg, 290 * kDeg, 4};
  double last = -1e300;
  for (int i = 0; i <= 1000; ++i) {
    const double s = axis(10 + 290.0 * i / 1000);
    CHECK(s > last);
    last = s;
  }
  for (int k = 0; k <= 4; ++k) CHECK(std::abs(axis(10 + 290.0 * k / 4) - (10 + 290.0 * k / 4) * kDeg) < 1e-14);
}

TEST_CASE("IGES analytic surfaces: the shared Ventilator in B-rep form reads every face" *
          test::needs_shared_models()) {
  nurbs::io::IgesReadLog log;
  const nurbs::Model m =
      nurbs::io::read_iges(test::shared_models_dir() / "generated/pythonocc_Ventilator_brep.igs", {}, &log);
  size_t faces = 0;
  for (const nurbs::Body& b : m.bodies) faces += b.faces.size();
  CHECK(faces == 305);  // OpenCASCADE 7.6: faces=305 (occt_reference.txt)
  CHECK(log.warnings.empty());
  for (int type : {190, 192, 194, 196, 198}) CHECK(m.skipped_entities.count(type) == 0);
  // The surfaces' 116 points and 123 directions are read through them: nothing is skipped.
  CHECK(m.skipped_entities.empty());
}

namespace {

// Model-space curves of the edges of a 510 face's 508 loops (504 CURV of each edge entry).
std::vector<nurbs::Curve3> edge_curves(nurbs::io::IgesGeometry& g, int face) {
  const nurbs::io::IgesFile& file = g.file();
  nurbs::io::EntityParams f(file, file.entry(face));
  std::vector<nurbs::Curve3> out;
  for (int l = 0; l < f.integer(2); ++l) {
    nurbs::io::EntityParams p(file, file.entry(f.pointer(4 + l)));
    for (int c = 0, i = 2; c < p.integer(1); ++c, i += 5 + 2 * p.integer(i + 4)) {
      if (p.integer(i) != 0) continue;
      nurbs::io::EntityParams edges(file, file.entry(p.pointer(i + 1)));
      for (nurbs::Curve3& k : g.curves(edges.pointer(2 + 5 * (p.integer(i + 2) - 1)), glm::dmat4(1.0)))
        out.push_back(std::move(k));
    }
  }
  return out;
}

// Distance from q to a polyline of 512 chords of an edge curve (chord error below 2e-4 here).
std::vector<glm::dvec3> polyline(const nurbs::Curve3& c) {
  const nurbs::Interval d = nurbs::curve_domain(c);
  std::vector<glm::dvec3> out;
  for (int i = 0; i <= 512; ++i) out.push_back(nurbs::curve_point(c, d.min + d.width() * i / 512));
  return out;
}

double polyline_distance(const std::vector<glm::dvec3>& line, glm::dvec3 q) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const glm::dvec3 a = line[i], ab = line[i + 1] - a;
    const double t = glm::dot(ab, ab) > 0 ? std::clamp(glm::dot(q - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(a + t * ab - q));
  }
  return best;
}

}  // namespace

TEST_CASE("IGES analytic surfaces: the Ventilator's trims on its analytic faces follow their edges" *
          test::needs_shared_models()) {
  // The parametrisations (degrees, the cone's v along the ruling, the torus' clockwise v, the 120's
  // turn) against OpenCASCADE's writer: S(s, t) along every mapped trim curve must lie on the face's
  // model-space edges.
  const std::filesystem::path path = test::shared_models_dir() / "generated/pythonocc_Ventilator_brep.igs";
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const nurbs::io::IgesFile file = nurbs::io::parse_iges_file(text.str(), path.string());
  nurbs::io::IgesGeometry g(file);
  const nurbs::Model m = nurbs::io::read_iges(path);
  int faces = 0;
  double worst = 0.0;
  for (const nurbs::Body& b : m.bodies)
    for (const nurbs::TrimmedSurface& f : b.faces) {
      nurbs::io::EntityParams p(file, file.entry(f.face_id));
      if (!nurbs::io::is_analytic_surface_type(file.entry(p.pointer(1)).type)) continue;
      ++faces;
      std::vector<std::vector<glm::dvec3>> edges;
      for (const nurbs::Curve3& e : edge_curves(g, f.face_id)) edges.push_back(polyline(e));
      for (const nurbs::TrimLoop& loop : f.loops)
        for (const nurbs::Curve2& k : loop.curves)
          for (int i = 0; i <= 8; ++i) {
            const nurbs::Interval d = nurbs::curve_domain(k);
            const glm::dvec2 st = nurbs::curve_point(k, d.min + d.width() * i / 8);
            const glm::dvec3 q = nurbs::surface_point(f.surface, st.x, st.y);
            double nearest = 1e300;
            for (const auto& e : edges) nearest = std::min(nearest, polyline_distance(e, q));
            worst = std::max(worst, nearest);
          }
    }
  CHECK(faces == 116);
  MESSAGE("largest distance of a trim point to the face's edges: ", worst);
  // The file's own edges miss each other by up to 0.0242 (its loops' gaps, see trim problems); a
  // wrong angle unit, sense or axis would put points millimetres away.
  CHECK(worst < 0.03);
}

// 144 trimmed surfaces over 120 surfaces of revolution, as OpenCASCADE 6.5 writes them: the 142's
// parameter curves are in the 120's (u, v) (u the generatrix's parameter, v the angle in radians,
// IGES 5.3 §4.18), so the face must come out on the exact surface with its trims in the same place:
// corners at known parameters on the cone, and the trimmed area of the cone strip they bound.
namespace revolution {

std::string r(double v) { return fmt::format("{:.17g}", v); }

// The cone of the generatrix line (1, 0, 0) -> (3, 0, 4) (IGES 110: u in [0, 1]) turned about the
// z axis (110 from the origin to (0, 0, 1)): S(u, v) = ((1 + 2u) cos v, (1 + 2u) sin v, 4u).
glm::dvec3 cone(double u, double v) { return {(1 + 2 * u) * std::cos(v), (1 + 2 * u) * std::sin(v), 4 * u}; }
// Area of the strip [u0, u1] x [v0, v1]: (v1 - v0) |C'| integral of (1 + 2u) du, |C'| = sqrt(20).
double cone_area(double u0, double u1, double v0, double v1) {
  return (v1 - v0) * std::sqrt(20.0) * ((u1 + u1 * u1) - (u0 + u0 * u0));
}

int line(IgesEdit& e, glm::dvec3 a, glm::dvec3 b) {
  return e.append(110, {r(a.x), r(a.y), r(a.z), r(b.x), r(b.y), r(b.z)});
}

int surface_120(IgesEdit& e, double sa, double ta) {
  const int axis = line(e, {0, 0, 0}, {0, 0, 1});
  const int generatrix = line(e, {1, 0, 0}, {3, 0, 4});
  return e.append(120, {s(axis), s(generatrix), r(sa), r(ta)});
}

struct File {
  std::string text;
  int trimmed = 0, whole = 0;  // the 144 with an outer loop, the 144 with N1 = 0
};

constexpr double kU0 = 0.25, kU1 = 0.75, kV0 = 0.5, kV1 = 2.0;

constexpr std::array<glm::dvec2, 4> kCorners = {glm::dvec2{kU0, kV0}, {kU1, kV0}, {kU1, kV1}, {kU0, kV1}};

IgesEdit base_file();
int quadrilateral_face(IgesEdit& e, int surface, const std::array<glm::dvec2, 4>& c);

File make_file() {
  IgesEdit e = base_file();  // a loose 128 first (the writer's file frame), then the 144s
  File f;
  // Face 1: the rectangle [kU0, kU1] x [kV0, kV1] of the 120's (u, v), a 102 of four 110 lines.
  f.trimmed = quadrilateral_face(e, surface_120(e, 0.0, 2 * std::numbers::pi), kCorners);
  // Face 2: no outer boundary (N1 = 0): the whole 120 between its angles.
  const int s2 = surface_120(e, kV0, kV1);
  f.whole = e.append(144, {s(s2), "0", "0", "0"});
  f.text = e.text();
  return f;
}

const nurbs::TrimmedSurface* find_face(const nurbs::Model& m, int de) {
  for (const nurbs::Body& b : m.bodies)
    for (const nurbs::TrimmedSurface& f : b.faces)
      if (f.face_id == de) return &f;
  return nullptr;
}

// Area of the material part of the face: midpoint rule on an n x n grid of its (s, t) domain.
double trimmed_area(const nurbs::TrimmedSurface& f, int n) {
  const nurbs::Interval su = nurbs::surface_domain_u(f.surface), sv = nurbs::surface_domain_v(f.surface);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(f, 1e-9);
  const double ds = su.width() / n, dt = sv.width() / n;
  double area = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = su.min + (i + 0.5) * ds, b = sv.min + (j + 0.5) * dt;
      if (!nurbs::is_material(trim, {a, b})) continue;
      const nurbs::SurfaceDerivatives d = nurbs::surface_derivatives(f.surface, a, b);
      area += glm::length(glm::cross(d.su, d.sv)) * ds * dt;
    }
  return area;
}

// An IGES file holding a loose 128 (the writer's file frame), to append entities to.
IgesEdit base_file() {
  nurbs::Model base;
  base.bodies.push_back({"b", {}, glm::dmat4(1.0), ""});
  nurbs::TrimmedSurface bump;
  bump.surface = nurbs::io::test::bump();
  base.bodies[0].faces.push_back(bump);
  return IgesEdit::parse(nurbs::io::write_iges_text(base));
}

// A 144 on `surface` whose outer loop is the (u, v) quadrilateral c (a 102 of four 110 lines, the
// 142's parameter curve); returns the 144.
int quadrilateral_face(IgesEdit& e, int surface, const std::array<glm::dvec2, 4>& c) {
  std::vector<std::string> pieces{"4"};
  for (int k = 0; k < 4; ++k)
    pieces.push_back(s(line(e, {c[k].x, c[k].y, 0}, {c[(k + 1) % 4].x, c[(k + 1) % 4].y, 0})));
  const int on_surface = e.append(142, {"1", s(surface), s(e.append(102, pieces)), "0", "2"});
  return e.append(144, {s(surface), "1", "0", s(on_surface)});
}

// Reads the file; the 144 `face` is read whole, one loop whose control points come within 1e-12 of
// `expected` at each corner (u, v) of c.
void check_corners(const IgesEdit& e, int face, const std::array<glm::dvec2, 4>& c,
                   const std::function<glm::dvec3(glm::dvec2)>& expected) {
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "revolution.igs", {}, &log);
  CHECK(m.dropped_faces.empty());
  CHECK(log.trim_problems.empty());
  const nurbs::TrimmedSurface* f = find_face(m, face);
  REQUIRE(f != nullptr);
  REQUIRE(f->loops.size() == 1);
  for (const glm::dvec2& q : c) {
    double nearest = 1e300;
    for (const nurbs::Curve2& curve : f->loops[0].curves)
      for (const glm::dvec2& st : curve.points)
        nearest = std::min(nearest, glm::length(nurbs::surface_point(f->surface, st.x, st.y) - expected(q)));
    CHECK(nearest < 1e-12);
  }
}

}  // namespace revolution

TEST_CASE("IGES 144 over a 120 surface of revolution: exact surface, trims in place, area kept") {
  using namespace revolution;
  const File file = make_file();
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(file.text, "revolution.igs", {}, &log);
  CHECK(log.warnings.empty());
  CHECK(m.dropped_faces.empty());
  CHECK(m.faces_in_file == 3);
  CHECK(log.trim_problems.empty());
  const nurbs::TrimmedSurface* f = find_face(m, file.trimmed);
  REQUIRE(f != nullptr);
  // Every control point of the trims maps onto the cone (|radius - (1 + z / 2)| = 0): the surface is
  // the exact rational cone, a few roundings of coordinates below 4 (1e-12).
  REQUIRE(f->loops.size() == 1);
  for (const nurbs::Curve2& c : f->loops[0].curves)
    for (const glm::dvec2& q : c.points) {
      const glm::dvec3 p = nurbs::surface_point(f->surface, q.x, q.y);
      CHECK(std::abs(std::hypot(p.x, p.y) - (1 + p.z / 2)) < 1e-12);
    }
  // The loop's corners are the cone's points at the file's (u, v) corners.
  for (const glm::dvec2& q : kCorners) {
    double nearest = 1e300;
    for (const nurbs::Curve2& c : f->loops[0].curves)
      for (const glm::dvec2& st : c.points)
        nearest = std::min(nearest, glm::length(nurbs::surface_point(f->surface, st.x, st.y) - cone(q.x, q.y)));
    CHECK(nearest < 1e-12);
  }
  // The trimmed face has the strip's area: the grid's boundary cells bound the error near 1 / n of
  // the perimeter's share, well under 1 % at n = 400; a trim read as NURBS parameters (angle not
  // mapped) or a whole-surface face would be off by more.
  const double area = trimmed_area(*f, 400), exact = cone_area(kU0, kU1, kV0, kV1);
  CHECK(std::abs(area - exact) < 0.01 * exact);

  // N1 = 0: the whole cone between SA and TA, untrimmed.
  const nurbs::TrimmedSurface* w = find_face(m, file.whole);
  REQUIRE(w != nullptr);
  CHECK(w->loops.empty());
  const nurbs::Interval su = nurbs::surface_domain_u(w->surface), sv = nurbs::surface_domain_v(w->surface);
  CHECK(glm::length(nurbs::surface_point(w->surface, su.min, sv.min) - cone(0, kV0)) < 1e-12);
  CHECK(glm::length(nurbs::surface_point(w->surface, su.max, sv.max) - cone(1, kV1)) < 1e-12);
  const double whole = trimmed_area(*w, 400), whole_exact = cone_area(0, 1, kV0, kV1);
  CHECK(std::abs(whole - whole_exact) < 1e-3 * whole_exact);  // untrimmed: only the midpoint rule's error
}

TEST_CASE("IGES 144 over a 120 whose generatrix is an arc: the pcurves' u is the arc's angle") {
  using namespace revolution;
  // The arc of centre (2, 0), radius 1, from 60 to 120 degrees (IGES 100: parametrised by its angle
  // from the start angle on) turned about the z axis: S(a, v) = Rz(v) (2 + cos a, sin a, 0).
  const auto point = [](double a, double v) {
    const glm::dvec3 q(2 + std::cos(a), std::sin(a), 0.0);
    return glm::dvec3(q.x * std::cos(v) - q.y * std::sin(v), q.x * std::sin(v) + q.y * std::cos(v), 0.0);
  };
  const double a0 = std::numbers::pi / 3, a1 = 2 * std::numbers::pi / 3;
  IgesEdit e = base_file();
  const int axis = line(e, {0, 0, 0}, {0, 0, 1});
  const int arc = e.append(100, {"0", "2", "0", revolution::r(2 + std::cos(a0)), revolution::r(std::sin(a0)),
                                 revolution::r(2 + std::cos(a1)), revolution::r(std::sin(a1))});
  const int surface = e.append(120, {s(axis), s(arc), "0", revolution::r(2 * std::numbers::pi)});
  const double u0 = 1.2, u1 = 1.9, v0 = 0.5, v1 = 2.0;  // inside [a0, a1] x [0, 2 pi]
  const std::array<glm::dvec2, 4> c = {glm::dvec2{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
  check_corners(e, quadrilateral_face(e, surface, c), c, [&](glm::dvec2 q) { return point(q.x, q.y); });
}

TEST_CASE("IGES 144 over a 120 placed by a mirroring 124: the face is the mirror image of the turned one") {
  // The cone of `revolution` placed by the mirror x -> -x (a 124 of form 1, determinant -1, as
  // OpenCASCADE writes mirrored parts): the trim's corners at (u, v) land on the mirror of cone(u, v),
  // where turning the mirrored generatrix the right-handed way would put them at (x, -y) of that.
  using namespace revolution;
  IgesEdit e = base_file();
  const int surface = surface_120(e, 0.0, 2 * std::numbers::pi);
  const int mirror = e.append(124, {"-1", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1", "0"}, 1);
  e.set_de_field(surface, 7, mirror);
  check_corners(e, quadrilateral_face(e, surface, kCorners), kCorners,
                [](glm::dvec2 q) { return cone(q.x, q.y) * glm::dvec3(-1, 1, 1); });
}
