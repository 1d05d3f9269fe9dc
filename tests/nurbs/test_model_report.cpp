// The reader's report and what it does to the certificate (nurbs/model_report.h): dropped faces
// leave every answer uncertified unless the partial model is accepted; a face with an invalid trim
// leaves the answers within its reach uncertified; an edge gap widens the bounds within its reach.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <random>

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

namespace {

// The square [0, 10]^2 of z = 0 trimmed to [lo, hi]^2, its edges `gap` off.
nurbs::TrimmedSurface trimmed_square(double lo, double hi, double gap) {
  nurbs::TrimmedSurface square;
  square.surface = models::bilinear_square(10.0);
  const glm::dvec2 a(lo, lo), b(hi, lo), c(hi, hi), d(lo, hi);
  square.loops = {
      {{nurbs::segment_curve(a, b), nurbs::segment_curve(b, c), nurbs::segment_curve(c, d), nurbs::segment_curve(d, a)},
       true}};
  square.edge_gap = gap;
  return square;
}

// Distance from p to the rectangle [x0, x1] x [y0, y1] of z = 0, and its closest point.
std::pair<double, glm::dvec3> rectangle_distance(const glm::dvec3& p, double x0, double x1, double y0, double y1) {
  const glm::dvec3 c(std::clamp(p.x, x0, x1), std::clamp(p.y, y0, y1), 0.0);
  return {glm::length(p - c), c};
}

}  // namespace

TEST_CASE("model report: an edge gap widens the bounds by what it can change at the answer") {
  const nurbs::Model m = two_spheres("", 0.25);
  const nurbs::ModelReport r = nurbs::model_report(m);
  REQUIRE(r.edge_gaps.size() == 1);
  CHECK(r.largest_gap() == 0.25);
  CHECK(r.uncertified_reason(false).empty());
  CHECK(nurbs::FaceDoubts(nurbs::world_faces(m)).at(glm::dvec3(-2, 0, 0), 1.0, 1e-6).widen == 0.0);

  // The square trimmed to [2, 8]^2, its edges 0.25 off.
  nurbs::TrimmedSurface square = trimmed_square(2, 8, 0.25);
  const nurbs::FaceDoubts doubts(std::vector<nurbs::TrimmedSurface>{square});
  const auto witness = [](glm::dvec3 q) { return nurbs::FaceDoubts::Witness{q, 1e-6}; };
  CHECK(doubts.at(glm::dvec3(5, 5, 1), 1.0, 1e-6).widen == 0.0);  // the boundary 3.2 away
  // 0.5 above the face, the boundary 0.71 away: material the file may add there lies at least
  // 0.71 - 0.25 = 0.457 away, so the lower end moves by 0.043; the closest point (5, 2.5, 0) lies
  // 0.5 inside the boundary, farther than the gap: the upper end stays.
  const nurbs::FaceDoubts::Verdict above = doubts.at(glm::dvec3(5, 2.5, 0.5), 0.5, 1e-6, witness({5, 2.5, 0}));
  CHECK(above.widen == doctest::Approx(0.5 - 1e-6 + 0.25 - std::sqrt(0.5)).epsilon(1e-3));
  CHECK(above.gap_face == 0);
  CHECK(above.gap == 0.25);
  // Without the closest point, the upper end must allow for a closest point beside the boundary.
  CHECK(doubts.at(glm::dvec3(5, 2.5, 0.5), 0.5, 1e-6).widen == 0.25);
  // The closest point on the boundary itself: the file may have cut it away.
  CHECK(doubts.at(glm::dvec3(5, -1, 0), 3.0, 1e-6, witness({5, 2, 0})).widen == 0.25);
  // Within the gap of the boundary, inside.
  CHECK(doubts.at(glm::dvec3(5, 2.1, 1), 1.0, 1e-6, witness({5, 2.1, 0})).widen == 0.25);
  // Untrimmed, the domain's sides are its boundary.
  square.loops.clear();
  const nurbs::FaceDoubts whole(std::vector<nurbs::TrimmedSurface>{square});
  CHECK(whole.at(glm::dvec3(5, 5, 1), 1.0, 1e-6).widen == 0.0);
  CHECK(whole.at(glm::dvec3(5, 0.2, 0.5), 0.5, 1e-6, witness({5, 0.2, 0})).widen == 0.25);
  CHECK(whole.at(glm::dvec3(5, 3, 0.5), 0.5, 1e-6, witness({5, 3, 0})).widen == 0.0);
}

TEST_CASE("model report: the widened bound holds the distance to faces whose edges lie off by known gaps") {
  // The file's face: our trimmed square with each side moved in its plane, in or out, by up to
  // g / sqrt(2), so that its edges lie within g of ours, corners included (what a gap g allows).
  // Its distance, exact, against ours widened by the rule, with and without the closest point, at
  // random points about the face. A widening short of what the gap changes fails; so does one as blunt as the whole gap
  // wherever the boundary is within reach (counted against the answers it must widen).
  std::mt19937 rng(55);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long long reachable = 0, checked = 0;
  double widened = 0.0;  // over those answers, the sum of w / g
  for (int model = 0; model < 40; ++model) {
    const double lo = 1 + 2 * unit(rng), hi = 7 + 2 * unit(rng), gap = 0.01 + 0.5 * unit(rng);
    const nurbs::FaceDoubts doubts(std::vector<nurbs::TrimmedSurface>{trimmed_square(lo, hi, gap)});
    for (int trial = 0; trial < 8; ++trial) {
      double off[4];
      for (double& o : off) o = gap / std::sqrt(2.0) * (2 * unit(rng) - 1);
      const double x0 = lo - off[0], x1 = hi + off[1], y0 = lo - off[2], y1 = hi + off[3];
      for (int i = 0; i < 200; ++i) {
        // Mostly over the face, some beside it; heights skewed towards it.
        const glm::dvec3 p(lo - 1 + (hi - lo + 2) * unit(rng), lo - 1 + (hi - lo + 2) * unit(rng),
                           3 * (2 * unit(rng) - 1) * unit(rng));
        const auto [d, closest] = rectangle_distance(p, lo, hi, lo, hi);
        const double file = rectangle_distance(p, x0, x1, y0, y1).first;
        const double b = 1e-9;  // the answer's own bound (the distance above is exact)
        const double w = doubts.at(p, d, b, nurbs::FaceDoubts::Witness{closest, 0.0}).widen;
        const double blind = doubts.at(p, d, b).widen;
        CHECK(w <= blind);
        // Rounding of the sampled boundary and the distances: 1e-12 of the square's size.
        CHECK(std::abs(file - d) <= b + w + 1e-11);
        CHECK(std::abs(file - d) <= b + blind + 1e-11);
        ++checked;
        // Over the face (beside it the closest point is on the boundary, where the whole gap counts):
        // the boundary's distance over the face's nearest side.
        const double side = std::min({p.x - lo, hi - p.x, p.y - lo, hi - p.y});
        if (side > 0.0 && std::hypot(p.z, side) <= d + b + 2 * gap) ++reachable, widened += w / gap;
      }
    }
  }
  CHECK(checked == 40 * 8 * 200);
  // The answers over the face that the whole gap widened (a boundary within d + b + 2 g) are widened
  // by about half the gap on average (0.51 with this seed), the whole-gap rule by all of it.
  MESSAGE(reachable, " answers over the face within the whole-gap rule's reach, widened by ", widened / double(reachable),
          " of the gap on average");
  CHECK(widened < 0.6 * double(reachable));
}
