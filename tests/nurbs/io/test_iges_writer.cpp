// Writer round trips: sample model and shared models read back bit-identical; orientation and
// domain-loop rules of the reader on written files.
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>

#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/trim_classify.h"
#include "sample_models.h"
#include "shared_models.h"

namespace fs = std::filesystem;
using nurbs::Model;

namespace {

std::vector<const nurbs::TrimmedSurface*> faces(const Model& m) {
  std::vector<const nurbs::TrimmedSurface*> out;
  for (const auto& b : m.bodies)
    for (const auto& f : b.faces) out.push_back(&f);
  return out;
}

template <int D>
void check_same_curve(const nurbs::Curve<D>& a, const nurbs::Curve<D>& b) {
  CHECK(a.degree == b.degree);
  CHECK(a.knots == b.knots);
  CHECK(a.points == b.points);
  CHECK(a.weights == b.weights);
}

// Exact equality: the writer prints the shortest text that reads back to the same double.
void check_same(const Model& a, const Model& b) {
  const auto fa = faces(a), fb = faces(b);
  REQUIRE(fa.size() == fb.size());
  for (size_t i = 0; i < fa.size(); ++i) {
    CAPTURE(i);
    const auto &s = fa[i]->surface, &t = fb[i]->surface;
    CHECK(s.degree_u == t.degree_u);
    CHECK(s.degree_v == t.degree_v);
    CHECK(s.knots_u == t.knots_u);
    CHECK(s.knots_v == t.knots_v);
    CHECK(s.points == t.points);
    CHECK(s.weights == t.weights);
    REQUIRE(fa[i]->loops.size() == fb[i]->loops.size());
    for (size_t k = 0; k < fa[i]->loops.size(); ++k) {
      CHECK(fa[i]->loops[k].outer == fb[i]->loops[k].outer);
      REQUIRE(fa[i]->loops[k].curves.size() == fb[i]->loops[k].curves.size());
      for (size_t c = 0; c < fa[i]->loops[k].curves.size(); ++c)
        check_same_curve(fa[i]->loops[k].curves[c], fb[i]->loops[k].curves[c]);
    }
  }
}

}  // namespace

TEST_CASE("IGES writer: sample model round trip is exact") {
  const Model m = nurbs::io::test::small_model();
  nurbs::io::IgesReadLog log;
  const Model r = nurbs::io::read_iges_text(nurbs::io::write_iges_text(m, "small.igs"), "small.igs", {}, &log);
  check_same(m, r);
  CHECK(log.reoriented_loops == 0);
  CHECK(r.unit_scale_to_mm == 1.0);
  CHECK(r.skipped_entities.empty());
}

TEST_CASE("IGES writer: units, body transforms, bad input") {
  Model m = nurbs::io::test::small_model();
  m.unit_scale_to_mm = 25.4;
  m.bodies[0].transform[3] = glm::dvec4(0.0, 0.0, 5.0, 1.0);  // +5 in z, baked into the points
  const Model r = nurbs::io::read_iges_text(nurbs::io::write_iges_text(m), "in.igs");
  CHECK(r.unit_scale_to_mm == 25.4);
  CHECK(r.resolution == 1e-7);  // G19 as written, in file units
  nurbs::io::IgesReadOptions to_mm;
  to_mm.convert_to_mm = true;
  CHECK(nurbs::io::read_iges_text(nurbs::io::write_iges_text(m), "in.igs", to_mm).resolution ==
        doctest::Approx(2.54e-6));
  CHECK(faces(r)[0]->surface.points[0] == glm::dvec3(2.0, 0.0, 5.0));  // exact: small integers
  m.unit_scale_to_mm = 3.0;
  CHECK_THROWS_AS(nurbs::io::write_iges_text(m), std::invalid_argument);
  m.unit_scale_to_mm = 1.0;
  m.bodies[0].faces[0].loops[1].outer = true;
  CHECK_THROWS_AS(nurbs::io::write_iges_text(m), std::invalid_argument);
}

TEST_CASE("IGES reader: holes only get a domain loop; wrong orientation is fixed") {
  Model m = nurbs::io::test::small_model();
  auto& f = m.bodies[0].faces[0];
  f.loops = {nurbs::io::test::circle_hole(0.2, false)};  // counter-clockwise hole, no outer loop
  nurbs::io::IgesReadLog log;
  const Model r = nurbs::io::read_iges_text(nurbs::io::write_iges_text(m), "holes.igs", {}, &log);
  CHECK(log.domain_loops_added == 1);
  CHECK(log.reoriented_loops == 1);
  const auto& loops = faces(r)[0]->loops;
  REQUIRE(loops.size() == 2);
  CHECK(loops[0].outer);
  // Shoelace area of the flattened loops: the square is exact (lines). The circle's polygon has its
  // vertices on the circle and its chords within the flattening tolerance s = 1e-4 of it, so it lies
  // between the circles of radius r and r - s: a relative area deficit in [0, 2 s / r] = [0, 1e-3]
  // (measured: 4.0e-4, 128 vertices). Clockwise: negative area.
  const nurbs::TrimPolygons polys = nurbs::flatten_trim(*faces(r)[0], 1e-4);
  CHECK(nurbs::signed_area(polys.loops[0]) == doctest::Approx(1.0).epsilon(1e-12));
  const double hole = -nurbs::signed_area(polys.loops[1]), disc = 3.14159265358979 * 0.2 * 0.2;
  CHECK(hole <= disc);
  CHECK(hole >= disc * (1.0 - 2.0 * 1e-4 / 0.2));
}

TEST_CASE("IGES writer: shared models round trip exactly" * test::needs_shared_models()) {
  const fs::path dir = test::shared_models_dir();
  for (const char* name : {"iges/occt_bearing.iges", "iges/occt_hammer.iges", "generated/vase_shell_t2.igs"}) {
    CAPTURE(std::string(name));
    const Model m = nurbs::io::read_iges(dir / name);
    check_same(m, nurbs::io::read_iges_text(nurbs::io::write_iges_text(m), "copy.igs"));
  }
}
