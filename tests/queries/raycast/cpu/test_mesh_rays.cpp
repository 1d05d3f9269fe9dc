// The ray caster's mesh method (queries/raycast/ray_caster.h, RayMethod::Mesh) against the BVH of
// Lemasson et al. and every patch tested (brute force): the same hits on random trimmed faces and
// exact shapes, no hit of its own later than theirs, and rays from a surface through a sphere.
#include <doctest/doctest.h>

#include <cmath>
#include <array>
#include <string>
#include <utility>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/raycast/ray_caster.h"
#include "tests/shared_models.h"

namespace {

std::vector<nurbs::ray::Ray> random_rays(std::uint64_t seed, int n, double spread) {
  models::Random rng(seed);
  std::vector<nurbs::ray::Ray> rays;
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 o(rng.uniform(-spread, spread), rng.uniform(-spread, spread), rng.uniform(-spread, spread));
    const glm::dvec3 aim(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    rays.push_back({o, glm::normalize(aim - o)});
  }
  return rays;
}

struct Compared {
  int hits = 0, differ = 0, later = 0;
};

/// Mesh against brute force: hit or miss alike, the same t (1e-9 size); `later` counts mesh hits
/// beyond the brute force's (a nearer hit missed).
Compared compare(const std::vector<nurbs::TrimmedSurface>& faces, const std::vector<nurbs::ray::Ray>& rays,
                 double mesh_tolerance, double t_min = 0.0, long long* fallbacks = nullptr) {
  queries::RayCasterOptions o;
  o.method = queries::RayMethod::Mesh;
  o.mesh_tolerance = mesh_tolerance;
  queries::RayCaster mesh(faces, o);
  const auto m = mesh.cast(rays, t_min);
  const auto& scene = mesh.scene();
  const auto b = nurbs::ray::cast_rays(scene, rays, t_min, nurbs::ray::Traversal::BruteForce);
  Compared c;
  for (size_t k = 0; k < rays.size(); ++k) {
    c.hits += b[k].face >= 0;
    c.differ += (m[k].face >= 0) != (b[k].face >= 0) ||
                (m[k].face >= 0 && std::abs(m[k].t - b[k].t) > 1e-9 * scene.size);
    c.later += m[k].face >= 0 && b[k].face >= 0 && m[k].t > b[k].t + 1e-9 * scene.size;
  }
  if (fallbacks) *fallbacks = mesh.figures().fallbacks;
  return c;
}

}  // namespace

TEST_CASE("mesh rays: the same nearest hits as every patch tested, on random trimmed faces") {
  std::vector<nurbs::TrimmedSurface> faces;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  for (double mesh_tolerance : {1e-3, 1e-4}) {
    long long fallbacks = 0;
    const Compared c = compare(faces, random_rays(5, 600, 4.0), mesh_tolerance, 0.0, &fallbacks);
    CAPTURE(mesh_tolerance);
    CHECK(c.hits > 150);
    CHECK(c.later == 0);
    CHECK(c.differ == 0);
    MESSAGE("mesh at " << mesh_tolerance << ": " << c.hits << " hits of 600, " << fallbacks << " rays to the BVH");
  }
}

TEST_CASE("a batch of more rays than a chunk, cast along a Morton curve of their origins: each ray's own hit") {
  std::vector<nurbs::TrimmedSurface> faces;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  const std::vector<nurbs::ray::Ray> rays = random_rays(17, 40000, 4.0);  // chunks of 16384 rays
  for (const queries::RayMethod method : {queries::RayMethod::Mesh, queries::RayMethod::Bvh}) {
    queries::RayCasterOptions o;
    o.method = method;
    queries::RayCaster caster(faces, o);
    const auto batch = caster.cast(rays, 0.0);
    REQUIRE(batch.size() == rays.size());
    int hits = 0, differ = 0;
    for (size_t first = 0; first < rays.size(); first += 1000) {  // slices cast in input order
      const std::vector<nurbs::ray::Ray> slice(rays.begin() + long(first), rays.begin() + long(first + 1000));
      const auto alone = caster.cast(slice, 0.0);
      for (size_t k = 0; k < slice.size(); ++k) {
        const nurbs::ray::Hit &a = alone[k], &b = batch[first + k];
        hits += a.face >= 0;
        differ += a.face != b.face || (a.face >= 0 && (a.t != b.t || a.uv != b.uv));
      }
    }
    CAPTURE(int(method));
    CHECK(hits > 10000);
    CHECK(differ == 0);
  }
}

