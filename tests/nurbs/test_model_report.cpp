// The reader's report and what it does to the certificate (nurbs/model_report.h): dropped faces
// leave every answer uncertified unless the partial model is accepted; a face with an invalid trim
// leaves the answers within its reach uncertified; an edge gap widens the bounds within its reach.
#include <doctest/doctest.h>

#include "models/exact_shapes.h"
#include "nurbs/curve_ends.h"
#include "nurbs/model_report.h"

namespace {

// Two spheres of radius 1, at x = 0 and x = 10; the second's face flagged as the test needs.
nurbs::Model two_spheres(const std::string& trim_problem, double edge_gap) {
  nurbs::Model m;
  m.source = "two.igs";
  nurbs::TrimmedSurface a, b;
  a.surface = models::rational_sphere(1.0), a.face_id = 11;
  b.surface = models::rational_sphere(1.0, glm::dvec3(10, 0, 0)), b.face_id = 12;
  b.trim_problem = trim_problem;
  b.edge_gap = edge_gap;
  m.bodies.push_back({"body", {a, b}, glm::dmat4(1.0), {}});
  m.faces_in_file = 2;
  return m;
}

}  // namespace

TEST_CASE("model report: dropped faces leave answers uncertified unless the partial model is accepted") {
  nurbs::Model m = two_spheres("", 0.0);
  CHECK(!nurbs::model_report(m).changed());
  CHECK(nurbs::model_report(m).uncertified_reason(false).empty());
  CHECK(nurbs::model_report(m).invalid_trim_reason().empty());
  m.faces_in_file = 3;
  m.dropped_faces.push_back({"D7", "it needs D9 of unsupported type 120"});
  const nurbs::ModelReport r = nurbs::model_report(m);
  CHECK(r.partial());
  CHECK(r.faces_read == 2);
  const std::string why = r.uncertified_reason(false);
  CHECK(why.find("dropped 1 of 3 faces of two.igs") != std::string::npos);
  CHECK(r.uncertified_reason(true).empty());
  const std::vector<std::string> lines = r.lines();
  REQUIRE(lines.size() == 2);
  CHECK(lines[0] == "1 of 3 faces of the file dropped by the reader");
  CHECK(lines[1] == "  face D7 dropped: it needs D9 of unsupported type 120");
}

TEST_CASE("model report: a face with an invalid trim uncertifies only the answers it may hold") {
  const nurbs::Model m = two_spheres("loop 0 crosses itself", 0.0);
  const nurbs::ModelReport r = nurbs::model_report(m);
  REQUIRE(r.invalid_trims.size() == 1);
  CHECK(r.invalid_trims[0].face == 1);
  CHECK(r.invalid_trims[0].face_id == 12);
  const nurbs::FaceDoubts doubts(nurbs::world_faces(m));
  // Near the first sphere: its distance 1 +- 1e-6 cannot reach the second's box (x >= 9 - slack).
  const nurbs::FaceDoubts::Verdict near_a = doubts.at(glm::dvec3(-2, 0, 0), 1.0, 1e-6);
  CHECK(near_a.invalid_face == -1);
  CHECK(near_a.reason.empty());
  // Between the two, the first sphere answers 4.5 but the second's box lies 3.5 away.
  const nurbs::FaceDoubts::Verdict between = doubts.at(glm::dvec3(5.5, 0, 0), 4.5, 1e-6);
  CHECK(between.invalid_face == 1);
  CHECK(between.reason.find("loop 0 crosses itself") != std::string::npos);
  CHECK(r.invalid_trim_reason().find("face 1 (id 12)") != std::string::npos);
  CHECK(r.invalid_trim_reason().find("loop 0 crosses itself") != std::string::npos);
  // A box far from the second sphere, and one that reaches it.
  CHECK(doubts.near({glm::dvec3(-5, -1, -1), glm::dvec3(-4, 1, 1)}, 2.0).reason.empty());
  CHECK(!doubts.near({glm::dvec3(-5, -1, -1), glm::dvec3(-4, 1, 1)}, 13.0).reason.empty());
}

TEST_CASE("model report: an edge gap widens the bounds whose answers its boundary may reach") {
  const nurbs::Model m = two_spheres("", 0.25);
  const nurbs::ModelReport r = nurbs::model_report(m);
  REQUIRE(r.edge_gaps.size() == 1);
  CHECK(r.largest_gap() == 0.25);
  CHECK(r.uncertified_reason(false).empty());
  CHECK(nurbs::FaceDoubts(nurbs::world_faces(m)).at(glm::dvec3(-2, 0, 0), 1.0, 1e-6).widen == 0.0);

  // The square [0, 10]^2 of z = 0 trimmed to [2, 8]^2, its edges 0.25 off: the file's edge may lie
  // nearer than an answer only where the trim boundary is within the answer's reach plus twice the gap.
  nurbs::TrimmedSurface square;
  square.surface = models::bilinear_square(10.0);
  const glm::dvec2 a(2, 2), b(8, 2), c(8, 8), d(2, 8);
  square.loops = {
      {{nurbs::segment_curve(a, b), nurbs::segment_curve(b, c), nurbs::segment_curve(c, d), nurbs::segment_curve(d, a)},
       true}};
  square.edge_gap = 0.25;
  const nurbs::FaceDoubts doubts(std::vector<nurbs::TrimmedSurface>{square});
  CHECK(doubts.at(glm::dvec3(5, 5, 1), 1.0, 1e-6).widen == 0.0);       // the boundary 3.2 away
  CHECK(doubts.at(glm::dvec3(5, 2.5, 0.5), 0.5, 1e-6).widen == 0.25);  // 0.71 away: within 0.5 + 0.5
  CHECK(doubts.at(glm::dvec3(5, -1, 0), 3.0, 1e-6).widen == 0.25);     // beyond the trim, 3 from it
  // Untrimmed, the domain's sides are its boundary.
  square.loops.clear();
  const nurbs::FaceDoubts whole(std::vector<nurbs::TrimmedSurface>{square});
  CHECK(whole.at(glm::dvec3(5, 5, 1), 1.0, 1e-6).widen == 0.0);
  CHECK(whole.at(glm::dvec3(5, 0.2, 0.5), 0.5, 1e-6).widen == 0.25);
}
