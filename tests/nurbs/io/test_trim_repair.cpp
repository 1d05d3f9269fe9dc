// The reader's trim repair: gaps between trim curves up to kTrimGapRepair of the trim extent are
// closed and counted; larger gaps and crossing loops are reported naming the face; rounding-level
// gaps are left alone (so round trips stay exact).
#include <doctest/doctest.h>

#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
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

  const io::IgesReadLog large = read_back(with_gap(2e-2));
  CHECK(large.gaps_closed == 0);
  REQUIRE(large.trim_problems.size() >= 1);
  CHECK(large.trim_problems[0].rfind("face ", 0) == 0);  // names the face (its IGES directory entry)
  CHECK(large.trim_problems[0].find("does not close") != std::string::npos);
}

TEST_CASE("IGES reader: crossing loops are reported, not silently accepted") {
  Model m = io::test::small_model();
  // A hole that pokes out of the outer square: the loops cross.
  m.bodies[0].faces[0].loops[1] = io::test::circle_hole(0.7, true);
  const io::IgesReadLog log = read_back(m);
  REQUIRE(!log.trim_problems.empty());
  CHECK(log.trim_problems[0].find("cross") != std::string::npos);
}
