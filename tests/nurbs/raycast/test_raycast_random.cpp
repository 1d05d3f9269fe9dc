// BVH (stackless, stack) and brute force give the same nearest hits on random trimmed faces.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/random_surfaces.h"
#include "nurbs/raycast/dacrt.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "nurbs/surface_eval.h"

using namespace nurbs;
using namespace nurbs::ray;

namespace {

std::vector<Ray> random_rays(std::uint64_t seed, int n) {
  models::Random rng(seed);
  std::vector<Ray> rays;
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 o(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-4, 4));
    const glm::dvec3 aim(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));  // where the surfaces are
    rays.push_back({o, glm::normalize(aim - o)});
  }
  return rays;
}

}  // namespace

TEST_CASE("raycast: BVH traversals, DACRT and brute force agree on random trimmed faces") {
  std::vector<TrimmedSurface> faces;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  // The random nets turn wildly: patches split by normal turn (SceneOptions::max_turn_degrees) would
  // number thousands per face; the traversals must agree on any patch set, so the paper's is used.
  SceneOptions opt;
  opt.max_turn_degrees = 0.0;
  const Scene scene = build_scene(faces, opt);
  const auto rays = random_rays(5, 400);
  TraversalStats st_less, st_stack;
  const auto t0 = std::chrono::steady_clock::now();
  const auto a = cast_rays(scene, rays, 0.0, Traversal::Stackless, &st_less);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto b = cast_rays(scene, rays, 0.0, Traversal::Stack, &st_stack);
  const auto c = cast_rays(scene, rays, 0.0, Traversal::BruteForce);
  DacrtStats ds;
  const auto d = cast_rays_dacrt(scene, rays, 0.0, {}, &ds);
  int hits = 0, differ = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    hits += c[k].face >= 0;
    // Same patch set and arithmetic: identical faces; t agree to round-off of the exact step (1e-12 size).
    for (const Hit* h : {&a[k], &b[k], &d[k]})
      differ += h->face != c[k].face || (h->face >= 0 && std::abs(h->t - c[k].t) > 1e-12 * scene.size);
  }
  CHECK(hits > 100);  // the aim points lie among the faces: most rays hit
  CHECK(differ == 0);
  // Each hit is a true surface point on the ray (the exact step's residual bound, 1e-10 size).
  int off = 0;
  for (size_t k = 0; k < rays.size(); ++k)
    if (a[k].face >= 0) {
      const glm::dvec3 s = surface_point(scene.faces[a[k].face].surface, a[k].uv.x, a[k].uv.y);
      off += glm::length(s - (rays[k].origin + a[k].t * rays[k].direction)) > 1e-9 * scene.size;
    }
  CHECK(off == 0);
  MESSAGE(scene.patches.size() << " patches; stackless: " << double(st_less.box_tests) / rays.size() << " box tests, "
                               << double(st_less.patch_tests) / rays.size() << " patch tests per ray, "
                               << rays.size() / secs << " rays/s; DACRT: " << double(ds.box_tests) / rays.size()
                               << " box tests, " << double(ds.patch_tests) / rays.size() << " patch tests per ray");
}

TEST_CASE("raycast: the §3.4 cubic trim test gives the hits of the winding-number oracle") {
  std::vector<TrimmedSurface> faces;
  for (std::uint64_t seed = 11; seed <= 18; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  SceneOptions opt;
  opt.max_turn_degrees = 0.0;  // as above: the trim tests must agree on any patch set
  const Scene polygons = build_scene(faces, opt);
  opt.trim = SceneOptions::Trim::Cubics;
  const Scene cubics = build_scene(faces, opt);
  const auto rays = random_rays(6, 400);
  const auto a = cast_rays(polygons, rays, 0.0), b = cast_rays(cubics, rays, 0.0);
  int differ = 0, hits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    hits += a[k].face >= 0;
    // Both trims are within 1e-7 of the domain of the exact loops; a random ray landing that close is unlikely.
    differ += a[k].face != b[k].face || (a[k].face >= 0 && std::abs(a[k].t - b[k].t) > 1e-12 * polygons.size);
  }
  CHECK(hits > 100);
  CHECK(differ == 0);
}
