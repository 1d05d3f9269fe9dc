// The clash report's front door (queries/distance/clash.h): on generated assemblies of spheres and
// of the paper's two surfaces, every computed pair answered as ClearancePair answers `--body-a I
// --body-b J` (the same bits), pairs farther apart than min_clearance by their boxes left out, the
// order of the rows, the thread count changing nothing, the pairs a caller asks for, and the
// requests it refuses.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <string>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "nurbs/request_error.h"
#include "queries/distance/clash.h"
#include "tests/gpgpu/gl_fixture.h"

namespace {

/// Spheres of radius 10 as the bodies of one model, each named and placed at its centre.
nurbs::LoadedModel spheres(const std::vector<std::pair<std::string, glm::dvec3>>& bodies) {
  nurbs::LoadedModel m;
  for (const auto& [name, centre] : bodies) {
    nurbs::Body body = models::loaded_sphere(10.0).model.bodies.front();
    body.name = name;
    body.transform = glm::translate(glm::dmat4(1.0), centre);
    m.model.bodies.push_back(std::move(body));
  }
  m.model.source = "spheres";
  m.report = nurbs::model_report(m.model);
  return m;
}

/// The answer of `clearance MODEL MODEL --body-a I --body-b J`: B in place, one frame.
queries::ClearanceAnswer reference(const nurbs::LoadedModel& m, int i, int j, queries::ClearanceOptions o) {
  o.body_a = std::to_string(i), o.body_b = std::to_string(j);
  queries::ClearancePair pair(m, nullptr, o, &test::gpu());
  const glm::dmat4 in_place(1.0);
  pair.prepare({&in_place, 1});
  return pair.query(in_place);
}

void check_same(const queries::ClashRow& row, const queries::ClearanceAnswer& ref) {
  INFO("bodies " << row.body_a << " and " << row.body_b);
  const queries::Clearance &c = row.answer.clearance, &r = ref.clearance;
  CHECK(row.computed);
  CHECK(c.distance == r.distance);
  CHECK(c.bound == r.bound);
  CHECK(c.face_a == r.face_a);
  CHECK(c.face_b == r.face_b);
  CHECK(c.point_a == r.point_a);
  CHECK(c.point_b == r.point_b);
  CHECK(c.intersecting == r.intersecting);
  CHECK(row.answer.meets() == ref.meets());
}

}  // namespace

TEST_CASE("clash report: each pair as clearance --body-a --body-b, far boxes left out, rows in order") {
  // a and c meet; b is 10 from a and 13.54 from c (their boxes 10 apart); d lies 150 and more from
  // every other.
  const nurbs::LoadedModel m = spheres({{"a", {0, 0, 0}}, {"b", {30, 0, 0}}, {"c", {0, 15, 0}}, {"d", {200, 0, 0}}});
  queries::ClashOptions o;
  o.clearance.tolerance = 1e-4;
  o.min_clearance = 12.0;
  size_t calls = 0, last_total = 0;
  o.progress = [&](size_t, size_t total) { ++calls, last_total = total; };
  const queries::ClashReport r = queries::clash_report(m, o, &test::gpu());
  CHECK(r.bodies == 4);
  REQUIRE(r.rows.size() == 6);
  CHECK(r.computed == 3);
  CHECK(r.beyond_boxes == 3);
  CHECK(r.beyond_computed == 1);  // b and c
  CHECK(r.intersecting == 1);
  CHECK(r.uncertified == 0);
  CHECK(r.failure().empty());
  CHECK(calls == 3);
  CHECK(last_total == 3);
  // Intersecting first, then by clearance, then the pairs left out by their box distance.
  CHECK((r.rows[0].body_a == 0 && r.rows[0].body_b == 2 && r.rows[0].answer.clearance.intersecting));
  CHECK((r.rows[1].body_a == 0 && r.rows[1].body_b == 1));
  CHECK(std::abs(r.rows[1].answer.clearance.distance - 10.0) <= r.rows[1].answer.clearance.bound);
  CHECK(!r.rows[1].beyond(o.min_clearance));
  CHECK((r.rows[2].body_a == 1 && r.rows[2].body_b == 2));
  CHECK(r.rows[2].beyond(o.min_clearance));
  CHECK(std::abs(r.rows[2].answer.clearance.distance - (std::hypot(30.0, 15.0) - 20.0)) <=
        r.rows[2].answer.clearance.bound);
  for (size_t k = 3; k < 6; ++k) {
    CHECK(!r.rows[k].computed);
    CHECK(r.rows[k].body_b == 3);
    CHECK(r.rows[k].box_distance > 12.0);
    CHECK(r.rows[k].beyond(o.min_clearance));
  }
  CHECK(r.rows[3].box_distance <= r.rows[4].box_distance);
  CHECK(r.rows[0].name_a == "a");
  CHECK(r.rows[0].name_b == "c");
  for (size_t k = 0; k < 3; ++k) check_same(r.rows[k], reference(m, r.rows[k].body_a, r.rows[k].body_b, o.clearance));

  // One thread answers the same; without a limit every pair is computed, the far ones beyond none.
  o.threads = 1;
  o.min_clearance = std::numeric_limits<double>::infinity();
  const queries::ClashReport all = queries::clash_report(m, o, &test::gpu());
  CHECK(all.computed == 6);
  CHECK(all.beyond_boxes == 0);
  for (size_t k = 0; k < 3; ++k) check_same(all.rows[k], r.rows[k].answer);
  CHECK(all.rows.back().answer.clearance.distance > 150.0);

  // The CPU engine starts no GL context: none given, none startable.
  o.clearance.engine = queries::EngineChoice::Cpu;
  const queries::ClashReport cpu = queries::clash_report(m, o, nullptr);
  CHECK(cpu.gpu == nullptr);
  CHECK(cpu.cpu_pairs == 6);
  for (const queries::ClashRow& row : cpu.rows) check_same(row, reference(m, row.body_a, row.body_b, o.clearance));
}

