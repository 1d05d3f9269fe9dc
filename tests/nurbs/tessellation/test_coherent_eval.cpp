// §8 coherent evaluation (coherent_eval.h) against nurbs::surface_point / surface_normal, the reuse
// counts, poles, and a benchmark printout (no timed assertion).
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <string>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/coherent_eval.h"
#include "test_suites.h"

using nurbs::Interval;
using nurbs::Surface;

namespace {

/// A mesh-like vertex set in (v, u) order: `rows` values of v (domain ends and knots included),
/// each with `cols` sorted u values (ends included) plus random ones.
std::vector<glm::dvec2> sorted_vertices(const Surface& s, int rows, int cols, models::Random& rng) {
  const Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
  std::vector<double> vs{dv.min, dv.max}, us{du.min, du.max};
  for (int k = s.degree_v + 1; k < s.count_v; ++k) vs.push_back(s.knots_v[size_t(k)]);  // interior knots
  for (int k = s.degree_u + 1; k < s.count_u; ++k) us.push_back(s.knots_u[size_t(k)]);
  while (int(vs.size()) < rows) vs.push_back(rng.uniform(dv.min, dv.max));
  std::vector<glm::dvec2> uv;
  for (double v : vs) {
    std::vector<double> row = us;
    while (int(row.size()) < cols) row.push_back(rng.uniform(du.min, du.max));
    for (double u : row) uv.push_back({u, v});
  }
  std::sort(uv.begin(), uv.end(), [](glm::dvec2 a, glm::dvec2 b) { return a.y < b.y || (a.y == b.y && a.x < b.x); });
  return uv;
}

double model_size(const Surface& s) {
  double r = 0;
  for (const auto& p : s.points) r = std::max(r, glm::length(p));
  return r;
}

/// Checks coherent results against the library's per-point evaluation: points to 1e-12 of the model
/// size (the closed-form tolerance of the tests; both sum the same terms, roundoff ~1e-15), normals to 1e-13 times
/// the condition |Su||Sv| / |Su x Sv| of the normalisation (roundoff of Su, Sv ~1e-15 relative).
void check_against_library(const Surface& s, const std::vector<glm::dvec2>& uv, const std::vector<glm::dvec3>& pos,
                           const std::vector<glm::dvec3>& nrm) {
  const double size = model_size(s);
  double worst_p = 0, worst_n = 0;
  for (size_t k = 0; k < uv.size(); ++k) {
    const glm::dvec3 p = nurbs::surface_point(s, uv[k].x, uv[k].y);
    const glm::dvec3 n = nurbs::surface_normal(s, uv[k].x, uv[k].y);
    const auto d = nurbs::surface_derivatives(s, uv[k].x, uv[k].y);
    const double cross = glm::length(glm::cross(d.su, d.sv));
    const double cond = cross > 0 ? std::max(1.0, glm::length(d.su) * glm::length(d.sv) / cross) : 1.0;
    worst_p = std::max(worst_p, glm::length(pos[k] - p) / size);
    worst_n = std::max(worst_n, glm::length(nrm[k] - n) / cond);
    CHECK(std::isfinite(nrm[k].x + nrm[k].y + nrm[k].z));
  }
  CHECK(worst_p <= 1e-12);
  CHECK(worst_n <= 1e-13);
}

}  // namespace

TEST_CASE("coherent evaluation equals direct evaluation on random surfaces, degrees 1-5") {
  models::Random rng(8);
  for (std::uint64_t seed = 0; seed < 150; ++seed) {
    const int du = 1 + int(seed % 5), dv = 1 + int(seed / 5 % 5);
    const Surface s = models::random_surface(seed, du, dv, seed % 2 == 1);
    const auto uv = sorted_vertices(s, 12, 15, rng);
    std::vector<glm::dvec3> pc, nc, pd, nd;
    nurbs::tess::CoherentStats st;
    nurbs::tess::evaluate_coherent(s, uv, pc, nc, &st);
    nurbs::tess::evaluate_direct(s, uv, pd, nd);
    check_against_library(s, uv, pc, nc);
    // Reused basis functions and inner sums are the very numbers a recomputation gives: bit equal.
    CHECK(pc == pd);
    CHECK(nc == nd);
    CHECK(st.points == uv.size());
    CHECK(st.swapped == (du > dv));
    if (!st.swapped) {
      CHECK(st.slow_basis == 12);                           // one v basis per distinct v
      CHECK(st.inner_sums < uv.size());                     // inner sums reused within a span
      CHECK(st.inner_sums <= 12 * size_t(s.count_u - du));  // at most once per (v, u span)
    }
  }
}

