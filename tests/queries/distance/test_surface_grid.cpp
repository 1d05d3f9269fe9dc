// GPU surface evaluation against its CPU twin (double) on random surfaces of degrees 1-7, rational
// and not, clamped and unclamped; and on the exact sphere, where the GPU points must lie on it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/surface_grid.h"
#include "tests/shared_models.h"

namespace {

struct Errors {
  double point = 0.0;       // max |GPU - CPU| / model size
  double normal_cos = 1.0;  // min cos(angle) between GPU and CPU normals where the CPU one is defined
  int normals_compared = 0;
};

Errors compare(gpgpu::Gpu& gpu, const nurbs::Surface& s, const nurbs::ParamGrid& params, queries::EvalMethod method,
               const queries::TileLimits& limits = {}) {
  const queries::GpuSurface g = queries::upload_surface(s, gpu.info().max_texture_size);
  const queries::SurfaceGrid grid = queries::evaluate_surface(gpu, g, params, method, limits);
  const queries::SurfaceGridCpu cpu = queries::evaluate_surface_cpu(s, params);
  const auto pts = grid.read_points();
  const auto nrm = grid.read_normals();
  const double size = nurbs::control_box(s).diagonal();
  Errors e;
  for (size_t k = 0; k < cpu.points.size(); ++k) {
    const glm::dvec3 gp(pts[4 * k], pts[4 * k + 1], pts[4 * k + 2]);
    e.point = std::max(e.point, glm::length(gp - cpu.points[k]) / size);
    // Wherever the CPU normal exists, the GPU one must too (a zero GPU normal gives cos 0 and fails).
    const glm::dvec3 gn(nrm[4 * k], nrm[4 * k + 1], nrm[4 * k + 2]);
    if (glm::length(cpu.normals[k]) > 0.5) {
      e.normal_cos = std::min(e.normal_cos, glm::dot(gn, cpu.normals[k]));
      ++e.normals_compared;
    }
  }
  return e;
}

Errors compare(gpgpu::Gpu& gpu, const nurbs::Surface& s, int n, int m, queries::EvalMethod method) {
  return compare(gpu, s, nurbs::uniform_param_grid(nurbs::surface_domain_u(s), nurbs::surface_domain_v(s), n, m),
                 method);
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
            // Float budget (surface_grid.h), measured for degree <= 7: per-fragment 1.6e-6 of the control
            // box, tabulated (double basis) 1.0e-7; allowed 2.5x and 5x that.
            CHECK(e.point <= (method == queries::EvalMethod::PerFragment ? 4e-6 : 5e-7));
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
    CHECK(e.normals_compared > 32 * 32 / 2);
  }
}

TEST_CASE("surface grid: GPU points of the exact rational sphere lie on it") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::Surface sphere = models::rational_sphere(2.5, glm::dvec3(1.0, -2.0, 3.0));
  const queries::SurfaceGrid grid =
      queries::evaluate_surface(gpu, queries::upload_surface(sphere, gpu.info().max_texture_size), 64, 32);
  const auto pts = grid.read_points();
  double worst = 0.0;
  for (size_t k = 0; k < pts.size(); k += 4)
    worst = std::max(worst,
                     std::fabs(glm::length(glm::dvec3(pts[k], pts[k + 1], pts[k + 2]) - glm::dvec3(1, -2, 3)) - 2.5));
  CHECK(worst <= 1e-5 * 2 * 2.5 * std::sqrt(3.0));  // 1e-5 x model size (box diagonal)
  MESSAGE("sphere radius error (float GPU): " << worst);
}

TEST_CASE("surface grid: every face of the shared IGES models, GPU against CPU" * test::needs_shared_models()) {
  const std::filesystem::path dir = test::shared_models_dir();
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
      const auto pts = grid.read_points();
      for (size_t k = 0; k < cpu.points.size(); ++k)
        worst = std::max(worst, glm::length(glm::dvec3(pts[4 * k], pts[4 * k + 1], pts[4 * k + 2]) - cpu.points[k]));
    }
    const std::string name = file;
    CAPTURE(name);
    CHECK(worst <= 5e-7 * size);  // the tabulated float budget above, relative to the model size
    MESSAGE(name << ": max GPU-CPU error " << worst << " = " << worst / size << " x model size");
  }
}

