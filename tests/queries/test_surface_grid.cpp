// GPU surface evaluation against its CPU twin (double) on random surfaces of degrees 1-7, rational
// and not, clamped and unclamped; and on the exact sphere, where the GPU points must lie on it.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "../gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "queries/surface_grid.h"

namespace {

double control_box_diagonal(const nurbs::Surface& s) {
  glm::dvec3 lo = s.points.front(), hi = lo;
  for (const auto& p : s.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

struct Errors {
  double point = 0.0;       // max |GPU - CPU| / model size
  double normal_cos = 1.0;  // min cos(angle) between GPU and CPU normals where well defined
};

Errors compare(gpgpu::Gpu& gpu, const nurbs::Surface& s, int n, int m, queries::EvalMethod method) {
  const queries::GpuSurface g = queries::upload_surface(s, gpu.info().max_texture_size);
  const queries::SurfaceGrid grid = queries::evaluate_surface(gpu, g, n, m, method);
  const queries::SurfaceGridCpu cpu = queries::evaluate_surface_cpu(s, n, m);
  const auto pts = grid.points.read();
  const auto nrm = grid.normals.read();
  const double size = control_box_diagonal(s);
  Errors e;
  for (size_t k = 0; k < cpu.points.size(); ++k) {
    const glm::dvec3 gp(pts[4 * k], pts[4 * k + 1], pts[4 * k + 2]);
    e.point = std::max(e.point, glm::length(gp - cpu.points[k]) / size);
    const glm::dvec3 gn(nrm[4 * k], nrm[4 * k + 1], nrm[4 * k + 2]);
    if (glm::length(cpu.normals[k]) > 0.5 && glm::length(gn) > 0.5)
      e.normal_cos = std::min(e.normal_cos, glm::dot(gn, cpu.normals[k]));
  }
  return e;
}

}  // namespace

TEST_CASE("surface grid: GPU evaluation matches the CPU twin, degrees 1-7") {
  gpgpu::Gpu& gpu = test::gpu();
  for (queries::EvalMethod method : {queries::EvalMethod::PerFragment, queries::EvalMethod::Tabulated}) {
    CAPTURE(int(method));
    double worst = 0.0;
    int compared = 0;
    for (int degree_u = 1; degree_u <= 7; ++degree_u) {
      for (int degree_v = 1; degree_v <= 7; degree_v += 2) {
        for (bool rational : {false, true}) {
          for (uint64_t seed = 0; seed < 3; ++seed) {
            const nurbs::Surface s =
                models::random_surface(seed * 1000 + uint64_t(degree_u * 10 + degree_v), degree_u, degree_v, rational);
            CAPTURE(degree_u);
            CAPTURE(degree_v);
            CAPTURE(rational);
            CAPTURE(seed);
            const Errors e = compare(gpu, s, 40, 23, method);
            // Float budget (surface_grid.h): ~1.2e-6 of the control box for degree <= 7; allowed 1e-5.
            CHECK(e.point <= 1e-5);
            worst = std::max(worst, e.point);
            ++compared;
          }
        }
      }
    }
    MESSAGE("method " << int(method) << ": max GPU-CPU point error / model size over " << compared
                      << " surfaces: " << worst);
  }
}

TEST_CASE("surface grid: normals agree where the surface is regular") {
  gpgpu::Gpu& gpu = test::gpu();
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const nurbs::Surface s = models::random_surface(seed, 3, 3, seed % 2 == 1);
    CAPTURE(seed);
    const Errors e = compare(gpu, s, 31, 31, queries::EvalMethod::Tabulated);
    // Random nets fold: near-degenerate normals are ill-conditioned in float; 1e-4 ~ 0.8 degree.
    CHECK(e.normal_cos >= 1.0 - 1e-4);
  }
}

TEST_CASE("surface grid: GPU points of the exact rational sphere lie on it") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::Surface sphere = models::rational_sphere(2.5, glm::dvec3(1.0, -2.0, 3.0));
  const queries::SurfaceGrid grid =
      queries::evaluate_surface(gpu, queries::upload_surface(sphere, gpu.info().max_texture_size), 64, 32);
  const auto pts = grid.points.read();
  double worst = 0.0;
  for (size_t k = 0; k < pts.size(); k += 4)
    worst = std::max(worst,
                     std::fabs(glm::length(glm::dvec3(pts[k], pts[k + 1], pts[k + 2]) - glm::dvec3(1, -2, 3)) - 2.5));
  CHECK(worst <= 1e-5 * 2 * 2.5 * std::sqrt(3.0));  // 1e-5 x model size (box diagonal)
  MESSAGE("sphere radius error (float GPU): " << worst);
}

TEST_CASE("surface grid: every face of the shared IGES models, GPU against CPU") {
  const std::filesystem::path dir = std::filesystem::path(NURBSGL_SHARED_DIR) / "models";
  if (!std::filesystem::exists(dir)) {
    MESSAGE("skipped: " << dir << " is absent (a fresh clone has no ../shared)");
    return;
  }
  gpgpu::Gpu& gpu = test::gpu();
  for (const char* file : {"iges/occt_bearing.iges", "iges/occt_hammer.iges", "iges/pythonocc_example_45_faces.iges",
                           "iges/pythonocc_sunglasses_lens.igs", "generated/vase_shell_t2.igs"}) {
    const nurbs::Model model = nurbs::io::read_model(dir / file);
    const double size = nurbs::model_size(model);
    double worst = 0.0;
    for (const nurbs::TrimmedSurface& f : nurbs::world_faces(model)) {
      const queries::SurfaceGrid grid =
          queries::evaluate_surface(gpu, queries::upload_surface(f.surface, gpu.info().max_texture_size), 24, 24);
      const queries::SurfaceGridCpu cpu = queries::evaluate_surface_cpu(f.surface, 24, 24);
      const auto pts = grid.points.read();
      for (size_t k = 0; k < cpu.points.size(); ++k)
        worst = std::max(worst, glm::length(glm::dvec3(pts[4 * k], pts[4 * k + 1], pts[4 * k + 2]) - cpu.points[k]));
    }
    const std::string name = file;
    CAPTURE(name);
    CHECK(worst <= 1e-5 * size);  // the float budget of surface_grid.h, relative to the model size
    MESSAGE(name << ": max GPU-CPU error " << worst << " = " << worst / size << " x model size");
  }
}
