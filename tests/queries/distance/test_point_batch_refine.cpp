// The batched point projection finished by refinement (point_batch.h, BatchFinish::refine in
// point_batch_finish.h): on coarse grids (Search::CoarseToFine) every answer is refined in double to
// T, and on faithful grids so is every answer whose float bound exceeds T (points far from the
// model). Both against the per-point coarse-to-fine query (refine.h): the same distances within
// both bounds, every bound within T wherever the point lies.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "nurbs/model_ops.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/point_distance.h"
#include "tests/queries/distance/point_batch_fixtures.h"

namespace {

/// Points near the faces, then points 1e4 model sizes away (where the float pass's bound is
/// 2 kFloatSlack 1e4 sizes, about 2e-2 of the size: far over the tolerances below, 1e-5 and 1e-3).
std::vector<glm::dvec3> near_and_far(const std::vector<nurbs::TrimmedSurface>& faces, double size) {
  std::vector<glm::dvec3> points = test::random_points(faces, 24, 5);
  for (const glm::dvec3 d : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0.6, 0.0, 0.8)})
    points.push_back(points.front() + 1e4 * size * d);
  return points;
}

void check_against_per_point(gpgpu::Gpu& gpu, const std::vector<nurbs::TrimmedSurface>& faces,
                             const std::vector<glm::dvec3>& points, const std::vector<queries::PointDistance>& res,
                             double tol) {
  queries::PointDistanceQuery ref(gpu, faces, tol, 1LL << 22, queries::Search::CoarseToFine);
  for (size_t i = 0; i < points.size(); ++i) {
    CAPTURE(i);
    const queries::PointDistance& r = res[i];
    REQUIRE(r.found);
    CHECK(r.meets_tolerance);
    CHECK(r.bound <= tol);
    const queries::PointDistance e = ref.query(points[i]);
    CHECK(std::abs(r.distance - e.distance) <= r.bound + e.bound);
  }
}

/// The largest control-box diagonal of the faces.
double size_of(const std::vector<nurbs::TrimmedSurface>& faces) {
  double size = 0.0;
  for (const auto& f : faces) size = std::max(size, nurbs::control_box(f.surface).diagonal());
  return size;
}

}  // namespace

TEST_CASE("point batch: coarse grids, every answer refined in double to T, near the model or far from it") {
  gpgpu::Gpu& gpu = test::gpu();
  const auto faces = test::spread_faces(4);
  const double size = size_of(faces);
  const double tol = 1e-5 * size;
  queries::PreparedModel m = queries::prepare_geometry(faces, tol, 1LL << 22, queries::Search::CoarseToFine);
  queries::prepare_atlases(gpu, m);
  queries::PointBatch batch(gpu, m);
  const std::vector<glm::dvec3> points = near_and_far(faces, size);
  for (const queries::BatchEngine engine : {queries::BatchEngine::Gpu, queries::BatchEngine::Cpu}) {
    batch.set_engine(engine);
    const auto res = batch.query(points);
    CHECK(batch.stats().refined_cells > 0);
    check_against_per_point(gpu, faces, points, res, tol);
  }
}

TEST_CASE("point batch: faithful grids, the answers whose float bound is over T refined to T") {
  gpgpu::Gpu& gpu = test::gpu();
  const auto faces = test::spread_faces(3);
  const double size = size_of(faces);
  const double tol = 1e-3 * size;
  const int side = std::min(gpu.info().max_texture_size, 4096);
  queries::PreparedModel m = queries::prepare_batch_geometry(faces, tol, 1LL << 22, side,
                                                             queries::PointBoxes::Oriented, 1LL << 30);
  REQUIRE(m.search == queries::Search::Faithful);
  queries::prepare_atlases(gpu, m, side);
  queries::PointBatch batch(gpu, m);
  batch.set_refine_tolerance(tol);
  const std::vector<glm::dvec3> points = near_and_far(faces, size);
  const auto res = batch.query(points);
  check_against_per_point(gpu, faces, points, res, tol);
  // The near points keep the pass's answers; only the far ones were refined.
  for (size_t i = 0; i + 3 < points.size(); ++i) CHECK(res[i].refined_cells == 0);
  for (size_t i = points.size() - 3; i < points.size(); ++i) CHECK(res[i].refined_cells > 0);
}

TEST_CASE("point batch: a model whose faithful grids exceed the byte limit gets coarse grids") {
  gpgpu::Gpu& gpu = test::gpu();
  const auto faces = test::spread_faces(3);
  const double tol = 1e-4 * nurbs::control_box(faces.front().surface).diagonal();
  const int side = std::min(gpu.info().max_texture_size, 4096);
  const queries::PreparedModel m =
      queries::prepare_batch_geometry(faces, tol, 1LL << 22, side, queries::PointBoxes::Oriented, 1LL << 20);
  CHECK(m.search == queries::Search::CoarseToFine);
  CHECK(m.tolerance == tol);
}
