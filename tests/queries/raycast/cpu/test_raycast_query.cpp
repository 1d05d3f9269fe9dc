// The ray casting front door (queries/raycast/raycast_query.h) on the CPU caster: the mesh method's
// hits on a sphere, certified within the hit residual; the BVH and DACRT answer with the reason their
// nearest hits are not certified (rays that graze a face within the bicubic tolerance: one the BVH
// misses here); a model that lost a face, or a face with an invalid trim, is named; a model of no
// size, the GPU without the BVH, or a GPU build without the GPU, is refused.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "queries/raycast/raycast_query.h"

namespace {

/// Rays along the z axis at distance rho from it, from z = -30: each meets the sphere of radius 10
/// about the origin at z = -sqrt(100 - rho^2), at t = 30 - sqrt(100 - rho^2).
std::vector<nurbs::ray::Ray> parallel_rays(const std::vector<double>& rho) {
  std::vector<nurbs::ray::Ray> rays;
  for (size_t k = 0; k < rho.size(); ++k) {
    const double a = 0.7 * double(k);
    rays.push_back({glm::dvec3(rho[k] * std::cos(a), rho[k] * std::sin(a), -30.0), glm::dvec3(0.0, 0.0, 1.0)});
  }
  return rays;
}

}  // namespace

TEST_CASE("raycast front door: the mesh method's hits on a sphere, certified within the hit residual") {
  const std::vector<double> rho{0.0, 3.0, 7.5, 9.9, 12.0};
  const queries::Raycast r = queries::raycast(models::loaded_sphere(10.0), parallel_rays(rho), 0.0, {}, nullptr);
  CHECK(r.method == queries::RayMethod::Mesh);
  CHECK(r.failure().empty());
  CHECK(r.hit_count == 4);
  REQUIRE(r.hits.size() == rho.size());
  for (size_t k = 0; k + 1 < rho.size(); ++k) {
    CAPTURE(k);
    REQUIRE(r.hits[k].face >= 0);
    CHECK(std::abs(r.hits[k].t - (30.0 - std::sqrt(100.0 - rho[k] * rho[k]))) <= r.hit_residual + 1e-9);
  }
  CHECK(r.hits[4].face < 0);
  CHECK(r.figures.mesh_triangles > 0);
}

TEST_CASE("raycast front door: the BVH and DACRT say why their nearest hits are not certified") {
  // Rays along z that graze the sphere of radius 10: at distance 10 - delta from its axis, a pair
  // of hits sqrt(20 delta) apart either side of z = 0.
  std::vector<double> rho;
  for (int k = 0; k < 400; ++k) rho.push_back(10.0 - 1e-6 * std::pow(1e4, k / 399.0));
  const std::vector<nurbs::ray::Ray> rays = parallel_rays(rho);
  queries::RaycastOptions o;
  const queries::Raycast mesh = queries::raycast(models::loaded_sphere(10.0), rays, 0.0, o, nullptr);
  CHECK(mesh.failure().empty());
  CHECK(mesh.hit_count == static_cast<long long>(rays.size()));
  for (const queries::RayMethod method : {queries::RayMethod::Bvh, queries::RayMethod::Dacrt}) {
    o.caster.method = method;
    const queries::Raycast r = queries::raycast(models::loaded_sphere(10.0), rays, 0.0, o, nullptr);
    CAPTURE(std::string(queries::method_name(method)));
    CHECK(r.method == method);
    CHECK(r.doubts.method == queries::nearest_hits_doubt(method));
    CHECK(r.failure().find("the nearest hits are not certified") == 0);
    CHECK(r.failure().find(queries::method_name(method)) != std::string::npos);
    // The reason, on these rays: the bicubic patches lie within 1e-5 of the size of the sphere,
    // and a ray closer to its rim than that may pass them by.
    CHECK(r.hit_count < mesh.hit_count);
    MESSAGE(std::string(queries::method_name(method)) << ": " << r.hit_count << " of " << rays.size() << " grazing rays hit");
  }
  CHECK(queries::nearest_hits_doubt(queries::RayMethod::Mesh).empty());
}

TEST_CASE("raycast front door: a model that lost a face, or a face with an invalid trim, is not certified") {
  const std::vector<nurbs::ray::Ray> rays = parallel_rays({1.0});
  nurbs::LoadedModel partial = models::loaded_sphere(10.0);
  partial.model.dropped_faces.push_back({"#7", "unreadable"});
  partial.report = nurbs::model_report(partial.model);
  queries::RaycastOptions o;
  CHECK(queries::raycast(partial, rays, 0.0, o, nullptr).failure() == partial.report.uncertified_reason(false));
  o.accept_partial = true;
  CHECK(queries::raycast(partial, rays, 0.0, o, nullptr).failure().empty());
  nurbs::LoadedModel invalid = models::loaded_sphere(10.0);
  invalid.model.bodies[0].faces[0].trim_problem = "the loop crosses itself";
  invalid.report = nurbs::model_report(invalid.model);
  const queries::Raycast r = queries::raycast(invalid, rays, 0.0, {}, nullptr);
  CHECK(r.doubt().find("the loop crosses itself") != std::string::npos);
  CHECK(r.failure() == r.doubt());
}

TEST_CASE("raycast front door: refused before the work: a model of no size, the GPU without the BVH, a GPU build "
          "without the GPU") {
  nurbs::LoadedModel empty;
  empty.report = nurbs::model_report(empty.model);
  CHECK_THROWS_AS((void)queries::raycast(empty, parallel_rays({1.0}), 0.0, {}, nullptr), nurbs::RequestError);
  const std::vector<nurbs::ray::Ray> rays = parallel_rays({1.0});
  queries::RaycastOptions o;
  o.caster.bvh_build = queries::BvhBuild::Gpu;
  CHECK_THROWS_AS((void)queries::raycast(models::loaded_sphere(10.0), rays, 0.0, o, nullptr), nurbs::RequestError);
  o.caster.bvh_build = queries::BvhBuild::Cpu;
  o.gpu = true;
  o.caster.method = queries::RayMethod::Dacrt;
  CHECK_THROWS_AS((void)queries::raycast(models::loaded_sphere(10.0), rays, 0.0, o, nullptr), nurbs::RequestError);
}