TEST_CASE("surface grid: knot-aligned grids of C0 surfaces, GPU against CPU") {
  gpgpu::Gpu& gpu = test::gpu();
  double worst = 0.0, worst_cos = 1.0, worst_per_fragment = 0.0;
  for (uint64_t seed = 0; seed < 24; ++seed) {
    const int p = 1 + int(seed % 7), q = 1 + int(seed / 7 % 4);
    const nurbs::Surface s = models::random_kinked_surface(seed + 500, p, q, seed % 2 ? 100.0 : 1.0);
    const double size = nurbs::control_box(s).diagonal();
    const nurbs::CertifiedGrid cg =
        nurbs::certified_grid(nurbs::filip_bound(s), 3e-2 * size, nurbs::GridLimits{200'000});
    CAPTURE(seed);
    REQUIRE(cg.grid.u.size() > 2);
    const Errors e = compare(gpu, s, cg.grid, queries::EvalMethod::Tabulated);
    CHECK(e.point <= 5e-7);  // the tabulated float budget above
    worst = std::max(worst, e.point);
    worst_cos = std::min(worst_cos, e.normal_cos);
    // The per-fragment method rounds knots to float: thin spans (1e-4 of the domain) cost accuracy.
    worst_per_fragment = std::max(worst_per_fragment, compare(gpu, s, cg.grid, queries::EvalMethod::PerFragment).point);
  }
  MESSAGE("knot-aligned grids: max GPU-CPU point error / size "
          << worst << " (per-fragment method: " << worst_per_fragment << "), min normal cos " << worst_cos);
}

TEST_CASE("surface grid: tiles give the same samples as one texture") {
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::Surface s = models::random_kinked_surface(7, 3, 2, 10.0);
  const nurbs::CertifiedGrid cg = nurbs::certified_grid(nurbs::filip_bound(s), 1e-2, nurbs::GridLimits{200'000});
  const queries::GpuSurface g = queries::upload_surface(s, gpu.info().max_texture_size);
  const auto whole = queries::evaluate_surface(gpu, g, cg.grid);
  REQUIRE(whole.tiles.size() == 1);
  for (int side : {2, 17, 64}) {
    CAPTURE(side);
    const auto tiled = queries::evaluate_surface(gpu, g, cg.grid, queries::EvalMethod::Tabulated, {side});
    CHECK(tiled.tiles.size() == queries::tile_starts(int(cg.grid.u.size()), side).size() *
                                    queries::tile_starts(int(cg.grid.v.size()), side).size());
    CHECK(tiled.read_points() == whole.read_points());  // same float computation per sample
    CHECK(tiled.read_normals() == whole.read_normals());
  }
  // A byte budget alone also tiles: 64 KiB holds 2048 samples of 32 bytes, a 45-sample square.
  const auto budget = queries::evaluate_surface(gpu, g, cg.grid, queries::EvalMethod::Tabulated, {0, 64 << 10});
  for (const auto& t : budget.tiles) CHECK(t.points.width() <= 45);
  CHECK(budget.read_points() == whole.read_points());
}

TEST_CASE("surface grid: control and knot arrays longer than the texture size limit") {
  gpgpu::Gpu& gpu = test::gpu();
  // A bicubic strip with more control points along u than GL_MAX_TEXTURE_SIZE.
  nurbs::Surface s;
  s.degree_u = 3;
  s.degree_v = 1;
  s.count_u = gpu.info().max_texture_size + 100;
  s.count_v = 2;
  for (int i = 0; i < s.count_u + 4; ++i) s.knots_u.push_back(std::clamp(i - 3, 0, s.count_u - 3));
  s.knots_v = {0, 0, 1, 1};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < s.count_u; ++i) s.points.emplace_back(i * 0.01, j, std::sin(i * 0.05));
  const Errors e = compare(gpu, s, 300, 3, queries::EvalMethod::Tabulated);
  CHECK(e.point <= 5e-7);  // the tabulated float budget above
  const Errors f = compare(gpu, s, 300, 3, queries::EvalMethod::PerFragment);
  CHECK(f.point <= 4e-6);  // the per-fragment float budget above
  MESSAGE(s.count_u << " control points along u: GPU-CPU error / size " << e.point);
}