TEST_CASE("mesh rays: a sphere from outside, from its surface and along its equator's plane") {
  const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(models::loaded_sphere(10.0).model);
  std::vector<nurbs::ray::Ray> rays = random_rays(9, 400, 30.0);
  // From the surface inwards, some in the plane z = 0 of the grid's lines (a ray along triangle edges).
  for (int k = 0; k < 64; ++k) {
    const double a = 2.0 * M_PI * k / 64, z = k % 2 ? 0.0 : 3.0;
    const glm::dvec3 p = glm::normalize(glm::dvec3(std::cos(a), std::sin(a), z / 10.0)) * 10.0;
    rays.push_back({p, -glm::normalize(p)});
  }
  queries::RayCaster mesh(faces, queries::RayCasterOptions{});
  const auto m = mesh.cast(rays, 1e-6);
  for (size_t k = 400; k < rays.size(); ++k) {
    CAPTURE(k);
    REQUIRE(m[k].face >= 0);
    CHECK(std::abs(m[k].t - 20.0) < 1e-8);
  }
  const Compared c = compare(faces, rays, 1e-4, 1e-6);  // (not the rays' own surface points)
  CHECK(c.differ == 0);
}

TEST_CASE("rays grazing a sphere: the first of the two hits, by the mesh method and by the BVH") {
  // A ray at distance 10 - delta from the centre of the sphere of radius 10 meets it twice, a chord
  // 2 sqrt(20 delta - delta^2) apart: for delta up to 2e-2 both hits lie within the slab around
  // the mesh (1e-4 of the size: 3.5e-3) or close to it, and Newton from near the pair may land on
  // the second. The answer must be the first.
  const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(models::loaded_sphere(10.0).model);
  models::Random rng(21);
  std::vector<nurbs::ray::Ray> rays;
  std::vector<double> first;
  for (int k = 0; k < 4000; ++k) {
    glm::dvec3 d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    glm::dvec3 a(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (glm::length(d) < 0.1) continue;
    d = glm::normalize(d);
    a -= glm::dot(a, d) * d;
    if (glm::length(a) < 0.1) continue;
    const double rho = 10.0 - rng.uniform(1e-4, 2e-2);
    rays.push_back({rho * glm::normalize(a) - 30.0 * d, d});
    first.push_back(30.0 - std::sqrt(100.0 - rho * rho));
  }
  // Two rays whose crossing into the slab Embree's fast traversal loses in float (the mesh method
  // asks for its robust mode).
  for (const auto& [o, d] : {std::pair{glm::dvec3(30.100641461539045, -9.622522580807058, -1.1216738777528898),
                                       glm::dvec3(-0.8095916583540542, 0.5678208575719249, 0.14879791809637624)},
                             std::pair{glm::dvec3(-21.42650553395088, -21.304786938884583, -9.323427890326519),
                                       glm::dvec3(0.4295308271939996, 0.8696311189212992, 0.24340292827681362)}}) {
    const glm::dvec3 u = glm::normalize(d);
    const double rho = glm::length(o - glm::dot(o, u) * u);
    rays.push_back({o, u});
    first.push_back(-glm::dot(o, u) - std::sqrt(100.0 - rho * rho));
  }
  queries::RayCaster mesh(faces, queries::RayCasterOptions{});
  const auto m = mesh.cast(rays, 0.0);
  queries::RayCasterOptions bvh_options;
  bvh_options.method = queries::RayMethod::Bvh;
  queries::RayCaster bvh(faces, bvh_options);
  const auto b = bvh.cast(rays, 0.0);
  int mesh_missed = 0, mesh_wrong = 0, bvh_wrong = 0, bvh_hits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    mesh_missed += m[k].face < 0;
    mesh_wrong += m[k].face >= 0 && std::abs(m[k].t - first[k]) > 1e-5;
    bvh_hits += b[k].face >= 0;
    bvh_wrong += b[k].face >= 0 && std::abs(b[k].t - first[k]) > 1e-5;
  }
  CAPTURE(rays.size());
  CHECK(mesh_missed == 0);
  CHECK(mesh_wrong == 0);
  // The BVH of Lemasson et al. may miss a pair its bicubic patches do not show; a hit it gives is
  // the first.
  CHECK(bvh_hits > int(rays.size()) * 9 / 10);
  CHECK(bvh_wrong == 0);
  MESSAGE(rays.size() << " grazing rays: the mesh method sent " << mesh.figures().fallbacks << " to the BVH; the BVH hit "
                      << bvh_hits);
}

