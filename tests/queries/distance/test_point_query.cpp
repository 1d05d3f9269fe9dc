// The point-set query's front door (queries/distance/point_query.h): what it decides for every caller. The
// answers against the paths it runs (PointBatch, PointDistanceQuery on the same grids), the reader's
// doubts (a dropped face leaves every answer uncertified unless the partial model is accepted), the
// refusal of a grid beyond max_samples, the papers' settings, and the one rule of meeting the
// tolerance.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "queries/distance/point_query.h"

namespace {

std::vector<glm::dvec3> points_around() {
  return {{0.0, 0.0, 25.0}, {13.0, -4.0, 2.0}, {3.0, 1.0, -1.0}, {-30.0, 8.0, 5.0}, {0.5, 0.5, 0.5}};
}

}  // namespace

TEST_CASE("point query: the three paths answer within their bounds, and the answers meet the tolerance") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::LoadedModel sphere = models::loaded_sphere(10.0);
  for (const int path : {0, 1, 2}) {  // the mesh (the default), the pyramid, one point at a time
    const bool per_point = path == 2;
    CAPTURE(path);
    queries::PointQueryOptions o;
    o.tolerance = 1e-4;
    o.per_point = per_point;
    o.path = path == 1 ? queries::PointPath::Batched : queries::PointPath::Auto;
    o.cache = false;
    queries::PointQuery q(gpu, sphere, o);
    CHECK(q.meshed() == (path == 0));
    CHECK(q.batched() == (path == 1));
    const auto points = points_around();
    const queries::PointQueryResult r = q.query(points);
    REQUIRE(r.answers.size() == points.size());
    CHECK(r.tolerance == doctest::Approx(1e-4 * nurbs::model_size(sphere.model)));
    CHECK(r.failure().empty());
    for (size_t k = 0; k < points.size(); ++k) {
      CAPTURE(k);
      const double exact = std::abs(glm::length(points[k]) - 10.0);
      CHECK(r.meets(k));
      CHECK(std::abs(r.answers[k].distance - exact) <= r.answers[k].bound);
    }
  }
}

TEST_CASE("point query: a model that lost a face certifies nothing unless the partial model is accepted") {
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::LoadedModel sphere = models::loaded_sphere(10.0);
  sphere.model.dropped_faces.push_back({"#12", "its surface could not be read"});
  sphere.report = nurbs::model_report(sphere.model);
  queries::PointQueryOptions o;
  o.tolerance = 1e-4;
  o.cache = false;
  {
    queries::PointQuery q(gpu, sphere, o);
    const queries::PointQueryResult r = q.query(points_around());
    CHECK(r.uncertified == r.answers.size());
    CHECK_FALSE(r.meets(0));
    CHECK_FALSE(r.answers[0].meets_tolerance);
    CHECK(r.failure() == sphere.report.uncertified_reason(false));
    CHECK(r.failure().find("dropped 1 of 2 faces") != std::string::npos);
  }
  o.accept_partial = true;
  queries::PointQuery q(gpu, sphere, o);
  const queries::PointQueryResult r = q.query(points_around());
  CHECK(r.uncertified == 0);
  CHECK(r.failure().empty());
}

TEST_CASE("point query: a face whose grid needs more than max_samples is refused as a request, naming it") {
  gpgpu::Gpu& gpu = test::gpu();
  queries::PointQueryOptions o;
  o.tolerance = 1e-7;
  o.max_samples = 16;
  o.cache = false;
  for (const bool per_point : {false, true}) {
    o.per_point = per_point;
    CHECK_THROWS_AS(queries::PointQuery(gpu, models::loaded_sphere(10.0), o), nurbs::RequestError);
  }
}

TEST_CASE("point query: paper() sets the paper's switches, each with its section") {
  const queries::PointQueryOptions paper = queries::PointQueryOptions{}.paper();
  CHECK(paper.per_point);
  CHECK(paper.search == queries::Search::Faithful);
  CHECK(paper.host_cells == 0);
  CHECK(nurbs::paper_section(queries::PointQueryOptions::paper_switches(), "search") == "§3.1, §4");
  CHECK(nurbs::paper_section(queries::PointQueryOptions::paper_switches(), "boxes").empty());
  gpgpu::Gpu& gpu = test::gpu();
  queries::PointQuery q(gpu, models::loaded_sphere(10.0), paper);
  CHECK_FALSE(q.batched());
  CHECK(q.grids() == queries::Search::Faithful);
  CHECK(q.host_cells_used() == 0);
}

TEST_CASE("point query: the one rule of meeting a tolerance") {
  queries::PointDistance d;
  d.found = true, d.bound = 1e-3;
  CHECK(queries::meets_tolerance(d, 1e-3));
  CHECK_FALSE(queries::meets_tolerance(d, 0.999e-3));
  d.meets_tolerance = false;  // its own search ran out of budget
  CHECK_FALSE(queries::meets_tolerance(d, 1e-2));
  d.meets_tolerance = true, d.found = false;
  CHECK_FALSE(queries::meets_tolerance(d, 1e-2));
}
