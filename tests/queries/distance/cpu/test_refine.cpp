// The coarse-to-fine refinement (queries/distance/refine.h) on the CPU, from every cell of a coarse grid,
// against independent references in double: the answer is realised by material surface points, the
// true distance lies in [distance - bound, distance], and bound <= T.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/point_distance.h"
#include "queries/distance/refine.h"
#include "test_suites.h"
#include "tests/queries/distance/distance_reference.h"

namespace {

/// Every cell of every face's grid: the candidates a GPU search that pruned nothing would return.
std::vector<queries::FaceCell> all_cells(const queries::PreparedModel& m) {
  std::vector<queries::FaceCell> out;
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int j = 0; j < m.grids[f].grid.cells_v(); ++j)
      for (int i = 0; i < m.grids[f].grid.cells_u(); ++i) out.push_back({int(f), i, j});
  return out;
}

std::vector<std::pair<queries::FaceCell, queries::FaceCell>> all_pairs(const queries::PreparedModel& a,
                                                                       const queries::PreparedModel& b) {
  std::vector<std::pair<queries::FaceCell, queries::FaceCell>> out;
  for (const auto& x : all_cells(a))
    for (const auto& y : all_cells(b)) out.emplace_back(x, y);
  return out;
}

}  // namespace

TEST_CASE("refine: point distance on random surfaces, proven interval against Newton references" * test::sweep()) {
  int cases = 0;
  double worst = 0.0;
  for (uint64_t seed = 0; seed < 12; ++seed) {
    nurbs::TrimmedSurface face;
    face.surface = models::random_surface(seed + 40, 1 + int(seed % 4), 1 + int(seed / 4 % 3), seed % 2 == 1);
    const double size = nurbs::control_box(face.surface).diagonal(), tol = 1e-5 * size;
    const auto m = queries::prepare_geometry({face}, tol, 1LL << 22, queries::Search::CoarseToFine);
    CHECK(m.grid_tolerance > 40 * tol);  // coarse grids: the refinement does the work
    models::Random rng(seed);
    for (int k = 0; k < 5; ++k) {
      const glm::dvec3 p(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
      const queries::Refined r = queries::refine_point(m, all_cells(m), p, tol);
      const test::Reference ref = test::reference(face.surface, p, r.uv_a);
      CAPTURE(seed);
      CAPTURE(k);
      test::check_proven(r.found, r.meets_tolerance, r.distance, r.bound, tol, ref.distance, 1e-12 * size);
      // Realised: the point is the surface at uv, at the reported distance.
      CHECK(glm::length(r.point_a - nurbs::surface_point(face.surface, r.uv_a.x, r.uv_a.y)) <= 1e-14 * size);
      CHECK(std::abs(glm::length(r.point_a - p) - r.distance) <= 1e-14 * size);
      worst = std::max(worst, (r.distance - ref.distance) / tol);
      ++cases;
    }
  }
  MESSAGE(cases << " points: distance - reference <= " << worst << " T");
}

TEST_CASE("refine: trimmed faces, the answer is material and below every material sample") {
  for (uint64_t seed = 0; seed < 8; ++seed) {
    const nurbs::TrimmedSurface face = models::random_trimmed_surface(seed);
    const double size = nurbs::control_box(face.surface).diagonal(), tol = 1e-5 * size;
    const auto m = queries::prepare_geometry({face}, 1e-2 * size);
    const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
    models::Random rng(seed + 5);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
      const queries::Refined r = queries::refine_point(m, all_cells(m), p, tol);
      CAPTURE(seed);
      CAPTURE(k);
      REQUIRE(r.found);
      CHECK(r.bound <= tol);
      CHECK(nurbs::is_material(m.trims[0], r.uv_a));
      // No material sample is closer than the proven lower bound.
      double sampled = 1e300;
      for (int j = 0; j <= 60; ++j)
        for (int i = 0; i <= 60; ++i) {
          const glm::dvec2 uv(du.min + du.width() * i / 60, dv.min + dv.width() * j / 60);
          if (nurbs::is_material(m.trims[0], uv))
            sampled = std::min(sampled, glm::length(nurbs::surface_point(face.surface, uv.x, uv.y) - p));
        }
      CHECK(sampled >= r.distance - r.bound - 1e-12 * size);
    }
  }
}

