// The object first stage of Krishnamurthy et al. §5.4 (queries/distance/voxel_stage.h): the GPU pass against
// its CPU twin in double on random trimmed models under random rigid motions, tiling, and on exact
// spheres (closest face pair known in closed form) that the face pair holding the closest points
// is always kept, that U is an honest upper bound, and that the stage prunes face pairs at all.
#include <doctest/doctest.h>

#include <algorithm>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "tests/shared_models.h"
#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/clearance.h"
#include "queries/distance/voxel_stage.h"

namespace {

/// A rigid motion: a random rotation about a random axis through the origin, then `shift`.
glm::dmat4 random_motion(models::Random& rng, const glm::dvec3& shift) {
  const glm::dvec3 axis(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.1, 1));
  return glm::translate(glm::dmat4(1.0), shift) * glm::rotate(glm::dmat4(1.0), rng.uniform(0, 6.28), axis);
}

/// `count` random trimmed faces, face k moved by k * `step`: a multi-face model spread along a line.
std::vector<nurbs::TrimmedSurface> random_model(uint64_t seed, int count, const glm::dvec3& step) {
  std::vector<nurbs::TrimmedSurface> faces;
  for (int k = 0; k < count; ++k) {
    faces.push_back(models::random_trimmed_surface(seed + uint64_t(k)));
    for (auto& p : faces.back().surface.points) p += double(k) * step;
  }
  return faces;
}

/// The faces listed by the voxel of `g` that holds point `p` (empty when that voxel is not occupied).
std::vector<int> faces_at(const queries::VoxelGrid& g, const glm::dvec3& p) {
  const glm::ivec3 v = glm::clamp(glm::ivec3(glm::floor((p - g.lo) / g.h)), glm::ivec3(0), glm::ivec3(g.n - 1));
  const int index = v.x + g.n * (v.y + g.n * v.z);
  const auto it = std::lower_bound(g.voxels.begin(), g.voxels.end(), index);
  if (it == g.voxels.end() || *it != index) return {};
  const size_t k = size_t(it - g.voxels.begin());
  return {g.faces.begin() + g.face_begin[k], g.faces.begin() + g.face_begin[k + 1]};
}

}  // namespace

TEST_CASE("voxel stage: GPU face pairs equal the CPU twin on random trimmed models and motions") {
  gpgpu::Gpu& gpu = test::gpu();
  long long pairs = 0, kept = 0, borderline = 0;
  for (uint64_t seed = 0; seed < 4; ++seed) {
    models::Random rng(seed + 17);
    const auto a = queries::voxelize(random_model(100 + 10 * seed, 3, {2.5, 0.0, 0.0}), {.n = 12 + 4 * int(seed % 3)});
    const auto b = queries::voxelize(random_model(500 + 10 * seed, 3, {0.0, 2.5, 0.5}), {.n = 16});
    const glm::dmat4 motion = random_motion(rng, {rng.uniform(-2, 4), rng.uniform(-2, 2), rng.uniform(2, 4)});
    const queries::VoxelStage g = queries::voxel_stage(gpu, a, b, motion);
    const queries::VoxelStage c = queries::voxel_stage_cpu(a, b, motion);
    CAPTURE(seed);
    REQUIRE(std::isfinite(c.upper));
    CHECK(std::abs(g.upper - c.upper) <= 1e-6 * c.upper);  // float boxes rounded outwards, float distances
    CHECK(g.face_pairs == c.face_pairs);
    CHECK(std::abs(g.surviving_pairs - c.surviving_pairs) <= c.borderline_pairs);
    CHECK(g.faces_a == c.faces_a);
    CHECK(g.faces_b == c.faces_b);
    CHECK(g.voxel_pairs == (long long)(a.voxels.size() * b.voxels.size()));
    pairs += g.voxel_pairs;
    kept += g.surviving_pairs;
    borderline += c.borderline_pairs;
  }
  MESSAGE(pairs << " voxel pairs, " << kept << " survive, " << borderline << " within rounding of the cut");
}

