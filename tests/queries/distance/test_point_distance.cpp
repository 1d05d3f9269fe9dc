// Point-surface distance (Krishnamurthy et al. §3.1-3.2, §4): the GPU query against its CPU twin
// (same cells and triangles in double) and against an independent reference (dense sampling and
// Newton projection in double, or the exact sphere): |d - d*| < K (Theorem 1) and the closest point
// within sqrt(4 K d + K^2) (Theorem 2), with K the Euclidean K_e over the surviving cells.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/clearance.h"
#include "queries/distance/point_distance.h"
#include "tests/queries/distance/distance_reference.h"
#include "tests/shared_models.h"

TEST_CASE("point distance: GPU query = CPU twin, within K of the reference (Theorems 1 and 2)") {
  gpgpu::Gpu& gpu = test::gpu();
  double worst_twin = 0.0, worst_ratio = 0.0;
  int queries = 0, point_checked = 0;
  for (uint64_t seed = 0; seed < 12; ++seed) {
    nurbs::TrimmedSurface face;
    face.surface = models::random_surface(seed + 40, 1 + int(seed % 4), 1 + int(seed / 4 % 3), seed % 2 == 1);
    const double size = nurbs::control_box(face.surface).diagonal(), tol = 2e-3 * size;
    queries::PointDistanceQuery q(gpu, {face}, tol);
    const nurbs::FilipBound b = nurbs::filip_bound(face.surface);
    models::Random rng(seed);
    for (int k = 0; k < 6; ++k) {
      const glm::dvec3 p(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
      const queries::PointDistance gpu_r = q.query(p);
      const queries::PointDistance cpu_r = queries::point_distance_cpu(face.surface, b, q.grids()[0].grid, p);
      const test::Reference ref = test::reference(face.surface, p, gpu_r.uv);
      CAPTURE(seed);
      CAPTURE(k);
      REQUIRE(gpu_r.found);
      CHECK(gpu_r.candidates >= 1);
      CHECK(gpu_r.bound <= tol);
      // Twin: the same triangles in double; the GPU's float boxes may keep a few more cells.
      CHECK(std::abs(gpu_r.distance - cpu_r.distance) <= 1e-12 * size);
      worst_twin = std::max(worst_twin, std::abs(gpu_r.distance - cpu_r.distance));
      // Theorem 1 against the reference (its own error is far below K: Newton in double).
      CAPTURE(gpu_r.distance);
      CAPTURE(ref.distance);
      CHECK(std::abs(gpu_r.distance - ref.distance) < gpu_r.bound + 1e-12 * size);
      worst_ratio = std::max(worst_ratio, std::abs(gpu_r.distance - ref.distance) / gpu_r.bound);
      // Theorem 2 where the closest point is well defined (the reference is clearly the best).
      if (glm::length(ref.point - gpu_r.point) > gpu_r.point_bound) {
        // Allowed only when another surface point is as close (a tie): then the reference's own
        // distance from the computed point's foot must also be within the bound.
        CHECK(std::abs(glm::length(p - gpu_r.point) - ref.distance) < gpu_r.bound);
      } else {
        ++point_checked;
      }
      ++queries;
    }
  }
  CHECK(point_checked > queries * 3 / 4);
  MESSAGE(queries << " queries: |GPU - twin| max " << worst_twin << ", |d - d_ref| / K max " << worst_ratio << ", "
                  << point_checked << " closest points within sqrt(4Kd+K^2)");
}

TEST_CASE("point distance: the exact sphere") {
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface sphere;
  sphere.surface = models::rational_sphere(2.0, glm::dvec3(1, 2, 3));
  queries::PointDistanceQuery q(gpu, {sphere}, 1e-3);
  models::Random rng(3);
  for (int k = 0; k < 20; ++k) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    const double r = rng.uniform(0.3, 6.0);
    const glm::dvec3 p = glm::dvec3(1, 2, 3) + r * dir;
    const queries::PointDistance d = q.query(p);
    CAPTURE(r);
    CHECK(std::abs(d.distance - std::abs(r - 2.0)) < d.bound);
    CHECK(glm::length(d.point - (glm::dvec3(1, 2, 3) + 2.0 * dir)) <= d.point_bound);
    CHECK(d.bound <= 1e-3);
  }
}