TEST_CASE("refine: exact spheres moved, the gap lies in the proven interval") {
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  const double tol = 1e-5;
  // Grids at 2e-2 so that every cell pair can be the start (the GPU search prunes them in use).
  const auto a = queries::prepare_geometry({s1}, 2e-2);
  const auto b = queries::prepare_geometry({s2}, 2e-2);
  for (double gap : {0.01, 0.7, 3.0}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1, 2, -0.5));
    const glm::dmat4 motion =
        glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir) * glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0.3, 1, 0.2));
    const queries::Refined r = queries::refine_pairs(a, b, motion, all_pairs(a, b), tol);
    CAPTURE(gap);
    test::check_proven(r.found, r.meets_tolerance, r.distance, r.bound, tol, gap, 1e-12);
    CHECK(std::abs(glm::length(r.point_a - r.point_b) - r.distance) < 1e-12);
    CHECK(std::abs(glm::length(r.point_a) - 1.0) < 1e-12);
    CHECK(glm::length(r.point_a - dir) < 0.01);
    MESSAGE("gap " << gap << ": " << r.distance << " - " << r.bound << ", " << r.rounds << " rounds, " << r.cells
                   << " cells, at most " << r.most_pairs << " pairs");
  }
}

TEST_CASE("refine: surface pairs, the lower bound holds against alternating projections") {
  for (uint64_t seed = 0; seed < 5; ++seed) {
    nurbs::TrimmedSurface fa, fb;
    fa.surface = models::random_surface(seed + 300, 1 + int(seed % 3), 2, seed % 2 == 1);
    fb.surface = models::random_surface(seed + 700, 2, 1 + int(seed % 3), seed % 3 == 1);
    const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 2.0 + 0.1 * double(seed)));
    const double tol = 1e-5 * 3.0;
    const auto a = queries::prepare_geometry({fa}, 5e-2), b = queries::prepare_geometry({fb}, 5e-2);
    const queries::Refined r = queries::refine_pairs(a, b, motion, all_pairs(a, b), tol);
    CAPTURE(seed);
    REQUIRE(r.found);
    CHECK(r.bound <= tol);
    // Reference: alternate closest-point projections from the answer's own points (each step a
    // realised distance that cannot increase), ending at a local minimum of the pair.
    nurbs::Surface moved = fb.surface;
    for (auto& p : moved.points) p = glm::dvec3(motion * glm::dvec4(p, 1.0));
    glm::dvec3 pa = r.point_a, pb = r.point_b;
    double d = glm::length(pa - pb);
    for (int it = 0; it < 2; ++it) {
      pb = test::reference(moved, pa, r.uv_b).point;
      pa = test::reference(fa.surface, pb, r.uv_a).point;
      d = std::min(d, glm::length(pa - pb));
    }
    CHECK(d <= r.distance + 1e-12);
    CHECK(d >= r.distance - r.bound - 1e-12);
  }
}

