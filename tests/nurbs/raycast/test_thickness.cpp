// Wall thickness (thickness.h) on shells with known walls: two parallel planes, a spherical shell,
// a cylinder shell; the vase of ../shared with its 2 mm wall. Faces are oriented by ray parity only,
// whatever the file says, so the tests also give some faces the wrong `reversed` flag.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/raycast/thickness.h"
#include "tests/shared_models.h"

using namespace nurbs;
using namespace nurbs::ray;

namespace {

TrimmedSurface face_of(Surface s, bool reversed = false) {
  TrimmedSurface f;
  f.surface = std::move(s);
  f.reversed = reversed;
  return f;
}

Surface square(double z, double size, bool flip_uv) {
  Surface p;
  p.degree_u = p.degree_v = 1;
  p.count_u = p.count_v = 2;
  p.knots_u = p.knots_v = {0, 0, 1, 1};
  p.points = {{0, 0, z}, {size, 0, z}, {0, size, z}, {size, size, z}};
  if (flip_uv) std::swap(p.points[1], p.points[2]);  // the other normal direction
  return p;
}

struct Result {
  ThicknessSamples samples;
  ThicknessRays rays;
  std::vector<Hit> hits;
};

Result thickness_of(const Scene& scene, double spacing) {
  const CastFn cast = [&](const std::vector<Ray>& rays, double t_min) {
    return cast_rays_parallel(scene, rays, t_min, Traversal::Stackless);
  };
  ThicknessOptions o;
  o.spacing = spacing;
  Result r;
  r.samples = thickness_samples(scene, o, cast);
  r.rays = thickness_rays(r.samples);
  r.hits = cast(r.rays.rays, o.start_offset * scene.size);
  return r;
}

}  // namespace

TEST_CASE("thickness: spherical shell, every sample R_out - R_in") {
  // The inner sphere's file flag is wrong on purpose: parity must orient it anyway.
  const Scene scene =
      build_scene({face_of(models::rational_sphere(10.0)), face_of(models::rational_sphere(7.0), true)});
  const Result r = thickness_of(scene, 1.0);
  CHECK(r.samples.orientation_unsure == 0);
  CHECK(r.samples.inward_sign[0] == -r.samples.inward_sign[1]);  // same parametrisation, opposite sides
  REQUIRE(r.rays.rays.size() > 1000);
  int wrong = 0;
  for (size_t k = 0; k < r.hits.size(); ++k) wrong += !(r.hits[k].face >= 0 && std::abs(r.hits[k].t - 3.0) < 1e-8);
  CHECK(wrong == 0);
  // The outer face's inward normal points to the centre.
  const auto& g = r.samples.faces[0];
  for (size_t k = 0; k < g.uv.size(); k += 97)
    if (g.material[k]) CHECK(glm::dot(g.inward[k], g.point[k]) < 0.0);
}

TEST_CASE("thickness: two parallel planes closed by nothing, rays across the gap") {
  // Two squares 0.25 apart; their normals both +z (parity from an unbounded pair: the lower plane's
  // +z ray crosses one face, so +z is its inward side).
  const Scene scene = build_scene({face_of(square(0.0, 4.0, false)), face_of(square(0.25, 4.0, true))});
  const Result r = thickness_of(scene, 0.2);
  CHECK(r.samples.inward_sign[0] == +1);
  CHECK(r.samples.inward_sign[1] == +1);  // flipped parametrisation: Su x Sv = -z points into the gap
  REQUIRE(r.rays.rays.size() >= 2 * 400);
  int wrong = 0;
  for (const Hit& h : r.hits) wrong += !(h.face >= 0 && std::abs(h.t - 0.25) < 1e-12);
  CHECK(wrong == 0);
}

TEST_CASE("thickness: cylinder shell, R_out - R_in away from the open ends") {
  const Scene scene =
      build_scene({face_of(models::rational_cylinder(5.0, 40.0)), face_of(models::rational_cylinder(4.0, 40.0))});
  const Result r = thickness_of(scene, 1.0);
  REQUIRE(r.rays.rays.size() > 500);
  int wrong = 0;
  for (size_t k = 0; k < r.hits.size(); ++k) wrong += !(r.hits[k].face >= 0 && std::abs(r.hits[k].t - 1.0) < 1e-8);
  CHECK(wrong == 0);
  CHECK(r.samples.inward_sign[0] == -r.samples.inward_sign[1]);
}

