// Clearance (Krishnamurthy et al. §5.1-5.3): the GPU hierarchy descent against an exhaustive CPU
// twin over all cell pairs (same triangles in double), exact spheres (|d - d*| < K_a + K_b), and a
// rigid motion applied in the leaf pass against the same model moved beforehand.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "tests/gpgpu/gl_fixture.h"
#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/clearance.h"
#include "queries/distance/prepared_model.h"
#include "queries/distance/voxel_stage.h"
#include "test_suites.h"
#include "tests/queries/distance/distance_reference.h"

namespace {

/// Every cell pair of the two models, two triangles each, in double: the exhaustive twin (a pair is
/// skipped only when the exact distance of the triangles' boxes already exceeds the best so far).
double brute_force(const queries::PreparedModel& a, const queries::PreparedModel& b) {
  double best = 1e300;
  auto tris = [](const queries::PreparedModel& m, size_t f) {
    std::vector<std::array<glm::dvec3, 3>> out;
    const auto& g = m.grids[f].grid;
    const auto& s = m.faces[f].surface;
    for (int j = 0; j < g.cells_v(); ++j)
      for (int i = 0; i < g.cells_u(); ++i) {
        const auto p = [&](int di, int dj) {
          return nurbs::surface_point(s, g.u[size_t(i + di)], g.v[size_t(j + dj)]);
        };
        out.push_back({p(0, 0), p(1, 0), p(1, 1)});
        out.push_back({p(0, 0), p(1, 1), p(0, 1)});
      }
    return out;
  };
  for (size_t fa = 0; fa < a.faces.size(); ++fa)
    for (size_t fb = 0; fb < b.faces.size(); ++fb) {
      const auto ta = tris(a, fa), tb = tris(b, fb);
      auto box = [](const std::array<glm::dvec3, 3>& t) {
        return std::pair{glm::min(glm::min(t[0], t[1]), t[2]), glm::max(glm::max(t[0], t[1]), t[2])};
      };
      std::vector<std::pair<glm::dvec3, glm::dvec3>> bb;
      for (const auto& y : tb) bb.push_back(box(y));
      for (const auto& x : ta) {
        const auto [lo, hi] = box(x);
        for (size_t k = 0; k < tb.size(); ++k) {
          const glm::dvec3 gap = glm::max(glm::max(bb[k].first - hi, lo - bb[k].second), glm::dvec3(0.0));
          if (glm::length(gap) >= best) continue;
          glm::dvec3 pa, pb, wa, wb;
          best = std::min(best, queries::triangle_distance(x.data(), tb[k].data(), pa, pb, wa, wb));
        }
      }
    }
  return best;
}

}  // namespace

TEST_CASE("clearance: hierarchy descent equals the exhaustive twin on random surface pairs" * test::sweep()) {
  gpgpu::Gpu& gpu = test::gpu();
  int cases = 0;
  size_t max_levels = 0;
  int chunked_levels = 0;  // levels whose input pairs needed more than one chunk of 1024
  int host_levels = 0;     // levels whose input pairs came from the host, a chunk at a time
  // K_e <= 2e-2 on surfaces about 3 wide; the twin prunes triangle pairs by exact box distances.
  for (uint64_t seed = 0; seed < 8; ++seed) {
    nurbs::TrimmedSurface fa, fb;
    fa.surface = models::random_surface(seed + 300, 1 + int(seed % 3), 2, seed % 2 == 1);
    fb.surface = models::random_surface(seed + 700, 2, 1 + int(seed % 3), seed % 3 == 1);
    for (auto& p : fb.surface.points) p += glm::dvec3(0.3, -0.2, 2.0 + 0.1 * double(seed));
    const auto a = queries::prepare_model(gpu, {fa}, 2e-2);
    const auto b = queries::prepare_model(gpu, {fb}, 2e-2);
    const queries::Clearance c = queries::clearance(gpu, a, b);
    CAPTURE(seed);
    REQUIRE(c.found);
    CHECK(c.distance == doctest::Approx(brute_force(a, b)).epsilon(1e-12));
    CHECK(c.bound <= 4e-2);  // K_a + K_b
    CHECK(std::abs(glm::length(c.point_a - c.point_b) - c.distance) < 1e-12);
    max_levels = std::max(max_levels, c.pairs_per_level.size());
    // The chunked descent (1024 pairs per chunk here) keeps the same pairs and finds the same answer;
    // on one seed with many pairs (it costs a second descent in chunks). A level that keeps more than
    // a chunk leaves its pairs on the host, uploaded a chunk at a time by the next level.
    if (seed == 3) {
      const queries::Clearance chunked = queries::clearance(gpu, a, b, glm::dmat4(1.0), nullptr, nullptr, {1024});
      CHECK(chunked.distance == c.distance);
      CHECK(chunked.pairs_per_level == c.pairs_per_level);
      for (size_t l = 0; l + 1 < c.pairs_per_level.size(); ++l) {
        chunked_levels += c.pairs_per_level[l] > 1024 ? 1 : 0;
        // Kept more than a chunk by a chunked level: the next level reads them from the host.
        host_levels += l > 0 && c.pairs_per_level[l - 1] > 1024 && c.pairs_per_level[l] > 1024 ? 1 : 0;
      }
    }
    ++cases;
  }
  MESSAGE(cases << " pairs, up to " << max_levels << " levels, " << chunked_levels << " chunked levels, " << host_levels
                << " from the host");
  CHECK(chunked_levels > 0);
  CHECK(host_levels > 0);
}

