// IGES 108 bounded plane (form 1, IGES 5.3 §4.8) as a face: a bilinear patch in the plane with the
// boundary curve as its outer loop, mapped exactly; classification of surface points against the
// exact boundary (a circle), a transform, and the errors of a boundary off the plane; a 144 trimmed
// surface over an unbounded 108, trimmed by its model-space curves.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "iges_edit.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/io/read_error.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "sample_models.h"

using nurbs::io::test::IgesEdit;

namespace {

/// A file holding one 128 (from the writer) plus a bounded plane z = 2 (or z = `zt` for its circle)
/// bounded by the unit circle about the z axis; the plane made independent (status 0).
IgesEdit plane_file(double zt, int& plane) {
  nurbs::Model m;
  m.bodies.push_back({"b", {}, glm::dmat4(1.0), ""});
  nurbs::TrimmedSurface f;
  f.surface = nurbs::io::test::bump();
  m.bodies[0].faces.push_back(f);
  IgesEdit e = IgesEdit::parse(nurbs::io::write_iges_text(m));
  const int circle = e.append(100, {std::to_string(zt), "0.", "0.", "1.", "0.", "1.", "0."});
  plane = e.append(108, {"0.", "0.", "1.", "2.", std::to_string(circle), "0.", "0.", "0.", "0."}, 1);
  e.set_de_field(plane, 9, 0);
  return e;
}

const nurbs::TrimmedSurface* find_face(const nurbs::Model& m, int de) {
  for (const auto& b : m.bodies)
    for (const auto& f : b.faces)
      if (f.face_id == de) return &f;
  return nullptr;
}

}  // namespace

TEST_CASE("IGES 108: a bounded plane is a face whose material is inside its boundary") {
  int plane = 0;
  IgesEdit e = plane_file(2.0, plane);
  // Also under a transform: +90 degrees about z and +5 in z (the disc maps onto itself, lifted).
  for (bool moved : {false, true}) {
    if (moved) {
      const int xf = e.append(124, {"0.", "-1.", "0.", "0.", "1.", "0.", "0.", "0.", "0.", "0.", "1.", "5."});
      e.set_de_field(plane, 7, xf);
    }
    const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "plane.igs");
    const nurbs::TrimmedSurface* f = find_face(m, plane);
    CAPTURE(moved);
    REQUIRE(f != nullptr);
    REQUIRE(f->loops.size() == 1);
    CHECK(f->loops[0].outer);
    const double z = moved ? 7.0 : 2.0;
    const nurbs::Interval du = nurbs::surface_domain_u(f->surface), dv = nurbs::surface_domain_v(f->surface);
    CHECK(du.width() == doctest::Approx(2.0));  // the circle's box
    const nurbs::TrimPolygons trim = nurbs::flatten_trim(*f, 1e-6);
    int inside = 0, checked = 0;
    for (int j = 0; j <= 20; ++j)
      for (int i = 0; i <= 20; ++i) {
        const glm::dvec2 uv(du.min + du.width() * (i + 0.5) / 21, dv.min + dv.width() * (j + 0.5) / 21);
        const glm::dvec3 p = nurbs::surface_point(f->surface, uv.x, uv.y);
        CHECK(p.z == doctest::Approx(z).epsilon(1e-12));
        const double r = std::hypot(p.x, p.y);
        if (std::abs(r - 1.0) < 1e-3) continue;  // within the flattening of the circle
        CHECK(nurbs::is_material(trim, uv) == (r < 1.0));
        inside += r < 1.0 ? 1 : 0;
        ++checked;
      }
    CHECK(inside > 100);
    CHECK(checked > 400);
    // The face's normal Su x Sv is the plane's (A, B, C) = +z.
    const auto d = nurbs::surface_derivatives(f->surface, du.min + 0.5 * du.width(), dv.min + 0.5 * dv.width());
    CHECK(glm::cross(d.su, d.sv).z > 0);
  }
}

