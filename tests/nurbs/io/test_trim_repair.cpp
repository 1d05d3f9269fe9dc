// The reader's repairs and range handling: declared 128 ranges bound untrimmed faces;
// trim repair: gaps between trim curves up to kTrimGapRepair of the trim extent are
// closed and counted; larger ones bridged up to the edge gap a face may keep, beyond it reported
// naming the face, as crossing loops are; rounding-level
// gaps are left alone (so round trips stay exact).
#include <doctest/doctest.h>

#include <array>
#include <glm/geometric.hpp>

#include "iges_edit.h"
#include "nurbs/io/iges_faces.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/surface_eval.h"
#include "sample_models.h"

namespace {

using namespace nurbs;

/// The sample model with the end of the outer square's first edge moved by `gap` along v.
Model with_gap(double gap) {
  Model m = io::test::small_model();
  Curve2& c = m.bodies[0].faces[0].loops[0].curves[0];
  c.points.back().y += gap;
  return m;
}

io::IgesReadLog read_back(const Model& m) {
  io::IgesReadLog log;
  (void)io::read_iges_text(io::write_iges_text(m, "gap.igs"), "gap.igs", {}, &log);
  return log;
}

}  // namespace

TEST_CASE("IGES reader: small trim gaps are closed and counted, large ones reported") {
  // Trim extent of the sample face is 1 (the unit square), so the repair limit is 1e-4.
  const io::IgesReadLog none = read_back(with_gap(0.0));
  CHECK(none.gaps_closed == 0);
  CHECK(none.trim_problems.empty());

  const io::IgesReadLog small = read_back(with_gap(3e-5));
  CHECK(small.gaps_closed == 1);
  CHECK(small.trim_problems.empty());

  // A larger gap, a short bridge on the surface (a missing edge), is bridged as OpenCASCADE's healing
  // does, its length the face's edge gap; one whose bridge would exceed the edge gap a face may keep
  // (0.15 of its size) is reported.
  const io::IgesReadLog bridged = read_back(with_gap(2e-2));
  CHECK(bridged.gaps_closed == 1);
  CHECK(bridged.trim_problems.empty());
  const Model r = io::read_iges_text(io::write_iges_text(with_gap(2e-2), "gap.igs"), "gap.igs");
  CHECK(r.bodies[0].faces[0].edge_gap > 0.0);
  const io::IgesReadLog large = read_back(with_gap(0.4));
  CHECK(large.gaps_closed == 0);
  REQUIRE(large.trim_problems.size() >= 1);
  CHECK(large.trim_problems[0].rfind("face ", 0) == 0);  // names the face (its IGES directory entry)
  CHECK(large.trim_problems[0].find("does not close") != std::string::npos);
}

TEST_CASE("IGES reader: a closed trim gap moves the face's boundary by its width in space: the edge gap") {
  // Without a gap the face's edges are its curves (gap 0); a gap of 3e-5 in v closed by the repair
  // moves the boundary by the surface's stretch times it, which the face's edge gap must carry.
  const Model exact = io::read_iges_text(io::write_iges_text(with_gap(0.0), "gap.igs"), "gap.igs");
  CHECK(exact.bodies[0].faces[0].edge_gap == 0.0);
  const Model m = with_gap(3e-5);
  const Model r = io::read_iges_text(io::write_iges_text(m, "gap.igs"), "gap.igs");
  const TrimmedSurface& f = m.bodies[0].faces[0];
  const glm::dvec2 a = f.loops[0].curves[0].points.back(), b = f.loops[0].curves[1].points.front();
  const double width = glm::length(surface_point(f.surface, a.x, a.y) - surface_point(f.surface, b.x, b.y));
  REQUIRE(width > 0.0);
  CHECK(r.bodies[0].faces[0].edge_gap == doctest::Approx(width).epsilon(1e-6));
}

TEST_CASE("IGES reader: crossing loops are reported, not silently accepted") {
  Model m = io::test::small_model();
  // A hole that pokes out of the outer square: the loops cross.
  m.bodies[0].faces[0].loops[1] = io::test::circle_hole(0.7, true);
  const io::IgesReadLog log = read_back(m);
  REQUIRE(!log.trim_problems.empty());
  CHECK(log.trim_problems[0].find("cross") != std::string::npos);
}