TEST_CASE("clearance: two exact spheres, and a rigid motion of the second") {
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  const auto a = queries::prepare_model(gpu, {s1}, 1e-3);
  const auto b = queries::prepare_model(gpu, {s2}, 1e-3);
  queries::ClearanceCache cache;  // A's hierarchy across the motions: the same answers as without
  for (double gap : {0.05, 0.7, 3.0}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1, 2, -0.5));
    // Rotate the second sphere about an axis through its centre (no change), then move it.
    const glm::dmat4 motion =
        glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir) * glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0.3, 1, 0.2));
    const queries::Clearance c = queries::clearance(gpu, a, b, motion);
    const queries::Clearance cc = queries::clearance(gpu, a, b, motion, nullptr, nullptr, {}, &cache);
    CHECK(cc.distance == c.distance);
    CHECK(cc.point_a == c.point_a);
    CHECK(cc.pairs_per_level == c.pairs_per_level);
    CAPTURE(gap);
    REQUIRE(c.found);
    CHECK(std::abs(c.distance - gap) < c.bound);
    CHECK(c.bound <= 2e-3);
    CHECK(glm::length(c.point_a - dir) < 0.1);  // near the true closest point of the first sphere
    // Theorem 2 (position bound): each sphere's nearest point to the other's closest point lies
    // within point_bound() of the point found on it.
    CHECK(glm::length(c.point_a - glm::normalize(c.point_b)) <= c.point_bound());
    const glm::dvec3 centre_b = (3.0 + gap) * dir;
    CHECK(glm::length(c.point_b - (centre_b + 2.0 * glm::normalize(c.point_a - centre_b))) <= c.point_bound());
    MESSAGE("gap " << gap << ": distance " << c.distance << " +- " << c.bound << ", pairs per level "
                   << c.pairs_per_level.size() << " levels, " << c.leaf_pairs << " leaf pairs");
  }
}

TEST_CASE("clearance: coarse-to-fine search on exact spheres and random pairs, against the faithful path" *
          test::sweep()) {
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  const double tol = 1e-4;
  const auto a = queries::prepare_model(gpu, {s1}, tol, 1LL << 22, queries::Search::CoarseToFine);
  const auto b = queries::prepare_model(gpu, {s2}, tol, 1LL << 22, queries::Search::CoarseToFine);
  for (double gap : {0.02, 1.5}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(-1, 0.4, 2));
    const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir);
    const queries::Clearance c = queries::clearance(gpu, a, b, motion);
    CAPTURE(gap);
    // The proven bound is T_a + T_b, the faithful path's K_a + K_b.
    test::check_proven(c.found, c.meets_tolerance, c.distance, c.bound, 2 * tol, gap, 1e-12);
    CHECK(std::abs(glm::length(c.point_a - c.point_b) - c.distance) < 1e-12);
    CHECK(glm::length(c.point_a - dir) < 0.02);
    MESSAGE("gap " << gap << ": " << c.distance << " - " << c.bound << ", " << c.leaf_pairs << " GPU leaf pairs, "
                   << c.rounds << " CPU rounds, " << c.refined_cells << " cells");
  }
  for (uint64_t seed = 0; seed < 4; ++seed) {
    nurbs::TrimmedSurface fa, fb;
    fa.surface = models::random_surface(seed + 310, 2, 1 + int(seed % 3), seed % 2 == 1);
    fb.surface = models::random_surface(seed + 710, 1 + int(seed % 3), 2, false);
    for (auto& p : fb.surface.points) p += glm::dvec3(-0.2, 0.4, 2.2);
    const double t = 2e-3;
    const auto fa_f = queries::prepare_model(gpu, {fa}, t), fb_f = queries::prepare_model(gpu, {fb}, t);
    const auto fa_c = queries::prepare_model(gpu, {fa}, t, 1LL << 22, queries::Search::CoarseToFine);
    const auto fb_c = queries::prepare_model(gpu, {fb}, t, 1LL << 22, queries::Search::CoarseToFine);
    const queries::Clearance f = queries::clearance(gpu, fa_f, fb_f), c = queries::clearance(gpu, fa_c, fb_c);
    CAPTURE(seed);
    REQUIRE(c.found);
    CHECK(c.bound <= 2 * t);
    CHECK(std::abs(f.distance - c.distance) <= f.bound + c.bound);
    CHECK(std::abs(glm::length(c.point_a - nurbs::surface_point(fa.surface, c.uv_a.x, c.uv_a.y))) < 1e-12);
  }
}