TEST_CASE("coherent evaluation: unsorted input gives the same results") {
  models::Random rng(5);
  const Surface s = models::random_surface(3, 4, 2, true);
  auto uv = sorted_vertices(s, 9, 11, rng);
  std::vector<glm::dvec3> p0, n0, p1, n1;
  nurbs::tess::evaluate_coherent(s, uv, p0, n0);
  std::vector<size_t> perm(uv.size());
  for (size_t k = 0; k < perm.size(); ++k) perm[k] = (k * 37) % perm.size();  // 37 coprime to 99
  std::vector<glm::dvec2> shuffled;
  for (size_t k : perm) shuffled.push_back(uv[k]);
  nurbs::tess::evaluate_coherent(s, shuffled, p1, n1);
  for (size_t k = 0; k < perm.size(); ++k) {
    CHECK(p1[k] == p0[perm[k]]);
    CHECK(n1[k] == n0[perm[k]]);
  }
}

TEST_CASE("coherent evaluation: normals at poles are finite and point outwards") {
  const glm::dvec3 centre(1, 2, 3);
  const Surface sphere = models::rational_sphere(2.0, centre);
  std::vector<glm::dvec2> uv;
  for (double v : {0.0, 1e-9, 0.5, 1.0 - 1e-9, 1.0})
    for (int i = 0; i <= 16; ++i) uv.push_back({i / 16.0, v});
  std::vector<glm::dvec3> p, n;
  nurbs::tess::evaluate_coherent(sphere, uv, p, n);
  for (size_t k = 0; k < uv.size(); ++k) {
    const glm::dvec3 outward = glm::normalize(p[k] - centre);
    // 1e-6: the normal is the exact radial direction up to the 1e-9 offset rows' roundoff.
    CHECK(glm::length(n[k] - outward) < 1e-6);
  }
  // A pole where Suv vanishes too (rows 0 and 1 collapsed): the offset fallback still gives a
  // unit normal close to the one just inside the domain.
  Surface cone = models::random_surface(11, 2, 2, false);
  cone.count_u = 3;
  cone.count_v = 3;
  cone.knots_u = cone.knots_v = {0, 0, 0, 1, 1, 1};
  cone.points = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {-1, 0, 1}, {0, 1, 1}, {1, 0, 1}};
  const std::vector<glm::dvec2> at_pole{{0.3, 0.0}, {0.3, 1e-3}};
  nurbs::tess::evaluate_coherent(cone, at_pole, p, n);
  CHECK(std::abs(glm::length(n[0]) - 1.0) < 1e-12);  // unit up to roundoff
  CHECK(glm::dot(n[0], n[1]) > 0.99);                // continuous with the normal 1e-3 inside
}

TEST_CASE("coherent evaluation benchmark (printout only)" * test::sweep()) {
  struct Case {
    const char* name;
    Surface s;
  };
  const Case cases[] = {{"wavy bicubic 100x105", models::wavy_surface_100x105()},
                        {"rational torus (2,2)", models::rational_torus(3.0, 1.0)},
                        {"random (5,5) rational", models::random_surface(1, 5, 5, true)}};
  for (const Case& c : cases) {
    const Interval du = nurbs::surface_domain_u(c.s), dv = nurbs::surface_domain_v(c.s);
    std::vector<glm::dvec2> uv;  // a 300 x 300 grid in (v, u) order, as §8's regular tessellation
    for (int j = 0; j < 300; ++j)
      for (int i = 0; i < 300; ++i) uv.push_back({du.min + du.width() * i / 299, dv.min + dv.width() * j / 299});
    std::vector<glm::dvec3> p, n;
    const auto time = [&](auto&& f) {  // best of 3: the machine is shared, the minimum is the cost
      double best = 1e30;
      for (int r = 0; r < 3; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      return best;
    };
    const double tc = time([&] { nurbs::tess::evaluate_coherent(c.s, uv, p, n); });
    const double td = time([&] { nurbs::tess::evaluate_direct(c.s, uv, p, n); });
    const double tl = time([&] {
      for (size_t k = 0; k < uv.size(); ++k) {
        p[k] = nurbs::surface_point(c.s, uv[k].x, uv[k].y);
        n[k] = nurbs::surface_normal(c.s, uv[k].x, uv[k].y);
      }
    });
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "%s, 90000 points: coherent %.1f ms, direct %.1f ms (x%.2f), library %.1f ms (x%.2f)", c.name,
                  tc * 1e3, td * 1e3, td / tc, tl * 1e3, tl / tc);
    MESSAGE(std::string(buf));
  }
}