TEST_CASE("point distance: many faces at once equal the best face, trimmed regions are skipped") {
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<nurbs::TrimmedSurface> faces;
  for (uint64_t seed = 0; seed < 16; ++seed) {
    faces.push_back(models::random_trimmed_surface(seed));
    for (auto& p : faces.back().surface.points) p += glm::dvec3(3.0 * double(seed % 4), 3.0 * double(seed / 4), 0.0);
    if (seed % 4 == 1) faces.back().loops.clear();  // (random_trimmed_surface gave every one of these seeds loops)
  }
  queries::PointDistanceQuery q(gpu, faces, 5e-3);
  models::Random rng(11);
  int trimmed_winners = 0, untrimmed_twins = 0;
  for (int k = 0; k < 12; ++k) {
    const glm::dvec3 p(rng.uniform(-1, 11), rng.uniform(-1, 11), rng.uniform(-2, 2));
    const queries::PointDistance d = q.query(p);
    REQUIRE(d.found);
    // The winner is material and no untrimmed face's twin is closer by more than the bound.
    const nurbs::TrimmedSurface& f = faces[size_t(d.face)];
    if (!f.loops.empty()) {
      CHECK(test::material_or_trim_edge(f, d.uv, d.on_trim_edge));
      ++trimmed_winners;
    }
    for (size_t i = 0; i < faces.size(); ++i) {
      if (!faces[i].loops.empty()) continue;
      const auto b = nurbs::filip_bound(faces[i].surface);
      const auto twin = queries::point_distance_cpu(faces[i].surface, b, q.grids()[i].grid, p);
      CHECK(d.distance <= twin.distance + 1e-12);
      ++untrimmed_twins;
    }
  }
  CHECK(trimmed_winners > 0);
  CHECK(untrimmed_twins == 12 * 4);  // four untrimmed faces, every query
  MESSAGE(q.atlases() << " atlas(es) for " << faces.size() << " faces; " << trimmed_winners
                      << " of 12 winners on trimmed faces");
}

TEST_CASE("point distance: atlases pruned on the CPU give the GPU passes' cells and answers") {
  // PointDistanceQuery::set_host_cells: U and the cells within it from one read-back instead of the
  // reduction, threshold and stream reduction: the same candidates and answers, bit for bit.
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<nurbs::TrimmedSurface> faces;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    faces.push_back(models::random_trimmed_surface(seed + 60));
    for (auto& p : faces.back().surface.points) p += glm::dvec3(3.0 * double(seed % 3), 3.0 * double(seed / 3), 0.0);
  }
  models::Random rng(31);
  int queries = 0;
  for (auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
    CAPTURE(int(search));
    queries::PointDistanceQuery q(gpu, faces, 5e-3, 1LL << 22, search);
    for (int k = 0; k < 10; ++k) {
      const glm::dvec3 p(rng.uniform(-1, 8), rng.uniform(-1, 5), rng.uniform(-2, 2));
      q.set_host_cells(0);
      const queries::PointDistance x = q.query(p);
      q.set_host_cells(1LL << 40);
      const queries::PointDistance y = q.query(p);
      REQUIRE(x.found);
      REQUIRE(y.found);
      CHECK(y.upper == x.upper);
      CHECK(y.candidates == x.candidates);
      CHECK(y.distance == x.distance);
      CHECK(y.bound == x.bound);
      CHECK(y.face == x.face);
      CHECK(y.uv == x.uv);
      ++queries;
    }
  }
  MESSAGE(queries << " points, both searches");
}