namespace {

/// Clearance with face samples against boxes (ClearanceLimits::Upper). The samples' U is no larger,
/// so at every level no more pairs survive; the faithful answer is the same, the coarse-to-fine ones
/// agree within their bounds. Adds the leaf pairs (boxes, samples) to `pairs`; returns the samples'.
queries::Clearance samples_against_boxes(const queries::PreparedModel& a, const queries::PreparedModel& b,
                                         const glm::dmat4& motion, std::pair<long long, long long>& pairs) {
  gpgpu::Gpu& gpu = test::gpu();
  queries::ClearanceLimits boxes, samples;
  boxes.upper = queries::ClearanceLimits::Upper::Boxes;
  samples.upper = queries::ClearanceLimits::Upper::Samples;
  const queries::Clearance x = queries::clearance(gpu, a, b, motion, nullptr, nullptr, boxes);
  const queries::Clearance y = queries::clearance(gpu, a, b, motion, nullptr, nullptr, samples);
  REQUIRE(x.found);
  REQUIRE(y.found);
  if (a.search == queries::Search::Faithful) {
    CHECK(y.distance == x.distance);
  } else {
    CHECK(std::abs(y.distance - x.distance) <= x.bound + y.bound);
  }
  REQUIRE(y.pairs_per_level.size() == x.pairs_per_level.size());
  for (size_t l = 0; l < x.pairs_per_level.size(); ++l) CHECK(y.pairs_per_level[l] <= x.pairs_per_level[l]);
  pairs.first += x.leaf_pairs, pairs.second += y.leaf_pairs;
  return y;
}

}  // namespace

TEST_CASE("clearance: face samples bound U tighter than the boxes on random pairs: fewer pairs, the same answer" *
          test::sweep()) {
  gpgpu::Gpu& gpu = test::gpu();
  std::pair<long long, long long> pairs{0, 0};
  for (uint64_t seed = 0; seed < 6; ++seed)
    for (auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
      CAPTURE(seed);
      nurbs::TrimmedSurface fb;
      const nurbs::TrimmedSurface fa = models::random_trimmed_surface(seed + 20);
      fb.surface = models::random_surface(seed + 720, 2, 1 + int(seed % 3), seed % 2 == 1);
      for (auto& p : fb.surface.points) p += glm::dvec3(0.3, -0.2, 2.0 + 0.1 * double(seed));
      const auto a = queries::prepare_model(gpu, {fa}, 5e-3, 1LL << 22, search);
      const auto b = queries::prepare_model(gpu, {fb}, 5e-3, 1LL << 22, search);
      const queries::Clearance y = samples_against_boxes(a, b, glm::dmat4(1.0), pairs);
      if (search == queries::Search::Faithful && fa.loops.empty())  // the twin knows no trims
        CHECK(y.distance == doctest::Approx(brute_force(a, b)).epsilon(1e-12));
    }
  CHECK(pairs.second < pairs.first);
  MESSAGE("leaf pairs over 12 random pairs: " << pairs.second << " with samples, " << pairs.first << " with boxes");
}