TEST_CASE("clash report: a pair the GPU answers is handed to the calling thread, as clearance answers it") {
  // The paper's pair: too many cell pairs for the CPU alone under auto.
  nurbs::LoadedModel m;
  for (nurbs::Surface s : {models::wavy_surface_199x33(), models::wavy_surface_100x105()}) {
    nurbs::Body body;
    body.name = "wavy";
    nurbs::TrimmedSurface face;
    face.surface = std::move(s);
    body.faces.push_back(std::move(face));
    m.model.bodies.push_back(std::move(body));
  }
  m.report = nurbs::model_report(m.model);
  queries::ClashOptions o;
  o.clearance.tolerance = 1e-4;
  const queries::ClashReport r = queries::clash_report(m, o, &test::gpu());
  REQUIRE(r.rows.size() == 1);
  CHECK(r.gpu_pairs == 1);
  CHECK(r.rows[0].engine == "gpu");
  check_same(r.rows[0], reference(m, 0, 1, o.clearance));
}

TEST_CASE("clash report: the pairs asked for, and the requests refused naming the model") {
  const nurbs::LoadedModel m = spheres({{"a", {0, 0, 0}}, {"b", {30, 0, 0}}, {"c", {0, 40, 0}}});
  queries::ClashOptions o;
  o.pairs = {{2, 0}};
  const queries::ClashReport r = queries::clash_report(m, o, &test::gpu());
  REQUIRE(r.rows.size() == 1);
  CHECK((r.rows[0].body_a == 2 && r.rows[0].body_b == 0));
  check_same(r.rows[0], reference(m, 2, 0, o.clearance));
  for (const auto& bad : {std::pair{1, 1}, std::pair{0, 3}, std::pair{-1, 0}}) {
    o.pairs = {bad};
    CHECK_THROWS_AS((void)queries::clash_report(m, o, nullptr), nurbs::RequestError);
  }
  o.pairs.clear();
  try {
    (void)queries::clash_report(spheres({{"alone", {0, 0, 0}}}), o, nullptr);
    FAIL("no error");
  } catch (const nurbs::RequestError& e) {
    CHECK(std::string(e.what()).find("spheres: 1 body; a clash report needs at least two") != std::string::npos);
  }
}

TEST_CASE("clash report: failure() names each pair not certified and why") {
  queries::ClashReport r;
  r.rows.resize(2);
  for (queries::ClashRow& row : r.rows) row.computed = true, row.answer.clearance.found = true;
  r.rows[1].body_a = 0, r.rows[1].name_a = "nut", r.rows[1].body_b = 3, r.rows[1].name_b = "bolt";
  r.rows[1].answer.reason = "A: face 2 has an invalid trim";
  r.computed = 2, r.uncertified = 1;
  CHECK(r.failure() ==
        "1 of 2 computed pairs not certified:\n  bodies 0 (nut) and 3 (bolt): the answer is not certified: A: face 2 "
        "has an invalid trim");
  r.rows[1].answer.reason.clear();
  CHECK(r.failure().empty());
}