TEST_CASE("rays through points of trimmed faces at shallow angles: none missed, none beyond the point") {
  // A ray through a material point p of a face meets the faces at p: the nearest hit lies at p or
  // before it. Tilted 0.01 to 0.1 from the face's tangent plane, such rays graze it: a pair of
  // hits close together, the way out of the slab unseen near an edge.
  std::vector<nurbs::TrimmedSurface> faces;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  queries::RayCaster mesh(faces, queries::RayCasterOptions{});
  const auto& scene = mesh.scene();
  models::Random rng(17);
  std::vector<nurbs::ray::Ray> rays;
  const double reach = 0.3 * scene.size;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto du = nurbs::surface_domain_u(faces[f].surface), dv = nurbs::surface_domain_v(faces[f].surface);
    for (int i = 0; i < 400; ++i) {
      const glm::dvec2 uv(rng.uniform(du.min, du.max), rng.uniform(dv.min, dv.max));
      if (!scene.is_material(int(f), uv)) continue;
      const auto d = nurbs::surface_derivatives(faces[f].surface, uv.x, uv.y);
      const glm::dvec3 n = glm::cross(d.su, d.sv);
      if (glm::length(n) == 0.0) continue;
      const double a = rng.uniform(0.0, 2.0 * M_PI), tilt = std::array{0.01, 0.03, 0.1}[size_t(i % 3)];
      glm::dvec3 dir = glm::normalize(std::cos(a) * glm::normalize(d.su) + std::sin(a) * glm::normalize(d.sv));
      dir = glm::normalize(dir + (i % 2 ? tilt : -tilt) * glm::normalize(n));
      rays.push_back({d.s - reach * dir, dir});
    }
  }
  const auto m = mesh.cast(rays, 0.0);
  int missed = 0, beyond = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    missed += m[k].face < 0;
    beyond += m[k].face >= 0 && m[k].t > reach + 1e-7 * scene.size;
  }
  CAPTURE(rays.size());
  CHECK(rays.size() > 1000);
  CHECK(missed == 0);
  CHECK(beyond == 0);
  MESSAGE(rays.size() << " rays through face points: " << mesh.figures().fallbacks << " to the BVH");
}

TEST_CASE("rays that start inside a face's slab and run along it: the hit where they leave the cylinder") {
  // A ray from a point delta inside the cylinder of radius 10 (within the slab around its mesh,
  // 1e-4 of the size on either side), along the axis and turned by a small angle around it, stays
  // within the slab for a long way, crosses no shell before it meets the face, and leaves the
  // cylinder where its distance from the axis reaches 10. From a point outside, turned away, it
  // meets nothing.
  nurbs::TrimmedSurface face;
  face.surface = models::rational_cylinder(10.0, 40.0);
  const std::vector<nurbs::TrimmedSurface> faces{face};
  models::Random rng(23);
  std::vector<nurbs::ray::Ray> rays;
  std::vector<double> first;  // -1: none
  for (int k = 0; k < 2000; ++k) {
    const double phi = rng.uniform(0.0, 2.0 * M_PI), z0 = rng.uniform(1.0, 10.0);
    const double delta = (k % 4 == 3 ? -1.0 : 1.0) * rng.uniform(1e-4, 4e-3), a = rng.uniform(0.01, 0.05);
    const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0), around(-std::sin(phi), std::cos(phi), 0.0);
    const glm::dvec3 w = glm::dvec3(0.0, 0.0, 1.0) + a * around;
    const double s = glm::length(w) * std::sqrt(std::max(0.0, 100.0 - (10.0 - delta) * (10.0 - delta))) / a;
    if (delta > 0.0 && z0 + s / glm::length(w) > 38.0) continue;
    rays.push_back({(10.0 - delta) * radial + glm::dvec3(0.0, 0.0, z0), glm::normalize(w)});
    first.push_back(delta > 0.0 ? s : -1.0);
  }
  queries::RayCaster mesh(faces, queries::RayCasterOptions{});
  const auto m = mesh.cast(rays, 0.0);
  int missed = 0, wrong = 0, invented = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    if (first[k] < 0.0) {
      invented += m[k].face >= 0;
      continue;
    }
    missed += m[k].face < 0;
    wrong += m[k].face >= 0 && std::abs(m[k].t - first[k]) > 1e-6;
  }
  CAPTURE(rays.size());
  CHECK(rays.size() > 1500);
  CHECK(missed == 0);
  CHECK(wrong == 0);
  CHECK(invented == 0);
  MESSAGE(rays.size() << " rays from inside the slab: " << mesh.figures().fallbacks << " to the BVH");
}