TEST_CASE("refine: the cases the paper warns about: contact, a point on the surface, a point over a pole") {
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  const double tol = 1e-5;
  const auto a = queries::prepare_geometry({s1}, 2e-2), b = queries::prepare_geometry({s2}, 2e-2);
  // Intersecting and touching spheres: distance 0 within the bound, the two points together.
  for (double gap : {-0.4, 0.0}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.2, -1, 0.7));
    const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir);
    const queries::Refined r = queries::refine_pairs(a, b, motion, all_pairs(a, b), tol);
    CAPTURE(gap);
    test::check_proven(r.found, r.meets_tolerance, r.distance, r.bound, tol, 0.0, 1e-12);
    CHECK(glm::length(r.point_a - r.point_b) <= tol);
    CHECK(std::abs(glm::length(r.point_a) - 1.0) < 1e-12);  // on the first sphere
  }
  // Points on the surface, and over both poles of the sphere's parametrisation (axis z).
  models::Random rng(7);
  for (int k = 0; k < 6; ++k) {
    const glm::dvec3 on = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    const queries::Refined r = queries::refine_point(a, all_cells(a), on, tol);
    test::check_proven(r.found, r.meets_tolerance, r.distance, r.bound, tol, 0.0, 1e-12);
  }
  for (double z : {1.5, -1.5, 0.25}) {
    const queries::Refined r = queries::refine_point(a, all_cells(a), {0.0, 0.0, z}, tol);
    CAPTURE(z);
    test::check_proven(r.found, r.meets_tolerance, r.distance, r.bound, tol, std::abs(std::abs(z) - 1.0), 1e-12);
  }
}

TEST_CASE("refine: parallel slanted trim edges of planes are proven by the cells the edges cut") {
  // Two planes cut to triangles by slanted edges (their domains reach 0.1 beyond the trim, as the
  // readers' planes do); B turned half a turn and moved so that the two long edges run parallel,
  // 0.4 apart in the plane and 0.3 above: every point of one edge lies 0.5 from the other. A cell an
  // edge cuts bounds its material side alone (its pieces), so a small pair budget proves 0.5; with
  // whole-cell boxes the equidistant pairs along the edges split until the budget ran out.
  auto triangle_face = [] {
    nurbs::TrimmedSurface f;
    nurbs::Surface& s = f.surface;
    s.degree_u = s.degree_v = 1;
    s.count_u = s.count_v = 2;
    s.knots_u = s.knots_v = {-0.1, -0.1, 1.1, 1.1};
    s.points = {{-0.1, -0.1, 0.0}, {1.1, -0.1, 0.0}, {-0.1, 1.1, 0.0}, {1.1, 1.1, 0.0}};
    nurbs::TrimLoop loop;
    loop.outer = true;
    const glm::dvec2 p[3] = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
    for (int k = 0; k < 3; ++k) {
      nurbs::Curve<2> c;
      c.degree = 1;
      c.knots = {0.0, 0.0, 1.0, 1.0};
      c.points = {p[k], p[(k + 1) % 3]};
      loop.curves.push_back(c);
    }
    f.loops.push_back(loop);
    return f;
  };
  const double tol = 1e-4;
  const auto a = queries::prepare_geometry({triangle_face()}, tol, 1LL << 22, queries::Search::CoarseToFine);
  const auto b = queries::prepare_geometry({triangle_face()}, tol, 1LL << 22, queries::Search::CoarseToFine);
  const glm::dvec3 centre(0.5, 0.5, 0.0), along = glm::normalize(glm::dvec3(1.0, 1.0, 0.0));
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), centre + 0.4 * along + glm::dvec3(0.0, 0.0, 0.3)) *
                            glm::rotate(glm::dmat4(1.0), M_PI, glm::dvec3(0.0, 0.0, 1.0)) *
                            glm::translate(glm::dmat4(1.0), -centre);
  queries::RefineLimits limits;
  limits.max_pairs = 1 << 14;
  const auto r = queries::refine_all_pairs(a, b, motion, 2 * tol, std::numeric_limits<double>::infinity(), -1, limits);
  REQUIRE(r.has_value());
  REQUIRE(r->found);
  MESSAGE("distance " << r->distance << " +- " << r->bound << " in " << r->rounds << " rounds, " << r->cells << " cells");
  CHECK(r->meets_tolerance);
  CHECK(r->bound <= 2 * tol);
  CHECK(std::abs(r->distance - 0.5) <= r->bound + 1e-12);
}
