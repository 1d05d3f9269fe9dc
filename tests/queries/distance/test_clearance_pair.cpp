// The clearance query's front door (queries/distance/clearance_pair.h): what it decides for every caller.
// Answers against the exact distance of two spheres at several placements, B in another unit scaled
// into A's, a body the model does not have refused as a request, faces culled for the placements
// asked for refusing another, and the papers' settings.
#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "queries/distance/clearance_pair.h"

namespace {

glm::dmat4 move(double x) { return glm::translate(glm::dmat4(1.0), glm::dvec3(x, 0.0, 0.0)); }

}  // namespace

TEST_CASE("clearance pair: placements answered within their bounds, on the GPU or the CPU alone") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::LoadedModel a = models::loaded_sphere(10.0);
  for (const queries::EngineChoice engine : {queries::EngineChoice::Auto, queries::EngineChoice::Gpu}) {
    queries::ClearanceOptions o;
    o.tolerance = 1e-4;
    o.engine = engine;
    queries::ClearancePair pair(a, nullptr, o, &gpu);
    const std::vector<glm::dmat4> frames = {move(30.0), move(45.0)};
    pair.prepare(frames);
    for (const glm::dmat4& m : frames) {
      const queries::ClearanceAnswer answer = pair.query(m);
      CHECK(answer.meets());
      CHECK(answer.failure().empty());
      CHECK(std::abs(answer.clearance.distance - (m[3].x - 20.0)) <= answer.clearance.bound);
    }
    CHECK_THROWS_AS((void)pair.query(move(60.0)), std::invalid_argument);
    CHECK(pair.gpu_queries() == 2);
  }
  // The CPU engine: no GL context started.
  queries::ClearanceOptions cpu;
  cpu.engine = queries::EngineChoice::Cpu;
  queries::ClearancePair pair(a, nullptr, cpu, nullptr);
  pair.prepare(std::vector{move(30.0)});
  const queries::ClearanceAnswer answer = pair.query(move(30.0));
  CHECK(answer.on_cpu);
  CHECK(pair.gpu() == nullptr);
  CHECK(answer.meets());
  CHECK(std::abs(answer.clearance.distance - 10.0) <= answer.clearance.bound);
}

TEST_CASE("clearance pair: B in inches is scaled into A's millimetres") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::LoadedModel a = models::loaded_sphere(10.0), b = models::loaded_sphere(10.0 / 25.4, 25.4);
  queries::ClearancePair pair(a, &b, {}, &gpu);
  pair.prepare(std::vector{move(30.0)});
  const queries::ClearanceAnswer answer = pair.query(move(30.0));
  CHECK(std::abs(answer.clearance.distance - 10.0) <= answer.clearance.bound);
}

TEST_CASE("clearance pair: a body the model does not have is refused, naming it") {
  gpgpu::Gpu& gpu = test::gpu();
  queries::ClearanceOptions o;
  o.body_b = "wheel";
  nurbs::LoadedModel sphere = models::loaded_sphere(10.0);
  sphere.path = "sphere.igs";
  try {
    queries::ClearancePair pair(sphere, nullptr, o, &gpu);
    FAIL("no error");
  } catch (const nurbs::RequestError& e) {
    CHECK(std::string(e.what()).find("--body-b: sphere.igs has no body 'wheel'") != std::string::npos);
  }
  o.body_b = "ball";  // by name
  queries::ClearancePair pair(models::loaded_sphere(10.0), nullptr, o, &gpu);
  CHECK(pair.faces_b() == 1);
}

TEST_CASE("clearance pair: paper() sets the paper's switches, each with its section") {
  const queries::ClearanceOptions paper = queries::ClearanceOptions{}.paper();
  CHECK(paper.search == queries::Search::Faithful);
  CHECK_FALSE(paper.face_cull);
  CHECK(paper.voxel_stage);
  CHECK(paper.voxels == 40);
  CHECK(paper.limits.reduce_block == 2);
  CHECK(paper.limits.start_pairs == 1);
  CHECK(nurbs::paper_section(queries::ClearanceOptions::paper_switches(), "voxels") == "§6");
}