TEST_CASE("point distance: every face of the shared IGES models takes part" * test::needs_shared_models()) {
  gpgpu::Gpu& gpu = test::gpu();
  const std::vector<std::filesystem::path> files = test::shared_iges_files();
  REQUIRE(files.size() >= 8);
  int faces = 0, queries_run = 0, on_edges = 0;
  for (const auto& file : files) {
    const nurbs::Model model = nurbs::io::read_model(file);
    const double size = nurbs::model_size(model);
    const auto all = nurbs::world_faces(model);
    queries::PointDistanceQuery q(gpu, all, 1e-3 * size);
    queries::PointDistanceQuery c2f(gpu, all, 1e-3 * size, 1LL << 22, queries::Search::CoarseToFine);
    faces += int(all.size());
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& f : all) {
      const nurbs::Box box = nurbs::control_box(f.surface);
      lo = glm::min(lo, box.min);
      hi = glm::max(hi, box.max);
    }
    const std::string name = file.filename().string();
    CAPTURE(name);
    for (const glm::dvec3& p : {0.5 * (lo + hi), lo - 0.1 * (hi - lo), glm::dvec3(hi.x, lo.y, 0.5 * (lo.z + hi.z))}) {
      const queries::PointDistance d = q.query(p);
      REQUIRE(d.found);
      // The untrimmed twin of every face bounds it from below; on untrimmed winners it is equal.
      double twin = 1e300;
      for (size_t i = 0; i < all.size(); ++i)
        twin = std::min(
            twin, queries::point_distance_cpu(all[i].surface, q.model().bounds[i], q.grids()[i].grid, p).distance);
      CHECK(d.distance >= twin - 1e-12 * size);
      if (all[size_t(d.face)].loops.empty()) CHECK(d.distance <= twin + 1e-12 * size);
      if (!all[size_t(d.face)].loops.empty())
        CHECK(test::material_or_trim_edge(all[size_t(d.face)], d.uv, d.on_trim_edge));
      // Within 1e-3 x size, on a trim edge too: the search goes on over the material parts of the
      // candidate triangles (§5.3, material_distance.h), whose answer Theorem 1 bounds by K.
      CHECK(d.bound <= 1e-3 * size);
      on_edges += d.on_trim_edge;
      const queries::PointDistance c = c2f.query(p);
      CHECK(c.meets_tolerance);
      CHECK(c.bound <= 1e-3 * size);
      // Both intervals hold the true distance: they overlap.
      CHECK(c.distance >= d.distance - d.bound - 1e-12 * size);
      CHECK(c.distance - c.bound <= d.distance + d.bound + 1e-12 * size);
      if (!all[size_t(c.face)].loops.empty()) CHECK(nurbs::is_material(all[size_t(c.face)], c.uv, 1e-9));
      ++queries_run;
    }
  }
  MESSAGE(faces << " faces of " << files.size() << " shared files, " << queries_run << " queries; faithful answers on "
                << "a trim edge " << on_edges);
}

TEST_CASE("point distance: coarse-to-fine search, proven interval holds the reference and the faithful answer") {
  gpgpu::Gpu& gpu = test::gpu();
  int queries = 0;
  long long coarse_cells = 0, fine_cells = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    nurbs::TrimmedSurface face;
    face.surface = models::random_surface(seed + 90, 1 + int(seed % 3), 3, seed % 2 == 0);
    const double size = nurbs::control_box(face.surface).diagonal(), tol = 2e-4 * size;
    queries::PointDistanceQuery faithful(gpu, {face}, tol);
    queries::PointDistanceQuery c2f(gpu, {face}, tol, 1LL << 22, queries::Search::CoarseToFine);
    coarse_cells += c2f.model().grids[0].grid.samples(), fine_cells += faithful.model().grids[0].grid.samples();
    models::Random rng(seed + 1);
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 p(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
      const queries::PointDistance f = faithful.query(p), c = c2f.query(p);
      const test::Reference ref = test::reference(face.surface, p, c.uv);
      CAPTURE(seed);
      CAPTURE(k);
      test::check_proven(c.found, c.meets_tolerance, c.distance, c.bound, tol, ref.distance, 1e-12 * size);
      CHECK(std::abs(glm::length(c.point - p) - c.distance) <= 1e-14 * size);  // realised
      CHECK(std::abs(f.distance - c.distance) <= f.bound + c.bound);
      ++queries;
    }
  }
  CHECK(coarse_cells * 2 < fine_cells);  // coarse grids at 5e-4 of the size, faithful at 2e-4
  MESSAGE(queries << " queries; samples evaluated: coarse-to-fine " << coarse_cells << ", faithful " << fine_cells);
}