namespace {

/// The writer's text with the parameter range (last four fields) of every 128 set to `range`.
std::string with_surface_range(const Model& m, const std::array<std::string, 4>& range) {
  io::test::IgesEdit e = io::test::IgesEdit::parse(io::write_iges_text(m, "range.igs"));
  for (auto& ent : e.entities)
    if (!ent.fields.empty() && ent.fields[0] == "128")
      for (size_t k = 0; k < 4; ++k) ent.fields[ent.fields.size() - 4 + k] = range[k];
  return e.text();
}

/// One untrimmed face, the bump.
Model bare_bump() {
  Model bare;
  TrimmedSurface bump;
  bump.surface = io::test::bump();
  bare.bodies.push_back({"b", {bump}, glm::dmat4(1.0), ""});
  return bare;
}

}  // namespace

TEST_CASE("IGES reader: a declared 128 range bounds an untrimmed face, not a trimmed one") {
  const Model bare = bare_bump();
  io::IgesReadLog log;
  const Model r = io::read_iges_text(with_surface_range(bare, {"0.25", "0.75", "0.1", "0.9"}), "range.igs", {}, &log);
  CHECK(log.ranges_restricted == 1);
  const Surface& s = r.bodies[0].faces[0].surface;
  CHECK(surface_domain_u(s).min == 0.25);
  CHECK(surface_domain_u(s).max == 0.75);
  CHECK(surface_domain_v(s).min == 0.1);
  CHECK(surface_domain_v(s).max == 0.9);
  // Same surface on the range: the restriction only re-represents it (1e-14: a few roundings).
  CHECK(glm::length(surface_point(s, 0.3, 0.8) - surface_point(io::test::bump(), 0.3, 0.8)) < 1e-14);

  // The sample model: face 0 has an outer loop, which bounds it, so its surface stays whole; face 1
  // (the bump, untrimmed) is cut to the range.
  io::IgesReadLog log2;
  const Model t = io::read_iges_text(with_surface_range(io::test::small_model(), {"0.25", "0.75", "0.1", "0.9"}),
                                     "r.igs", {}, &log2);
  CHECK(log2.ranges_restricted == 1);
  CHECK(surface_domain_u(t.bodies[0].faces[0].surface).min == 0.0);
  CHECK(surface_domain_u(t.bodies[0].faces[1].surface).min == 0.25);
}

TEST_CASE("IGES reader: an empty declared 128 range keeps the knot domain, with a warning") {
  const Model bare = bare_bump();
  io::IgesReadLog log;
  const Model r = io::read_iges_text(with_surface_range(bare, {"0.5", "0.5", "0.1", "0.9"}), "empty.igs", {}, &log);
  CHECK(log.ranges_restricted == 0);
  REQUIRE(r.bodies.size() == 1);
  const Surface& s = r.bodies[0].faces[0].surface;
  CHECK(surface_domain_u(s).min == surface_domain_u(io::test::bump()).min);
  CHECK(surface_domain_v(s).max == surface_domain_v(io::test::bump()).max);
  REQUIRE(r.read_warnings.size() == 1);
  CHECK(r.read_warnings[0].rfind("line ", 0) == 0);
  CHECK(r.read_warnings[0].find("(type 128)") != std::string::npos);
  CHECK(r.read_warnings[0].find("parameter range [0.5, 0.5] x [0.1, 0.9] is empty") != std::string::npos);
}

TEST_CASE("trim loops: a curve whose knots do not fit its points is said, never evaluated, and its face dropped") {
  // A bump's face with a loop whose one curve has 4 points of degree 3 and 20 knots (a clamped cut
  // of a longer curve gone wrong): the repairs and the flattening would read its points past the
  // end (AddressSanitizer: heap-buffer-overflow).
  nurbs::TrimmedSurface f;
  f.surface = nurbs::io::test::bump();
  nurbs::Curve2 c;
  c.degree = 3;
  c.points = {{0.2, 0.2}, {0.8, 0.2}, {0.8, 0.8}, {0.2, 0.2}};
  for (int i = 0; i < 20; ++i) c.knots.push_back(i < 4 ? 0.0 : (i < 16 ? (i - 3) / 13.0 : 1.0));
  nurbs::TrimLoop loop;
  loop.outer = true;
  loop.curves.push_back(c);
  f.loops.push_back(loop);
  nurbs::io::IgesReadLog log;
  nurbs::io::finish_trim_loops(f, 1.0, log);
  CHECK(f.trim_problem.find("knots") != std::string::npos);
  CHECK(!nurbs::io::trims_evaluable(f));
  CHECK(log.reoriented_loops == 0);
}