TEST_CASE("thickness: the vase's wall is 2 mm" * test::needs_shared_models()) {
  const auto path = test::shared_models_dir() / "generated/vase_shell_t2.igs";
  REQUIRE_MESSAGE(std::filesystem::exists(path), path.string() << " is missing from the shared models");
  const Model model = io::read_model(path);
  const Scene scene = build_scene(world_faces(model));
  const Result r = thickness_of(scene, 0.02 * model_size(model));
  CHECK(r.samples.orientation_flips == 0);  // the file has 514 shells: parity agrees with them
  REQUIRE(r.hits.size() > 1000);
  // The side walls (not the rim ring, whose rays run down inside the wall): 2 mm at most samples.
  std::vector<double> t;
  for (const Hit& h : r.hits)
    if (h.face >= 0) t.push_back(h.t);
  std::sort(t.begin(), t.end());
  CHECK(t.size() == r.hits.size());  // a closed shell: every ray hits
  const double median = t[t.size() / 2];
  CHECK(median == doctest::Approx(2.0).epsilon(1e-3));
  long long near_two = std::count_if(t.begin(), t.end(), [](double x) { return std::abs(x - 2.0) < 0.02; });
  CHECK(double(near_two) > 0.9 * double(t.size()));
}

TEST_CASE("thickness: the coloured mesh of the samples faces outward, one vertex per sample") {
  // Outer sphere only: inward = towards the centre, every ray crosses the ball (thickness 2 R).
  const Scene scene = build_scene({face_of(models::rational_sphere(10.0))});
  const Result r = thickness_of(scene, 1.5);
  SampleThickness th(r.samples.faces.size());
  for (size_t f = 0; f < th.size(); ++f) th[f].assign(r.samples.faces[f].uv.size(), -1.0);
  for (size_t k = 0; k < r.hits.size(); ++k)
    th[size_t(r.rays.source[k].first)][size_t(r.rays.source[k].second)] = r.hits[k].t;
  std::vector<double> per_vertex;
  const TriangleMesh m = thickness_mesh(r.samples, th, 0.0, 40.0, &per_vertex);
  CHECK(static_cast<long long>(m.positions.size()) == r.samples.count());
  REQUIRE(m.triangles.size() > 500);
  int inward = 0;
  for (const glm::ivec3& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[size_t(t.y)] - m.positions[size_t(t.x)],
                                    m.positions[size_t(t.z)] - m.positions[size_t(t.x)]);
    inward += glm::dot(n, m.positions[size_t(t.x)]) < 0.0;  // outward = away from the centre
  }
  CHECK(inward == 0);
  for (size_t v = 0; v < per_vertex.size(); ++v) {
    CHECK(per_vertex[v] == doctest::Approx(20.0).epsilon(1e-9));
    CHECK(glm::length(m.colors[v] - thickness_colour(20.0, 0.0, 40.0)) < 1e-9);
  }
  // The values themselves travel with the colours (the PLY's thickness property).
  CHECK(m.values_name == "thickness");
  CHECK(m.values == per_vertex);
  // The viewer's ramp: thin red, yellow, green, thick blue; grey without a hit.
  CHECK(glm::length(thickness_colour(0.0, 0.0, 40.0) - glm::dvec3(0.9, 0.1, 0.1)) < 1e-12);
  CHECK(glm::length(thickness_colour(20.0, 0.0, 40.0) - glm::dvec3(0.575, 0.8, 0.2)) < 1e-12);
  CHECK(glm::length(thickness_colour(40.0, 0.0, 40.0) - glm::dvec3(0.15, 0.35, 0.9)) < 1e-12);
  CHECK(thickness_colour(-1.0, 0.0, 40.0) == glm::dvec3(0.5));
}

TEST_CASE("thickness: the summary the CLI reports (min, upper median, mean, max; -1 when empty)") {
  const nurbs::ray::ThicknessSummary s = nurbs::ray::summarize_thickness({3.0, 1.0, 10.0, 2.0});
  CHECK(s.count == 4);
  CHECK(s.min == 1.0);
  CHECK(s.median == 3.0);  // the upper of the two middle values, as the sorted values[n / 2]
  CHECK(s.mean == 4.0);
  CHECK(s.max == 10.0);
  const nurbs::ray::ThicknessSummary e = nurbs::ray::summarize_thickness({});
  CHECK(e.count == 0);
  CHECK((e.min == -1.0 && e.median == -1.0 && e.mean == -1.0 && e.max == -1.0));
}