TEST_CASE("clearance: levels pruned on the CPU keep the GPU passes' pairs on random pairs" * test::sweep()) {
  // ClearanceLimits::host_pairs: U and the survivors from one read-back instead of the reduction and
  // the stream reduction: the same pairs per level, leaves and answer, bit for bit.
  gpgpu::Gpu& gpu = test::gpu();
  long long host_levels = 0;
  for (uint64_t seed = 0; seed < 4; ++seed)
    for (auto search : {queries::Search::Faithful, queries::Search::CoarseToFine})
      for (auto upper : {queries::ClearanceLimits::Upper::Boxes, queries::ClearanceLimits::Upper::Samples}) {
        CAPTURE(seed);
        CAPTURE(int(search));
        CAPTURE(int(upper));
        nurbs::TrimmedSurface fb;
        const nurbs::TrimmedSurface fa = models::random_trimmed_surface(seed + 40);
        fb.surface = models::random_surface(seed + 740, 3, 1 + int(seed % 3), seed % 2 == 0);
        for (auto& p : fb.surface.points) p += glm::dvec3(-0.2, 0.3, 1.5 + 0.2 * double(seed));
        const auto a = queries::prepare_model(gpu, {fa}, 5e-3, 1LL << 22, search);
        const auto b = queries::prepare_model(gpu, {fb}, 5e-3, 1LL << 22, search);
        queries::ClearanceLimits on_gpu, on_host;
        on_gpu.upper = on_host.upper = upper;
        on_gpu.host_pairs = 0;
        on_host.host_pairs = 1LL << 40;  // every level that fits one pass
        const auto motion = glm::rotate(glm::dmat4(1.0), 0.3 * double(seed), glm::dvec3(0, 0, 1));
        const queries::Clearance x = queries::clearance(gpu, a, b, motion, nullptr, nullptr, on_gpu);
        const queries::Clearance y = queries::clearance(gpu, a, b, motion, nullptr, nullptr, on_host);
        REQUIRE(x.found);
        REQUIRE(y.found);
        CHECK(y.pairs_per_level == x.pairs_per_level);
        CHECK(y.leaf_pairs == x.leaf_pairs);
        CHECK(y.distance == x.distance);
        CHECK(y.bound == x.bound);
        host_levels += static_cast<long long>(y.pairs_per_level.size());
      }
  MESSAGE(host_levels << " levels pruned on the CPU over 16 queries");
}

TEST_CASE("clearance: face samples never come from a hole (a sphere over a holed plane)") {
  // A sample in a hole would be a point of no face: a square with a hole of radius 0.3 (in (u, v))
  // under a sphere of radius 0.2 whose centre is 0.25 above the hole's: the clearance is the rim's.
  gpgpu::Gpu& gpu = test::gpu();
  std::pair<long long, long long> pairs{0, 0};
  const nurbs::TrimmedSurface square = models::cubic_square_with_hole(0.3);
  nurbs::TrimmedSurface ball;
  ball.surface = models::rational_sphere(0.2);
  const glm::dvec3 centre(1.0, 1.0, 0.25);
  double truth = 1e300;  // the rim's closest point (the plane's points get farther from (1, 1))
  for (int k = 0; k < 100000; ++k) {
    const double t = 2.0 * M_PI * k / 100000;
    const glm::dvec3 p = nurbs::surface_point(square.surface, 1.0 + 0.3 * std::cos(t), 1.0 + 0.3 * std::sin(t));
    truth = std::min(truth, glm::length(p - centre) - 0.2);
  }
  for (auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
    const double tol = 1e-3;
    const auto a = queries::prepare_model(gpu, {square}, tol, 1LL << 22, search);
    const auto b = queries::prepare_model(gpu, {ball}, tol, 1LL << 22, search);
    CAPTURE(int(search));
    const queries::Clearance c = samples_against_boxes(a, b, glm::translate(glm::dmat4(1.0), centre), pairs);
    // Within the bound, less the rim's flattening into a polygon (1e-6 of the domain) and sampling.
    CHECK(std::abs(c.distance - truth) <= c.bound + 1e-5);
    CHECK(c.distance > 0.1);  // the 0.05 of a point in the hole is far outside
    MESSAGE(std::string(search == queries::Search::Faithful ? "faithful" : "coarse-to-fine")
            << ": " << c.distance << " +- " << c.bound << " (truth " << truth << "), leaf pairs " << c.leaf_pairs);
  }
}

