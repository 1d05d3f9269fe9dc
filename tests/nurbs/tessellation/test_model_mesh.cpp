// The tessellation's front door (nurbs/tessellation/model_mesh.h): what it decides for every
// caller. The guaranteed mesh of a sphere within eps of it, measured; the request refused before
// the work (eps below the smallest usable, a face the model does not have); a model that lost a face
// and a face with an invalid trim each failing the certificate, named; the papers' settings.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/tessellation/model_mesh.h"

TEST_CASE("model mesh: the guaranteed mesh of a sphere lies within eps of it, measured both ways") {
  nurbs::tess::ModelMeshOptions o;
  o.eps = 2e-3;
  o.check = true;
  const nurbs::tess::ModelMesh m = nurbs::tess::mesh_model(models::loaded_sphere(10.0), o);
  CHECK(m.eps == doctest::Approx(2e-3 * m.size));
  CHECK(m.failure().empty());
  REQUIRE(m.deviation.has_value());
  CHECK(m.deviation->max() <= m.eps);
  REQUIRE_FALSE(m.result.mesh.positions.empty());
  for (const glm::dvec3& p : m.result.mesh.positions) CHECK(std::abs(glm::length(p) - 10.0) <= m.eps);
}

TEST_CASE("model mesh: requests refused before the work") {
  nurbs::tess::ModelMeshOptions o;
  o.eps = 1e-9;
  CHECK_THROWS_AS((void)nurbs::tess::mesh_model(models::loaded_sphere(10.0), o), nurbs::RequestError);
  o.eps = 1e-2;
  o.faces = {1};
  CHECK_THROWS_WITH_AS((void)nurbs::tess::mesh_model(models::loaded_sphere(10.0), o), "--face 1: the model has faces 0..0",
                       nurbs::RequestError);
}

TEST_CASE("model mesh: a model that lost a face, or a face with an invalid trim, is not certified") {
  nurbs::tess::ModelMeshOptions o;
  o.eps = 1e-2;
  nurbs::LoadedModel partial = models::loaded_sphere(10.0);
  partial.model.dropped_faces.push_back({"#7", "unreadable"});
  partial.report = nurbs::model_report(partial.model);
  CHECK(nurbs::tess::mesh_model(partial, o).failure() == partial.report.uncertified_reason(false));
  o.accept_partial = true;
  CHECK(nurbs::tess::mesh_model(partial, o).failure().empty());
  nurbs::LoadedModel invalid = models::loaded_sphere(10.0);
  invalid.model.bodies[0].faces[0].trim_problem = "the loop crosses itself";
  invalid.report = nurbs::model_report(invalid.model);
  const std::string why = nurbs::tess::mesh_model(invalid, o).failure();
  CHECK(why.find("face 0 (id -1): the loop crosses itself") != std::string::npos);
  o.tess.mode = nurbs::tess::TessMode::Approximate;  // no certificate asked
  CHECK(nurbs::tess::mesh_model(invalid, o).failure().empty());
}

TEST_CASE("model mesh: paper() sets the paper's switches, each with its section") {
  const nurbs::tess::ModelMeshOptions paper = nurbs::tess::ModelMeshOptions{}.paper();
  CHECK(paper.tess.cell_bound == nurbs::tess::CellBound::ControlNet);
  CHECK_FALSE(paper.tess.thin_polylines);
  CHECK_FALSE(paper.tess.rectangle_faces);
  CHECK(paper.tess.mode == nurbs::tess::TessMode::Guaranteed);
  CHECK(nurbs::paper_section(nurbs::tess::ModelMeshOptions::paper_switches(), "evaluation") == "§8");
}

TEST_CASE("model mesh: a measured deviation above eps within the file's edge gaps is certified to them") {
  // The mesh of faces whose file edges lie off them by the gap is certified within eps plus it:
  // the deviation fails only beyond that bound.
  nurbs::tess::ModelMesh m;
  m.eps = 0.01;
  m.gap = 0.05;
  m.deviation = nurbs::tess::Deviation{};
  m.deviation->surface_to_mesh = 0.04;  // above eps, below eps + gap
  CHECK(m.failure().empty());
  m.deviation->surface_to_mesh = 0.07;
  CHECK(m.failure().find("measured deviation 0.07 exceeds eps 0.01 plus the file's edge gaps, 0.06") == 0);
  m.gap = 0.0;  // no gap: the bound is eps
  m.deviation->surface_to_mesh = 0.04;
  CHECK(m.failure() == "measured deviation 0.04 exceeds eps 0.01");
}
