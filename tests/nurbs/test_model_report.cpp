// The reader's report and what it does to the certificate (nurbs/model_report.h): dropped faces
// leave every answer uncertified unless the partial model is accepted; a face with an invalid trim
// leaves the answers within its reach uncertified; an edge gap widens the bounds within its reach.
#include <doctest/doctest.h>

#include "models/exact_shapes.h"
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
  CHECK(doubts.any().invalid_face == 1);
  // A box far from the second sphere, and one that reaches it.
  CHECK(doubts.near({glm::dvec3(-5, -1, -1), glm::dvec3(-4, 1, 1)}, 2.0).reason.empty());
  CHECK(!doubts.near({glm::dvec3(-5, -1, -1), glm::dvec3(-4, 1, 1)}, 13.0).reason.empty());
}

TEST_CASE("model report: an edge gap widens the bounds within its reach by the gap") {
  const nurbs::Model m = two_spheres("", 0.25);
  const nurbs::ModelReport r = nurbs::model_report(m);
  REQUIRE(r.edge_gaps.size() == 1);
  CHECK(r.largest_gap() == 0.25);
  CHECK(r.uncertified_reason(false).empty());
  const nurbs::FaceDoubts doubts(nurbs::world_faces(m));
  CHECK(doubts.at(glm::dvec3(-2, 0, 0), 1.0, 1e-6).widen == 0.0);
  const nurbs::FaceDoubts::Verdict v = doubts.at(glm::dvec3(12, 0, 0), 1.0, 1e-6);
  CHECK(v.widen == 0.25);
  CHECK(v.reason.empty());
  // Within reach only through the gap itself: the second sphere's box starts at x = 9 (control
  // points of the rational sphere lie on its bounding cube), 0.2 beyond a reach of 8.8.
  CHECK(doubts.at(glm::dvec3(0, 0, 0), 8.75, 0.05).widen == 0.25);
  CHECK(doubts.at(glm::dvec3(0, 0, 0), 8.0, 0.05).widen == 0.0);
}