TEST_CASE("voxel stage: tiles of the pair texture, culled or not, give the same pairs as one tile") {
  gpgpu::Gpu& gpu = test::gpu();
  models::Random rng(5);
  // Faces spread along x (A, x in about [-1, 7]) and y (B), B moved beyond A's last face: the tiles
  // of A's first faces are far from the answer.
  const auto a = queries::voxelize(random_model(40, 3, {3.0, 0.0, 0.0}), {.n = 16});
  const auto b = queries::voxelize(random_model(60, 3, {0.0, 3.0, 0.0}), {.n = 16});
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), {12.0, -3.0, 0.0}) * random_motion(rng, {0, 0, 0});
  const queries::VoxelStage one = queries::voxel_stage(gpu, a, b, motion);
  // 257: prime, so the last row and column of tiles are partial.
  const queries::VoxelStage tiled = queries::voxel_stage(gpu, a, b, motion, {.max_tile = 257});
  CHECK(one.tiles == 1);
  CHECK(tiled.tiles == int(((a.voxels.size() + 256) / 257) * ((b.voxels.size() + 256) / 257)));
  CHECK(tiled.upper == one.upper);
  CHECK(tiled.surviving_pairs == one.surviving_pairs);
  CHECK(tiled.face_pairs == one.face_pairs);
  // Culling tiles (beyond the paper) changes nothing but the work.
  const queries::VoxelStage culled = queries::voxel_stage(gpu, a, b, motion, {.max_tile = 257, .cull_tiles = true});
  CHECK(culled.upper == one.upper);
  CHECK(culled.surviving_pairs == one.surviving_pairs);
  CHECK(culled.face_pairs == one.face_pairs);
  CHECK(culled.culled_tiles > 0);
  MESSAGE(tiled.tiles << " tiles, " << culled.culled_tiles << " culled");
}

TEST_CASE("voxel stage: exact spheres keep the closest face pair, U bounds the distance, pairs are pruned") {
  gpgpu::Gpu& gpu = test::gpu();
  int cases = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    models::Random rng(seed + 1000);
    // Four spheres per object spread over a 12-wide box: faces far apart, so most pairs are pruned.
    std::vector<nurbs::TrimmedSurface> fa(4), fb(4);
    std::vector<glm::dvec3> ca, cb;
    std::vector<double> ra, rb;
    for (int k = 0; k < 4; ++k) {
      ca.emplace_back(rng.uniform(0, 12), rng.uniform(0, 12), rng.uniform(0, 3));
      cb.emplace_back(rng.uniform(0, 12), rng.uniform(0, 12), rng.uniform(0, 3));
      ra.push_back(rng.uniform(0.5, 1.5));
      rb.push_back(rng.uniform(0.5, 1.5));
      fa[size_t(k)].surface = models::rational_sphere(ra.back(), ca.back());
      fb[size_t(k)].surface = models::rational_sphere(rb.back(), cb.back());
    }
    const glm::dmat4 motion = random_motion(rng, {rng.uniform(-1, 1), rng.uniform(-1, 1), 6.0 + rng.uniform(0, 2)});
    // Exact distances of the sphere pairs (B's centres moved); the closest pair must be unique.
    std::vector<std::pair<double, std::pair<int, int>>> d;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const glm::dvec3 c(motion * glm::dvec4(cb[size_t(j)], 1.0));
        d.push_back({glm::length(ca[size_t(i)] - c) - ra[size_t(i)] - rb[size_t(j)], {i, j}});
      }
    std::sort(d.begin(), d.end());
    CAPTURE(seed);
    if (d[0].first <= 0.0 || d[1].first - d[0].first < 1e-3) continue;  // touching or ambiguous: not this test
    const auto a = queries::voxelize(fa, {.n = 20}), b = queries::voxelize(fb, {.n = 20});
    for (const queries::VoxelStage& s :
         {queries::voxel_stage(gpu, a, b, motion), queries::voxel_stage_cpu(a, b, motion)}) {
      CHECK(s.upper >= d[0].first);  // witnesses hold surface points: U is an upper bound
      CHECK(std::binary_search(s.face_pairs.begin(), s.face_pairs.end(), d[0].second));
      CHECK(s.face_pairs.size() < 16);
      CHECK(s.surviving_pairs < s.voxel_pairs);
    }
    ++cases;
  }
  CHECK(cases >= 4);
}

TEST_CASE("voxel stage: the voxel grid lists every face of a dense sample of material points") {
  // Conservative occupancy: sample each trimmed face far finer than its coarse grid, keep the
  // material points, and find each one's face in the voxel holding it.
  const auto faces = random_model(900, 3, {1.5, 0.5, 0.0});
  const queries::VoxelGrid g = queries::voxelize(faces, {.n = 32});
  long long checked = 0;
  for (int f = 0; f < 3; ++f) {
    const auto& s = faces[size_t(f)].surface;
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const auto trim = nurbs::flatten_trim(faces[size_t(f)], 1e-6 * du.width());
    for (int j = 0; j <= 60; ++j)
      for (int i = 0; i <= 60; ++i) {
        const glm::dvec2 uv(du.min + du.width() * i / 60.0, dv.min + dv.width() * j / 60.0);
        if (!faces[size_t(f)].loops.empty() && !nurbs::is_material(trim, uv)) continue;
        const std::vector<int> listed = faces_at(g, nurbs::surface_point(s, uv.x, uv.y));
        CHECK(std::binary_search(listed.begin(), listed.end(), f));
        ++checked;
      }
  }
  CHECK(std::count(g.witness.begin(), g.witness.end(), 1) > 0);
  MESSAGE(checked << " material samples, " << g.voxels.size() << " occupied voxels of " << g.n * g.n * g.n);
}