TEST_CASE("mesh rays on the shared models: rays whose nearer hit lies in a slab reached unseen" *
          test::needs_shared_models()) {
  // Each ray with a hit at or before `first` (an exact hit on a material point): through tubes into
  // a neighbour's slab (the Ventilator's fan, where OpenCASCADE's IntCurvesFace_ShapeIntersector
  // gives the same t), past more than 8 tubes of a narrow face (the bearing), from a start inside a
  // cylinder's slab along its ruling (component8).
  struct Case {
    const char* file;
    glm::dvec3 origin, direction;
    double first;
  };
  const Case cases[] = {
      {"step/pythonocc_Ventilator.stp", {21.583129263, 19.721419649, 26.297019962}, {-0.0095, -0.037266, -1}, 21.4128708493},
      {"step/pythonocc_Ventilator.stp", {20.144911199, -26.787568243, 26.297019962}, {0.042884, -0.024473, -1}, 23.6164750886},
      {"step/pythonocc_Ventilator.stp", {23.988944952, 17.370790865, 26.297019962}, {-0.053989, 0.065341, -1}, 21.8552038745},
      {"iges/occt_bearing.iges", {-0.044656453694653236, 0.025762554381868048, 0.017324330362211936},
       {0.5371526350300139, -0.8373608118968144, -0.10145894430665241}, 0.0484270867459477},
      {"iges/occt_bearing.iges", {0.048454987349617756, 0.021360551663970728, 0.031457673442180756},
       {-0.9957867807862668, -0.09148041661337937, -0.00632618270097349}, 0.0484270867459477},
      {"step/gmsh_component8.step", {-2.9310752534680793, 158.74897457146284, -9.190646752232146},
       {-0.0006376612787243956, 0.9999997776802725, 0.00019500640833502433}, 18.580485577864536},
  };
  for (const Case& c : cases) {
    const std::filesystem::path file = test::shared_models_dir() / c.file;
    if (!std::filesystem::exists(file)) {
      MESSAGE(file.string() << " absent: skipped");
      continue;
    }
    const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(nurbs::io::read_model(file));
    queries::RayCaster mesh(faces, queries::RayCasterOptions{});
    const auto h = mesh.cast({{c.origin, glm::normalize(c.direction)}}, 0.0);
    const std::string name = c.file;
    CAPTURE(name);
    CAPTURE(c.first);
    CHECK(h[0].face >= 0);
    CHECK(h[0].t <= c.first + 1e-7 * mesh.scene().size);
  }
}

TEST_CASE("mesh rays: a ray through the edge two faces share meets one of them, whatever rounding parts their loops") {
  // One plane, two faces whose loops meet at u = 1 but for 1e-10 either side (each face's loop a
  // rounding off the other's, as two faces' trims of one edge are): a ray through that line meets
  // the model there, on one face or the other.
  nurbs::TrimmedSurface left, right;
  left.surface = right.surface = models::bilinear_square(2.0);
  const auto box = [](double u0, double u1) {
    const glm::dvec2 a(u0, 0.0), b(u1, 0.0), c(u1, 2.0), d(u0, 2.0);
    return nurbs::TrimLoop{{models::trim_line(a, b), models::trim_line(b, c), models::trim_line(c, d),
                            models::trim_line(d, a)},
                           true};
  };
  left.loops = {box(0.0, 1.0 - 1e-10)};
  right.loops = {box(1.0 + 1e-10, 2.0)};
  const std::vector<nurbs::TrimmedSurface> faces = {left, right};
  queries::RayCaster mesh(faces, queries::RayCasterOptions{});
  std::vector<nurbs::ray::Ray> rays;
  std::vector<glm::dvec3> through;
  for (const glm::dvec3& d : {glm::dvec3(0, 0, -1), glm::dvec3(0.3, 0.1, -1), glm::dvec3(-0.05, 0.7, -1),
                              glm::dvec3(2.0, 0.3, -0.2)}) {
    const glm::dvec3 p(1.0, 0.6 + 0.1 * double(rays.size()), 0.0), u = glm::normalize(d);
    rays.push_back({p - 2.0 * u, u});
    through.push_back(p);
  }
  const std::vector<nurbs::ray::Hit> hits = mesh.cast(rays, 0.0);
  for (size_t k = 0; k < rays.size(); ++k) {
    CAPTURE(k);
    CHECK(hits[k].face >= 0);
    CHECK(hits[k].t == doctest::Approx(2.0).epsilon(1e-9));
    CHECK(glm::length(hits[k].point - through[k]) < 1e-9);
  }
}
