// Morton codes, Karras tree invariants, stackless vs stack vs brute-force leaf sets.
#include <doctest/doctest.h>

#include <algorithm>
#include <glm/geometric.hpp>
#include <set>

#include "models/random_surfaces.h"
#include "nurbs/raycast/morton_bvh.h"

using namespace nurbs::ray;

namespace {

struct Boxes {
  std::vector<glm::dvec3> lo, hi;
};

Boxes random_boxes(std::uint64_t seed, int n, bool clustered) {
  models::Random rng(seed);
  Boxes b;
  for (int i = 0; i < n; ++i) {
    // Clustered: many equal centroids (equal Morton codes), the case Karras' index tie-break is for.
    const glm::dvec3 c = clustered ? glm::dvec3(rng.integer(0, 2), 0.5, rng.integer(0, 1))
                                   : glm::dvec3(rng.uniform(-5, 5), rng.uniform(-1, 1), rng.uniform(0, 20));
    const glm::dvec3 e(rng.uniform(0.01, 0.5), rng.uniform(0.01, 0.5), rng.uniform(0.01, 0.5));
    b.lo.push_back(c - e);
    b.hi.push_back(c + e);
  }
  return b;
}

}  // namespace

TEST_CASE("morton: bit interleaving") {
  CHECK(morton3({0, 0, 0}) == 0u);
  CHECK(morton3({1, 1, 1}) == 0x3FFFFFFFu);   // 30 bits set, clamped at the top cell
  CHECK(morton3({0.5, 0, 0}) == (1u << 29));  // the highest x bit is bit 29
  CHECK(morton3({0, 0.5, 0}) == (1u << 28));
  CHECK(morton3({0, 0, 1.0 / 1024}) == 1u);
}

TEST_CASE("karras: every leaf reached once, ranges nest, boxes contain their children") {
  for (int n : {1, 2, 3, 7, 64, 1000})
    for (bool clustered : {false, true}) {
      CAPTURE(n);
      CAPTURE(clustered);
      const Boxes b = random_boxes(100 + n, n, clustered);
      const Bvh bvh = build_bvh(b.lo, b.hi);
      REQUIRE(bvh.nodes.size() == static_cast<size_t>(2 * n - 1));
      CHECK(std::is_sorted(bvh.codes.begin(), bvh.codes.end()));
      CHECK(bvh.nodes[bvh.root()].parent == -1);
      std::vector<int> reached(n, 0);
      std::vector<int> stack{bvh.root()};
      int bad = 0;
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[i];
        if (node.leaf()) {
          bad += node.first != node.last || i != n - 1 + node.first;
          ++reached[node.first];
          continue;
        }
        const BvhNode &l = bvh.nodes[node.left], &r = bvh.nodes[node.right];
        bad += l.parent != i || r.parent != i;
        bad += l.first != node.first || r.last != node.last || l.last + 1 != r.first;  // ranges split the parent's
        for (const BvhNode* c : {&l, &r})
          bad +=
              glm::any(glm::lessThan(c->box_min, node.box_min)) || glm::any(glm::greaterThan(c->box_max, node.box_max));
        stack.push_back(node.left);
        stack.push_back(node.right);
      }
      CHECK(bad == 0);
      CHECK(std::count(reached.begin(), reached.end(), 1) == n);
    }
}

TEST_CASE("bvh traversal: stackless and stack reach exactly the leaves whose box the ray crosses") {
  const Boxes b = random_boxes(7, 500, false);
  const Bvh bvh = build_bvh(b.lo, b.hi);
  models::Random rng(8);
  int differ = 0;
  long box_tests = 0;
  for (int k = 0; k < 300; ++k) {
    const glm::dvec3 o(rng.uniform(-8, 8), rng.uniform(-3, 3), rng.uniform(-5, 25));
    // Every third ray axis-aligned: zero direction components take the slab test's special case.
    glm::dvec3 d = k % 3 ? glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)) : glm::dvec3(0, 0, 1);
    d = glm::normalize(d);
    const Ray ray{o, d};
    std::multiset<int> a, s, brute;
    TraversalStats st;
    traverse_stackless(
        bvh, ray, 0.0, 1e300,
        [&](int f, int) {
          a.insert(f);
          return 1e300;
        },
        &st);
    traverse_stack(bvh, ray, 0.0, 1e300, [&](int f, int) {
      s.insert(f);
      return 1e300;
    });
    const glm::dvec3 inv = 1.0 / d;
    for (int i = 0; i < 500; ++i)
      if (ray_box(ray, inv, b.lo[bvh.order[i]], b.hi[bvh.order[i]], 0.0, 1e300)) brute.insert(i);
    differ += a != brute || s != brute;
    box_tests += st.box_tests;
  }
  CHECK(differ == 0);
  MESSAGE("stackless: " << box_tests / 300.0 << " box tests per ray over 500 boxes");
}
