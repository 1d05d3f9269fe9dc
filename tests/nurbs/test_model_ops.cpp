// Model operations: rigid-transform validation, transformed faces (affine invariance: evaluating
// the moved surface equals moving the evaluated point), world faces and the model size.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"

TEST_CASE("model ops: validate_rigid accepts rotations and translations only") {
  const glm::dmat4 rigid = glm::translate(glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(1, 2, 3)), glm::dvec3(4, -5, 6));
  CHECK(nurbs::validate_rigid(rigid).empty());
  CHECK(!nurbs::validate_rigid(glm::scale(glm::dmat4(1.0), glm::dvec3(2, 2, 2))).empty());
  glm::dmat4 mirror(1.0);
  mirror[0][0] = -1.0;  // orthonormal but det -1
  REQUIRE(nurbs::validate_rigid(mirror).size() == 1);
  CHECK(nurbs::validate_rigid(mirror)[0].find("det R = -1") != std::string::npos);
  glm::dmat4 projective(1.0);
  projective[2][3] = 0.5;
  CHECK(!nurbs::validate_rigid(projective).empty());
}

TEST_CASE("model ops: a moved rational surface is the moved surface (affine invariance)") {
  nurbs::TrimmedSurface face;
  face.surface = models::rational_torus(3.0, 1.0);
  const glm::dmat4 m = glm::translate(glm::rotate(glm::dmat4(1.0), 1.1, glm::dvec3(0, 1, 1)), glm::dvec3(10, 0, -2));
  const nurbs::TrimmedSurface moved = nurbs::transformed(face, m);
  for (double u : {0.0, 0.13, 0.5, 0.91})
    for (double v : {0.0, 0.37, 0.77, 1.0}) {
      const glm::dvec3 a = nurbs::surface_point(moved.surface, u, v);
      const glm::dvec3 b = glm::dvec3(m * glm::dvec4(nurbs::surface_point(face.surface, u, v), 1.0));
      CHECK(glm::length(a - b) < 1e-12 * 20);  // rounding of a rotation of coordinates ~10: 1e-12 relative
    }
}

TEST_CASE("model ops: world faces apply body transforms; model size of a sphere") {
  nurbs::Model model;
  nurbs::TrimmedSurface sphere;
  sphere.surface = models::rational_sphere(2.0);
  model.bodies.push_back({"a", {sphere}, glm::dmat4(1.0), ""});
  sphere.face_id = 1;
  model.bodies.push_back({"b", {sphere}, glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 0)), ""});
  const auto faces = nurbs::world_faces(model);
  REQUIRE(faces.size() == 2);
  const nurbs::Box box = nurbs::model_box(model);
  // Two spheres of radius 2 at x = 0 and x = 10: box [-2, 12] x [-2, 2]^2 (sampled on 17 x 17
  // grids, which include the extreme points of these spheres: poles and the equator's quarters).
  CHECK(box.min.x == doctest::Approx(-2.0).epsilon(1e-12));
  CHECK(box.max.x == doctest::Approx(12.0).epsilon(1e-12));
  CHECK(box.max.z == doctest::Approx(2.0).epsilon(1e-12));
  CHECK(nurbs::model_size(model) == doctest::Approx(std::sqrt(14.0 * 14.0 + 4.0 * 4.0 + 4.0 * 4.0)).epsilon(1e-12));
  CHECK(nurbs::model_size(nurbs::Model{}) == 0.0);
}