TEST_CASE("point distance and clearance: a trimmed face smaller than one grid cell is not culled (5.3)") {
  // A flat bilinear face: its certified grid is one cell, whose four corners lie outside the small
  // disc that trims it. The corner test of the paper alone culls it; the crossed-cell flag keeps it.
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface plate;
  plate.surface = models::bilinear_patch({{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}}});
  plate.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.1, true)}, true});
  for (const auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
    queries::PointDistanceQuery q(gpu, {plate}, 1e-3, 1LL << 22, search);
    REQUIRE(q.grids()[0].grid.cells_u() * q.grids()[0].grid.cells_v() == 1);
    const queries::PointDistance d = q.query({5.0, 5.0, 2.0});
    REQUIRE(d.found);
    CHECK(std::abs(d.distance - 2.0) <= d.bound + 1e-12);
    CHECK(d.bound <= 1e-3);
  }
  const auto a = queries::prepare_model(gpu, {plate}, 1e-3, 1LL << 22, queries::Search::CoarseToFine);
  const queries::Clearance c = queries::clearance(gpu, a, a, glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0, 3)));
  REQUIRE(c.found);
  CHECK(std::abs(c.distance - 3.0) <= c.bound + 1e-12);
}

TEST_CASE("point distance and clearance: over a hole of a one-cell face, the search goes on to the rim (5.3)") {
  // A flat bilinear plate [0, 10]^2 (one grid cell, K = 0) with a hole of radius 1 around (5, 5).
  // Both triangles' closest points to a point (or a small square) above the hole lie in it: the
  // paper discards them and continues the search, which ends on the rim's material side.
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface plate, square;
  plate.surface = models::bilinear_patch({{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}}});
  plate.loops.push_back({{models::rational_circle_2d({0.5, 0.5}, 0.1, false)}, false});
  square.surface = models::bilinear_patch({{{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {-0.1, 0.1, 0}, {0.1, 0.1, 0}}});
  // The rim's polygon is inscribed in the circle: its points lie up to 1e-5 inside radius 1.
  const double flat = 1e-4;
  for (const auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
    CAPTURE(int(search));
    queries::PointDistanceQuery q(gpu, {plate}, 1e-3, 1LL << 22, search);
    if (search == queries::Search::Faithful) REQUIRE(q.grids()[0].grid.cells_u() * q.grids()[0].grid.cells_v() == 1);
    for (const glm::dvec3 p : {glm::dvec3(5, 5, 2), glm::dvec3(5.5, 5, 2), glm::dvec3(5, 4.8, 0.5)}) {
      CAPTURE(p.x);
      CAPTURE(p.y);
      CAPTURE(p.z);
      const queries::PointDistance d = q.query(p);
      REQUIRE(d.found);
      const glm::dvec2 r(p.x - 5, p.y - 5);
      const double truth = std::hypot(1.0 - glm::length(r), p.z);
      CHECK(std::abs(d.distance - truth) <= d.bound + flat);
      CHECK(std::abs(glm::length(glm::dvec2(d.point) - glm::dvec2(5, 5)) - 1.0) <= flat);
      // (coarse-to-fine: its material point may stop within T of the rim, in a cell the rim misses)
      if (search == queries::Search::Faithful) CHECK(d.on_trim_edge);
    }
    // A square of side 0.2 at height 0.5 over the hole's centre: its corners are the nearest to the rim.
    const auto a = queries::prepare_model(gpu, {plate}, 1e-3, 1LL << 22, search);
    const auto b = queries::prepare_model(gpu, {square}, 1e-3, 1LL << 22, search);
    const queries::Clearance c = queries::clearance(gpu, a, b, glm::translate(glm::dmat4(1.0), glm::dvec3(5, 5, 0.5)));
    REQUIRE(c.found);
    const double truth = std::hypot(1.0 - 0.1 * std::sqrt(2.0), 0.5);
    CHECK(std::abs(c.distance - truth) <= c.bound + flat);
    CHECK(c.on_trim_edge);
    MESSAGE(std::string(search == queries::Search::Faithful ? "faithful" : "coarse-to-fine")
            << ": clearance " << c.distance << " +- " << c.bound << " (truth " << truth << ")");
  }
}