TEST_CASE("IGES 108: a boundary off the plane is refused, naming the entity") {
  int plane = 0;
  IgesEdit e = plane_file(2.5, plane);  // the circle lies in z = 2.5, the plane is z = 2
  try {
    (void)nurbs::io::read_iges_text(e.text(), "plane.igs");
    FAIL("expected a ReadError");
  } catch (const nurbs::io::ReadError& err) {
    const std::string what = err.what();
    CAPTURE(what);
    CHECK(what.find("type 108") != std::string::npos);
    CHECK(what.find("off the plane") != std::string::npos);
  }
}

TEST_CASE("IGES 144 over a 108 plane: its loops are its model-space curves on the plane") {
  // The plane z = 2 (unbounded, form 0, as OpenCASCADE writes a face's plane) trimmed by the square
  // [-1, 1]^2 and a hole of radius 0.5 about the z axis, given by model-space curves only (142: BPTR
  // = 0, PREF = 2): IGES gives a plane no parameters.
  int plane = 0;
  IgesEdit e = plane_file(2.0, plane);
  const int unbounded = e.append(108, {"0.", "0.", "1.", "2.", "0", "0.", "0.", "0.", "0."});
  const glm::dvec2 c[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  std::vector<std::string> sides{"4"};
  for (int k = 0; k < 4; ++k) {
    const glm::dvec2 a = c[k], b = c[(k + 1) % 4];
    sides.push_back(std::to_string(e.append(110, {fmt::format("{}", a.x), fmt::format("{}", a.y), "2.",
                                                  fmt::format("{}", b.x), fmt::format("{}", b.y), "2."})));
  }
  const int square = e.append(102, sides);
  const int hole = e.append(100, {"2.", "0.", "0.", "0.5", "0.", "0.5", "0."});
  const int outer = e.append(142, {"0", std::to_string(unbounded), "0", std::to_string(square), "2"});
  const int inner = e.append(142, {"0", std::to_string(unbounded), "0", std::to_string(hole), "2"});
  const int face = e.append(144, {std::to_string(unbounded), "1", "1", std::to_string(outer), std::to_string(inner)});
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "plane_144.igs", {}, &log);
  CHECK(m.dropped_faces.empty());
  CHECK(log.trim_problems.empty());
  const nurbs::TrimmedSurface* f = find_face(m, face);
  REQUIRE(f != nullptr);
  REQUIRE(f->loops.size() == 2);
  CHECK(f->edge_gap < 1e-12);
  const nurbs::Interval du = nurbs::surface_domain_u(f->surface), dv = nurbs::surface_domain_v(f->surface);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(*f, 1e-6);
  int inside = 0, checked = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const glm::dvec2 uv(du.min + du.width() * (i + 0.5) / 40, dv.min + dv.width() * (j + 0.5) / 40);
      const glm::dvec3 p = nurbs::surface_point(f->surface, uv.x, uv.y);
      CHECK(p.z == doctest::Approx(2.0).epsilon(1e-12));
      const double r = std::hypot(p.x, p.y), box = std::max(std::abs(p.x), std::abs(p.y));
      if (std::abs(r - 0.5) < 1e-3 || std::abs(box - 1.0) < 1e-3) continue;
      CHECK(nurbs::is_material(trim, uv) == (r > 0.5 && box < 1.0));
      inside += r > 0.5 && box < 1.0;
      ++checked;
    }
  CHECK(inside > 800);
  CHECK(checked > 1500);
  const auto d = nurbs::surface_derivatives(f->surface, du.min + 0.5 * du.width(), dv.min + 0.5 * dv.width());
  CHECK(glm::cross(d.su, d.sv).z > 0);

  // A 142 on the plane with a parameter-space curve and no model-space one: dropped, saying why.
  const int given = e.append(142, {"0", std::to_string(unbounded), std::to_string(square), "0", "1"});
  const int no_model = e.append(144, {std::to_string(unbounded), "1", "0", std::to_string(given)});
  const nurbs::Model d2 = nurbs::io::read_iges_text(e.text(), "plane_144.igs", {}, nullptr);
  REQUIRE(d2.dropped_faces.size() == 1);
  CHECK(d2.dropped_faces[0].entity == fmt::format("D{}", no_model));
  CHECK(d2.dropped_faces[0].reason.find("is a 108 plane, which IGES gives no parameters") != std::string::npos);
}
