// The Morton BVH built on the GPU (queries/raycast/bvh_gpu.h, Lemasson et al. §3.2 after Karras 2012)
// against its CPU twin: the same float Morton codes, then nurbs::ray::build_bvh_codes. Node for
// node: codes, leaf order, parents, children, leaf ranges, boxes (exact: min and max of floats),
// and the ray caster's traversal vectors and siblings.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "tests/gpgpu/gl_fixture.h"
#include "queries/raycast/bvh_gpu.h"
#include "tests/test_suites.h"

namespace {

/// n random boxes in [-50, 50]^3; with `clusters`, the centres fall on a few points so that many
/// Morton codes are equal (the index then orders the keys, Karras §4).
void random_boxes(std::uint64_t seed, int n, int clusters, std::vector<glm::vec3>& lo, std::vector<glm::vec3>& hi) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> pos(-50.0f, 50.0f), size(0.0f, 3.0f);
  std::vector<glm::vec3> centres;
  for (int c = 0; c < clusters; ++c) centres.emplace_back(pos(rng), pos(rng), pos(rng));
  lo.clear();
  hi.clear();
  for (int i = 0; i < n; ++i) {
    const glm::vec3 c = clusters > 0 ? centres[size_t(i % clusters)] : glm::vec3(pos(rng), pos(rng), pos(rng));
    const glm::vec3 h(size(rng), size(rng), size(rng));
    lo.push_back(c - h);
    hi.push_back(c + h);
  }
}

}  // namespace

TEST_CASE("GPU Morton BVH: Karras' tree, parents and boxes equal the CPU twin node for node") {
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<glm::vec3> lo, hi;
  struct Case {
    int n, clusters;
  };
  for (const Case c : {Case{1, 0}, Case{2, 0}, Case{3, 0}, Case{5, 0}, Case{17, 0}, Case{1000, 0}, Case{4097, 0},
                       Case{300, 7}, Case{2048, 1}}) {
    CAPTURE(c.n);
    CAPTURE(c.clusters);
    random_boxes(std::uint64_t(c.n) * 31 + std::uint64_t(c.clusters), c.n, c.clusters, lo, hi);
    const queries::GpuBvh g = queries::build_bvh_gpu(gpu, lo, hi);
    const nurbs::ray::Bvh got = queries::read_bvh(g), want = queries::bvh_twin(lo, hi);
    REQUIRE(got.nodes.size() == want.nodes.size());
    CHECK(got.codes == want.codes);
    CHECK(got.order == want.order);
    CHECK(queries::read_order(g) == want.order);
    int wrong_links = 0, wrong_boxes = 0, wrong_vectors = 0;
    const std::vector<float> table = g.nodes.read();
    for (size_t i = 0; i < want.nodes.size(); ++i) {
      const nurbs::ray::BvhNode &a = got.nodes[i], &b = want.nodes[i];
      const bool leaf_ok = !b.leaf() || (a.first == b.first && a.last == b.last);
      wrong_links += a.parent != b.parent || a.left != b.left || a.right != b.right || !leaf_ok;
      wrong_boxes += a.box_min != b.box_min || a.box_max != b.box_max;
      // Texel 2 of an internal node and texel 3: (l.min + l.max) - (r.min + r.max) in float.
      const auto vector_of = [&](const nurbs::ray::BvhNode& n) {
        const auto &l = want.nodes[size_t(n.left)], &r = want.nodes[size_t(n.right)];
        return (l.box_min + l.box_max) - (r.box_min + r.box_max);
      };
      const float* e = &table[16 * i];
      const auto near = [](const float* v, glm::dvec3 w) {
        for (int k = 0; k < 3; ++k)
          if (std::abs(v[k] - w[k]) > 1e-5 * (1.0 + std::abs(w[k]))) return false;
        return true;
      };
      if (!b.leaf()) wrong_vectors += !near(e + 8, vector_of(b));
      if (b.parent >= 0) {
        const nurbs::ray::BvhNode& p = want.nodes[size_t(b.parent)];
        const bool left = p.left == int(i);
        wrong_vectors += !near(e + 12, vector_of(p)) || int(e[15]) != (left ? p.right : -1 - p.left);
      }
    }
    CHECK(wrong_links == 0);
    CHECK(wrong_boxes == 0);
    CHECK(wrong_vectors == 0);
    MESSAGE(c.n, " leaves: ", g.passes, " passes, ", g.seconds * 1e3, " ms");
  }
}

TEST_CASE("GPU Morton BVH: build time against the CPU build, 10^3 to 10^5 leaves" * test::sweep()) {
  // Printout benchmark (no timed assertion): the GPU build warm (its programs compiled by a first
  // build), and build_bvh in double on one core; the tree checked against the twin at each size.
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<glm::vec3> lo, hi;
  random_boxes(5, 64, 0, lo, hi);
  (void)queries::build_bvh_gpu(gpu, lo, hi);
  for (const int n : {1000, 10000, 100000}) {
    random_boxes(std::uint64_t(n), n, 0, lo, hi);
    const queries::GpuBvh g = queries::build_bvh_gpu(gpu, lo, hi);
    const std::vector<glm::dvec3> dlo(lo.begin(), lo.end()), dhi(hi.begin(), hi.end());
    const auto t0 = std::chrono::steady_clock::now();
    const nurbs::ray::Bvh cpu = nurbs::ray::build_bvh(dlo, dhi);
    const double cpu_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const nurbs::ray::Bvh got = queries::read_bvh(g), want = queries::bvh_twin(lo, hi);
    int wrong = 0;
    for (size_t i = 0; i < want.nodes.size(); ++i)
      wrong += got.nodes[i].parent != want.nodes[i].parent || got.nodes[i].left != want.nodes[i].left ||
               got.nodes[i].box_min != want.nodes[i].box_min || got.nodes[i].box_max != want.nodes[i].box_max;
    CHECK(wrong == 0);
    CHECK(got.order == want.order);
    CHECK(cpu.nodes.size() == got.nodes.size());
    MESSAGE(n << " leaves: GPU build " << g.seconds * 1e3 << " ms in " << g.passes << " passes; CPU build "
              << cpu_seconds * 1e3 << " ms (one core, double)");
  }
}