TEST_CASE("clearance: models in several atlases give the answer of one atlas and of the exhaustive twin") {
  // Four faces per model, prepared once into one atlas and once into atlases of side just above
  // the largest grid (two or more atlases each): every atlas pair is searched, the least upper
  // bound shared, the leaf pairs joined.
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<nurbs::TrimmedSurface> fa, fb;
  for (uint64_t k = 0; k < 4; ++k) {
    nurbs::TrimmedSurface a, b;
    a.surface = models::random_surface(k + 40, 2, 1 + int(k % 3), k % 2 == 1);
    // B: A's faces moved (grids of 64x3 and 28x90 samples: no atlas of side 90 holds both).
    b.surface = models::random_surface(k + 40, 2, 1 + int(k % 3), k % 2 == 1);
    for (auto& p : a.surface.points) p += glm::dvec3(3.0 * double(k), 0.0, 0.0);
    for (auto& p : b.surface.points) p += glm::dvec3(3.0 * double(k) + 1.0, 0.5, 2.5);
    fa.push_back(a);
    fb.push_back(b);
  }
  const auto one_a = queries::prepare_model(gpu, fa, 2e-2), one_b = queries::prepare_model(gpu, fb, 2e-2);
  REQUIRE(one_a.atlases.size() == 1);
  auto side_of = [](const queries::PreparedModel& m) {  // the largest grid's side: no two large grids share
    int side = 0;
    for (const auto& g : m.grids) side = std::max({side, int(g.grid.u.size()), int(g.grid.v.size())});
    return side;
  };
  const auto many_a = queries::prepare_model(gpu, fa, 2e-2, 1LL << 22, queries::Search::Faithful, side_of(one_a));
  const auto many_b = queries::prepare_model(gpu, fb, 2e-2, 1LL << 22, queries::Search::Faithful, side_of(one_b));
  CHECK(many_a.atlases.size() >= 2);
  CHECK(many_b.atlases.size() >= 2);
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, -0.3, 0.1));
  const queries::Clearance one = queries::clearance(gpu, one_a, one_b);
  const queries::Clearance many = queries::clearance(gpu, many_a, many_b);
  REQUIRE(many.found);
  CHECK(many.distance == doctest::Approx(one.distance).epsilon(1e-12));
  CHECK(many.distance == doctest::Approx(brute_force(one_a, one_b)).epsilon(1e-12));
  CHECK(many.face_a == one.face_a);
  CHECK(many.face_b == one.face_b);
  // Face samples in every atlas's hierarchy (U shared across the atlas pairs): the same answer.
  queries::ClearanceLimits samples;
  samples.upper = queries::ClearanceLimits::Upper::Samples;
  const queries::Clearance many_samples =
      queries::clearance(gpu, many_a, many_b, glm::dmat4(1.0), nullptr, nullptr, samples);
  CHECK(many_samples.distance == many.distance);
  CHECK(many_samples.leaf_pairs <= many.leaf_pairs);
  // Moved, with A's hierarchies cached across two queries.
  queries::ClearanceCache cache;
  const queries::Clearance moved_one = queries::clearance(gpu, one_a, one_b, motion);
  for (int k = 0; k < 2; ++k) {
    const queries::Clearance moved = queries::clearance(gpu, many_a, many_b, motion, nullptr, nullptr, {}, &cache);
    CHECK(moved.distance == doctest::Approx(moved_one.distance).epsilon(1e-12));
  }
  MESSAGE("atlases " << many_a.atlases.size() << " x " << many_b.atlases.size() << ": distance " << many.distance
                     << ", leaf pairs " << many.leaf_pairs << " (one atlas " << one.leaf_pairs << "; face samples "
                     << many_samples.leaf_pairs << ")");
}

