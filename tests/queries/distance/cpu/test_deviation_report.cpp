// The deviation report of a scan (queries/distance/deviation_report.h): the summary, the share of
// points within each tolerance (and how many are so certainly or possibly, their bounds included),
// and the colours of the coloured point cloud.
#include <doctest/doctest.h>

#include <cmath>

#include "queries/distance/deviation_report.h"

namespace {

queries::PointQueryResult answers(const std::vector<double>& distances, double bound) {
  queries::PointQueryResult r;
  for (const double d : distances) {
    queries::PointDistance a;
    a.found = std::isfinite(d);
    a.distance = std::abs(d);
    a.bound = bound;
    r.answers.push_back(a);
    r.signed_distance.push_back(a.found ? d : std::nan(""));
  }
  r.reasons.resize(r.answers.size());
  return r;
}

}  // namespace

TEST_CASE("deviation report: shares within each tolerance, with the bounds' certain and possible counts") {
  // Deviations -0.3, -0.05, 0.0, 0.099, 0.2, not found; bounds 0.002.
  const queries::PointQueryResult r = answers({-0.3, -0.05, 0.0, 0.099, 0.2, std::nan("")}, 0.002);
  const std::vector<double> within{0.25, 0.1};
  const queries::DeviationReport rep = queries::deviation_report(r, within);
  CHECK(rep.signed_values);
  CHECK(rep.found == 5);
  CHECK(rep.min == -0.3);
  CHECK(rep.max == 0.2);
  CHECK(rep.mean == doctest::Approx((-0.3 - 0.05 + 0.099 + 0.2) / 5));
  REQUIRE(rep.bands.size() == 2);
  CHECK(rep.bands[0].within == 0.1);  // ascending
  CHECK(rep.bands[0].points == 3);    // -0.05, 0, 0.099
  CHECK(rep.bands[0].certain == 2);   // 0.099 + 0.002 > 0.1
  CHECK(rep.bands[0].possible == 3);
  CHECK(rep.bands[0].share == doctest::Approx(0.6));
  CHECK(rep.bands[1].points == 4);
  CHECK(std::isnan(rep.deviation[5]));
}

TEST_CASE("deviation report: unsigned answers report distances; colours by side and size") {
  queries::PointQueryResult r = answers({-0.3, 0.2}, 0.0);
  r.signed_distance.clear();
  const queries::DeviationReport rep = queries::deviation_report(r, {});
  CHECK(!rep.signed_values);
  CHECK(rep.min == 0.2);
  CHECK(rep.max == 0.3);
  const glm::dvec3 green = queries::deviation_colour(0.05, 0.1, 1.0);
  const glm::dvec3 out = queries::deviation_colour(1.0, 0.1, 1.0), in = queries::deviation_colour(-1.0, 0.1, 1.0);
  CHECK(green.g > green.r);
  CHECK(out.r > out.b);  // outside: red
  CHECK(in.b > in.r);    // inside: blue
  const std::vector<glm::dvec3> points{{0, 0, 0}, {1, 0, 0}};
  const nurbs::TriangleMesh cloud = queries::deviation_cloud(points, rep, 0.1);
  CHECK(cloud.positions.size() == 2);
  CHECK(cloud.triangles.empty());
  CHECK(cloud.values_name == "deviation");
}