TEST_CASE("voxel stage: a material island between the corners of a cell keeps its voxel (§5.3)") {
  // A 10 x 10 plane trimmed to a disc of parameter radius 0.01 inside one grid cell (8^3 voxels:
  // cells of 1/16 of the domain): no grid sample is material, so the corner test alone (the GPU
  // leaf pass) would drop the whole face; the trim edge through the cell keeps it.
  nurbs::TrimmedSurface f;
  f.surface = {1, 1, 2, 2, {0, 0, 1, 1}, {0, 0, 1, 1}, {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}}, {}};
  const glm::dvec2 centre(0.34, 0.35);
  f.loops.push_back({{models::rational_circle_2d(centre, 0.01, true)}, true});
  const queries::VoxelGrid g = queries::voxelize({f}, {.n = 8});
  CHECK(g.cells - g.skipped_cells >= 1);
  CHECK(g.cells - g.skipped_cells <= 4);
  const std::vector<int> listed = faces_at(g, nurbs::surface_point(f.surface, centre.x + 0.005, centre.y));
  CHECK(listed == std::vector<int>{0});
  CHECK(std::count(g.witness.begin(), g.witness.end(), 1) == 0);  // no material sample: no upper bound
}

TEST_CASE("voxel stage: teapot beside the vase wall, GPU = twin, the clearance's face pair kept" *
          test::needs_shared_models()) {
  // The pair of experiments/bench_voxel_stage.cpp (its default move), at 16^3 voxels to stay fast.
  gpgpu::Gpu& gpu = test::gpu();
  const nurbs::Model vase = nurbs::io::read_model(test::shared_models_dir() / "generated/vase_shell_t2.igs");
  const nurbs::Model teapot = nurbs::io::read_model(test::shared_models_dir() / "generated/teapot_bezier32.igs");
  const auto fa = nurbs::world_faces(vase), fb = nurbs::world_faces(teapot);
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), {33.75, 0.0, 48.65});
  const auto a = queries::voxelize(fa, {.n = 16}), b = queries::voxelize(fb, {.n = 16});
  const queries::VoxelStage g = queries::voxel_stage(gpu, a, b, motion), c = queries::voxel_stage_cpu(a, b, motion);
  CHECK(g.face_pairs == c.face_pairs);
  CHECK(std::abs(g.surviving_pairs - c.surviving_pairs) <= c.borderline_pairs);
  CHECK(g.face_pairs.size() < fa.size() * fb.size());
  // The hierarchy search over all faces (clearance.h) at 5e-4 of the vase size: its closest points
  // are within its bound of the true ones, far less than a voxel, so its face pair must be kept.
  const double tol = 5e-4 * nurbs::model_size(vase);
  const queries::PreparedModel pa = queries::prepare_model(gpu, fa, tol), pb = queries::prepare_model(gpu, fb, tol);
  const queries::Clearance cl = queries::clearance(gpu, pa, pb, motion);
  // A prepared model (its Filip bounds and trim polygons) gives the same voxel grid as its faces.
  const queries::VoxelGrid ap = queries::voxelize(pa, {.n = 16});
  CHECK(ap.voxels == a.voxels);
  CHECK(ap.faces == a.faces);
  CHECK(ap.witness == a.witness);
  REQUIRE(cl.found);
  CHECK(g.upper >= cl.distance - cl.bound);
  CHECK(std::binary_search(g.face_pairs.begin(), g.face_pairs.end(), std::pair{cl.face_a, cl.face_b}));
  MESSAGE("clearance " << cl.distance << " (faces " << cl.face_a << ", " << cl.face_b << "), U " << g.upper << ", "
                       << g.face_pairs.size() << " of " << fa.size() * fb.size() << " face pairs kept");
}

TEST_CASE("voxel stage: a model without faces gives no pairs and no upper bound") {
  const queries::VoxelGrid empty = queries::voxelize(std::vector<nurbs::TrimmedSurface>{});
  const queries::VoxelGrid b = queries::voxelize(random_model(7, 2, {2.0, 0.0, 0.0}), {.n = 8});
  for (const queries::VoxelStage& s :
       {queries::voxel_stage(test::gpu(), empty, b), queries::voxel_stage_cpu(empty, b)}) {
    CHECK(s.voxels_a == 0);
    CHECK(s.voxel_pairs == 0);
    CHECK(s.face_pairs.empty());
    CHECK(s.faces_b == std::vector<char>(2, 0));
    CHECK(std::isinf(s.upper));
  }
}