TEST_CASE("clearance: compile_clearance_programs compiles every program that preparation and a query use") {
  // The CLI compiles them while the geometry threads work; a program left out of the list would
  // compile at its first pass instead, silently. From no programs: compile the list for a search,
  // then prepare two pairs (trimmed and not) and query them with it, at both fan-outs and two
  // reduction blocks: nothing new.
  gpgpu::Gpu& gpu = test::gpu();
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  for (const auto& [fanout, block] : {std::pair{16, 4}, {4, 2}})
    for (auto search : {queries::Search::Faithful, queries::Search::CoarseToFine}) {
      CAPTURE(fanout);
      CAPTURE(int(search));
      queries::ClearanceLimits limits;
      limits.compact_fanout = fanout;
      limits.reduce_block = block;
      gpu.forget_programs();
      queries::compile_clearance_programs(gpu, limits, search);
      const size_t compiled = gpu.program_count();
      CHECK(compiled >= 8);
      const queries::PreparedPair p =
          queries::prepare_pair(gpu, {s1}, {models::random_trimmed_surface(7)}, 1e-3, search);
      (void)queries::clearance(gpu, p.a, p.b, glm::translate(glm::dmat4(1.0), glm::dvec3(3, 0, 0)), nullptr, nullptr,
                               limits);
      const queries::PreparedPair q = queries::prepare_pair(gpu, {s1}, {s2}, 1e-3, search);
      (void)queries::clearance(gpu, q.a, q.b, glm::translate(glm::dmat4(1.0), glm::dvec3(3.5, 0, 0)), nullptr, nullptr,
                               limits);
      CHECK(gpu.program_count() == compiled);
    }
}

TEST_CASE("clearance: the CPU search (clearance_cpu) proves the GPU descent's answer on spheres, random pairs and a "
          "holed plane" * test::sweep()) {
  gpgpu::Gpu& gpu = test::gpu();
  const double tol = 1e-3;
  auto both = [&](const nurbs::TrimmedSurface& x, const nurbs::TrimmedSurface& y, const glm::dmat4& motion) {
    const auto a = queries::prepare_model(gpu, {x}, tol, 1LL << 22, queries::Search::CoarseToFine);
    const auto b = queries::prepare_model(gpu, {y}, tol, 1LL << 22, queries::Search::CoarseToFine);
    const queries::Clearance g = queries::clearance(gpu, a, b, motion);
    // Every pair, then only those within an upper bound (the GPU's answer, grown): the same search.
    const queries::Clearance c = queries::clearance_cpu(a, b, motion).value();
    const queries::Clearance u = queries::clearance_cpu(a, b, motion, 1.01 * g.distance + 1e-9).value();
    // Over a budget of start pairs: no answer (the caller takes the GPU descent).
    CHECK_FALSE(queries::clearance_cpu(a, b, motion, 1.01 * g.distance + 1e-9, u.start_pairs - 1).has_value());
    CHECK(u.start_pairs <= c.start_pairs);
    REQUIRE(g.found);
    REQUIRE(c.found);
    REQUIRE(u.found);
    CHECK(c.meets_tolerance);
    CHECK(c.bound <= 2 * tol);
    CHECK(std::abs(c.distance - g.distance) <= c.bound + g.bound + 1e-12);
    CHECK(std::abs(u.distance - c.distance) <= u.bound + c.bound);
    CHECK(std::abs(glm::length(c.point_a - c.point_b) - c.distance) < 1e-12);
    CHECK(c.pairs_per_level.empty());  // no GPU descent
    return c;
  };
  nurbs::TrimmedSurface s1, s2;
  s1.surface = models::rational_sphere(1.0);
  s2.surface = models::rational_sphere(2.0);
  for (double gap : {0.02, 1.5}) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(-1, 0.4, 2));
    const queries::Clearance c = both(s1, s2, glm::translate(glm::dmat4(1.0), (3.0 + gap) * dir));
    CAPTURE(gap);
    test::check_proven(c.found, c.meets_tolerance, c.distance, c.bound, 2 * tol, gap, 1e-12);
  }
  for (uint64_t seed = 0; seed < 4; ++seed) {
    nurbs::TrimmedSurface fa, fb;
    fa.surface = models::random_surface(seed + 310, 2, 1 + int(seed % 3), seed % 2 == 1);
    fb.surface = models::random_surface(seed + 710, 1 + int(seed % 3), 2, false);
    CAPTURE(seed);
    both(fa, fb, glm::translate(glm::dmat4(1.0), glm::dvec3(-0.2, 0.4, 2.2)));
  }
  // A trimmed face: the clearance is the hole's rim's, never a point in the hole (0.05).
  nurbs::TrimmedSurface ball;
  ball.surface = models::rational_sphere(0.2);
  const queries::Clearance c = both(models::cubic_square_with_hole(0.3), ball,
                                    glm::translate(glm::dmat4(1.0), glm::dvec3(1.0, 1.0, 0.25)));
  CHECK(c.distance > 0.1);
  // Search::Faithful models have no coarse grids to refine.
  const auto f = queries::prepare_model(gpu, {s1}, tol);
  CHECK_THROWS_AS((void)queries::clearance_cpu(f, f), std::invalid_argument);
}

