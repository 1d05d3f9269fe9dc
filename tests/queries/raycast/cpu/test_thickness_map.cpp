// The thickness map's front door (queries/raycast/thickness_map.h) on the CPU caster: a sphere's wall is its
// diameter at every sample, within the hit residual; a spacing finer than the most samples allowed
// is refused before the work; a model that lost a face, or a face with an invalid trim, and the
// BVH method leave the map uncertified, named; the papers' settings.
#include <doctest/doctest.h>

#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "queries/raycast/thickness_map.h"

TEST_CASE("thickness map: a sphere's wall is its diameter at every sample") {
  queries::ThicknessMapOptions o;
  o.samples = 2000;
  o.min_wall = 20.5;
  const queries::ThicknessMap m = queries::thickness_map(models::loaded_sphere(10.0), o, nullptr);
  CHECK(m.failure().empty());
  REQUIRE(m.hit_count > 1000);
  CHECK(m.hit_count == static_cast<long long>(m.rays.rays.size()));
  CHECK(m.below_min_wall == m.hit_count);
  CHECK(std::abs(m.lo - 20.0) <= m.hit_residual);
  CHECK(std::abs(m.hi - 20.0) <= m.hit_residual);
  CHECK(m.thickness[size_t(m.rays.source[m.thinnest].first)][size_t(m.rays.source[m.thinnest].second)] == m.lo);
}

TEST_CASE("thickness map: a spacing finer than the most samples allowed is refused before the work") {
  queries::ThicknessMapOptions o;
  o.spacing = 1e-6;
  CHECK_THROWS_AS((void)queries::thickness_map(models::loaded_sphere(10.0), o, nullptr), nurbs::RequestError);
}

TEST_CASE("thickness map: a model that lost a face, or a face with an invalid trim, is not certified") {
  queries::ThicknessMapOptions o;
  o.samples = 500;
  nurbs::LoadedModel partial = models::loaded_sphere(10.0);
  partial.model.dropped_faces.push_back({"#7", "unreadable"});
  partial.report = nurbs::model_report(partial.model);
  CHECK(queries::thickness_map(partial, o, nullptr).failure() == partial.report.uncertified_reason(false));
  nurbs::LoadedModel invalid = models::loaded_sphere(10.0);
  invalid.model.bodies[0].faces[0].trim_problem = "the loop crosses itself";
  invalid.report = nurbs::model_report(invalid.model);
  CHECK(queries::thickness_map(invalid, o, nullptr).failure().find("the loop crosses itself") != std::string::npos);
}

TEST_CASE("thickness map: the BVH's map says why its nearest hits are not certified") {
  queries::ThicknessMapOptions o;
  o.samples = 500;
  o.caster.method = queries::RayMethod::Bvh;
  const queries::ThicknessMap m = queries::thickness_map(models::loaded_sphere(10.0), o, nullptr);
  CHECK(m.doubts.method == queries::nearest_hits_doubt(queries::RayMethod::Bvh));
  CHECK(m.failure() == m.doubts.method);
  CHECK(m.doubt() == m.doubts.method);
}

TEST_CASE("thickness map: paper() sets the paper's switches, each with its section") {
  const queries::ThicknessMapOptions paper = queries::ThicknessMapOptions{}.paper();
  CHECK(paper.gpu);
  CHECK(paper.caster.method == queries::RayMethod::Bvh);
  CHECK(paper.caster.bvh_build == queries::BvhBuild::Gpu);
  CHECK(nurbs::paper_section(queries::ThicknessMapOptions::paper_switches(), "engine") == "§3.2-3.4");
}