TEST_CASE("clearance kernels: leaf boxes hold the moved surface, merges equal their children's, pair bounds the twin's") {
  // glsl/distance/aabb_leaf.frag, aabb_merge.frag and aabb_pairs_minmax.frag one at a time against their
  // twins: every leaf box holds the exact surface over its cell under the rigid motion (the Filip
  // bound's claim, sampled densely in double); every merged node is its children's box, bit for bit;
  // every pair's (min, max) distance that of queries::box_box_minmax in double on the same boxes.
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<nurbs::TrimmedSurface> faces;
  for (uint64_t seed = 0; seed < 3; ++seed) faces.push_back(models::random_trimmed_surface(seed + 40));
  nurbs::TrimmedSurface ball;
  ball.surface = models::rational_sphere(0.7);
  for (auto& p : ball.surface.points) p += glm::dvec3(1.5, -0.5, 0.3);
  faces.push_back(ball);
  const queries::PreparedModel m = queries::prepare_model(gpu, faces, 2e-3);
  REQUIRE(m.atlases.size() == 1);
  const glm::dmat4 motion = glm::translate(glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(1, 2, 3)), glm::dvec3(4, -1, 2));
  const glm::dvec3 origin = m.centre;
  const queries::HierarchyLevels h = queries::clearance_hierarchy(gpu, m, 0, motion, origin);
  REQUIRE(h.size.size() > 2);
  // Leaves: 3 x 3 surface points of every cell (its corners among them), moved, inside the box
  // within the float rounding of its corners; a cell all of whose corners are material is not empty.
  const auto& lo0 = h.lo[0];
  const auto& hi0 = h.hi[0];
  long long cells = 0, checked = 0, loose = 0;
  double worst = 0.0;  // the largest excursion beyond a box, relative to the coordinates
  for (int y = 0; y < h.size[0].y; ++y)
    for (int x = 0; x < h.size[0].x; ++x) {
      const auto c = m.cell_at(0, x, y);
      const size_t t = size_t(y) * size_t(h.size[0].x) + size_t(x);
      const bool empty = lo0[4 * t] > hi0[4 * t];
      if (!c) {
        CHECK(empty);
        continue;
      }
      const auto& f = m.faces[size_t(c->face)];
      const auto& g = m.grids[size_t(c->face)].grid;
      const double u0 = g.u[size_t(c->i)], u1 = g.u[size_t(c->i) + 1], v0 = g.v[size_t(c->j)], v1 = g.v[size_t(c->j) + 1];
      bool all_material = true;
      for (int k = 0; k < 4; ++k)
        all_material = all_material && (f.loops.empty() || nurbs::is_material(m.trims[size_t(c->face)],
                                                                                  {k & 1 ? u1 : u0, k & 2 ? v1 : v0}));
      if (all_material) CHECK_MESSAGE(!empty, "cell (" << x << ", " << y << ") of face " << c->face);
      if (empty) continue;
      ++cells;
      // Not larger than the corners' box grown by K_e and the float budget (and float rounding).
      glm::dvec3 clo(1e300), chi(-1e300);
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 q = glm::dvec3(motion * glm::dvec4(nurbs::surface_point(f.surface, k & 1 ? u1 : u0,
                                                                                  k & 2 ? v1 : v0), 1.0)) - origin;
        clo = glm::min(clo, q), chi = glm::max(chi, q);
      }
      const double grow = m.grids[size_t(c->face)].k_e + queries::float_budget(f.surface);
      for (int k = 0; k < 3; ++k)
        loose += double(hi0[4 * t + size_t(k)]) - double(lo0[4 * t + size_t(k)]) >
                 chi[k] - clo[k] + 2.0 * grow + 1e-5 * (glm::length(chi) + glm::length(origin) + 1.0);
      for (int a = 0; a <= 2; ++a)
        for (int b = 0; b <= 2; ++b) {
          const double u = u0 + 0.5 * a * (u1 - u0), v = v0 + 0.5 * b * (v1 - v0);
          const glm::dvec3 p = glm::dvec3(motion * glm::dvec4(nurbs::surface_point(f.surface, u, v), 1.0)) - origin;
          for (int k = 0; k < 3; ++k) {
            const double scale = 1e-6 * (std::abs(p[k]) + glm::length(origin) + 1.0);
            worst = std::max({worst, (double(lo0[4 * t + size_t(k)]) - p[k]) / scale,
                              (p[k] - double(hi0[4 * t + size_t(k)])) / scale});
          }
          ++checked;
        }
    }
  MESSAGE(cells << " leaf boxes, " << checked << " surface points, worst excursion " << worst << " x 1e-6");
  CHECK(cells > 100);
  CHECK(worst <= 1.0);
  CHECK(loose == 0);
  // Merges: each node the box of its (up to four) children, exactly.
  long long mismatched = 0;
  for (size_t l = 1; l < h.size.size(); ++l)
    for (int y = 0; y < h.size[l].y; ++y)
      for (int x = 0; x < h.size[l].x; ++x) {
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        for (int k = 0; k < 4; ++k) {
          const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
          if (cx >= h.size[l - 1].x || cy >= h.size[l - 1].y) continue;
          const size_t ct = size_t(cy) * size_t(h.size[l - 1].x) + size_t(cx);
          lo = glm::min(lo, glm::vec3(h.lo[l - 1][4 * ct], h.lo[l - 1][4 * ct + 1], h.lo[l - 1][4 * ct + 2]));
          hi = glm::max(hi, glm::vec3(h.hi[l - 1][4 * ct], h.hi[l - 1][4 * ct + 1], h.hi[l - 1][4 * ct + 2]));
        }
        const size_t t = size_t(y) * size_t(h.size[l].x) + size_t(x);
        mismatched += lo != glm::vec3(h.lo[l][4 * t], h.lo[l][4 * t + 1], h.lo[l][4 * t + 2]) ||
                      hi != glm::vec3(h.hi[l][4 * t], h.hi[l][4 * t + 1], h.hi[l][4 * t + 2]);
      }
  CHECK(mismatched == 0);
  // Pairs: A unmoved against B = the same model moved, at a middle level of each (empty nodes too).
  const int la = int(h.size.size()) / 2, lb = int(h.size.size()) / 2 - 1;
  const queries::HierarchyLevels ha = queries::clearance_hierarchy(gpu, m, 0, glm::dmat4(1.0), origin);
  std::vector<glm::ivec4> pairs;
  for (int ya = 0; ya < ha.size[size_t(la)].y; ++ya)
    for (int xa = 0; xa < ha.size[size_t(la)].x; ++xa)
      for (int yb = 0; yb < h.size[size_t(lb)].y; yb += 2)
        for (int xb = 0; xb < h.size[size_t(lb)].x; xb += 3) pairs.emplace_back(xa, ya, xb, yb);
  REQUIRE(pairs.size() > 50);
  const std::vector<glm::vec2> bounds = queries::clearance_pair_bounds(gpu, m, m, motion, la, lb, pairs);
  REQUIRE(bounds.size() == pairs.size());
  long long off = 0, empties = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const size_t ta = size_t(pairs[k].y) * size_t(ha.size[size_t(la)].x) + size_t(pairs[k].x);
    const size_t tb = size_t(pairs[k].w) * size_t(h.size[size_t(lb)].x) + size_t(pairs[k].z);
    const auto box = [](const queries::HierarchyLevels& hh, int l, size_t t, bool upper) {
      const auto& v = upper ? hh.hi[size_t(l)] : hh.lo[size_t(l)];
      return glm::dvec3(v[4 * t], v[4 * t + 1], v[4 * t + 2]);
    };
    const glm::dvec3 lo1 = box(ha, la, ta, false), hi1 = box(ha, la, ta, true);
    const glm::dvec3 lo2 = box(h, lb, tb, false), hi2 = box(h, lb, tb, true);
    if (glm::any(glm::greaterThan(lo1, hi1)) || glm::any(glm::greaterThan(lo2, hi2))) {
      ++empties;
      off += !(std::isinf(bounds[k].x) && std::isinf(bounds[k].y));
      continue;
    }
    const auto [dmin, dmax] = queries::box_box_minmax(lo1, hi1, lo2, hi2);
    const double scale = 1e-6 * (dmax + 1.0);
    off += std::abs(double(bounds[k].x) - dmin) > scale || std::abs(double(bounds[k].y) - dmax) > scale;
  }
  MESSAGE(pairs.size() << " pairs, " << empties << " with an empty box");
  CHECK(off == 0);
}
