// Certified knot-aligned grids: on random surfaces with C^0 and repeated knots, degrees
// 1-11, polynomial and rational with weight ratios up to 10^3, the chosen grid meets the tolerance
// with a finite K_e, and dense samples of cell interiors never deviate from the grid triangles by
// more than the cell's K (per coordinate) and K_e (Euclidean). The adaptive bound is compared with
// sampled second derivatives.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/model_ops.h"
#include "test_suites.h"
#include "tests/nurbs/distance/grid_check.h"

namespace {

/// Slack for a sampled deviation against its bound: the bound is attained exactly by quadratics
/// (u v at a cell centre), and both sides carry double rounding of points of size `scale`.
bool within(double sampled, double bound, double scale) { return sampled <= bound * (1 + 1e-9) + 1e-12 * scale; }

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * double(v.size() - 1))];
}

}  // namespace

TEST_CASE("certified grids bound the deviation on random C0, high-degree and strongly rational surfaces" *
          test::sweep()) {
  constexpr int kSurfaces = 363;        // 11 x 11 degree pairs x 3 weight families
  constexpr int kCellsPerSurface = 60;  // cells checked densely (all when fewer), the worst one always
  std::vector<double> ratios, samples_ratio;
  int non_c1 = 0, uniform_infinite = 0, cells_checked = 0, met = 0, met_by_family[3] = {0, 0, 0};
  long long samples_total = 0;
  for (int seed = 0; seed < kSurfaces; ++seed) {
    const int p = 1 + seed % 11, q = 1 + (seed / 11) % 11;
    const double weight_ratio = seed / 121 == 0 ? 1.0 : (seed / 121 == 1 ? 10.0 : 1e3);
    const nurbs::Surface s = models::random_kinked_surface(std::uint64_t(seed) + 100, p, q, weight_ratio);
    const double scale = nurbs::control_box(s).diagonal(), tol = 2e-3 * scale;
    const nurbs::FilipBound b = nurbs::filip_bound(s);
    // A limit well under the default keeps the test fast; surfaces that need more (weights 10^3 apart
    // on neighbouring points make the parametrisation, not the shape, very uneven) must say so.
    const nurbs::CertifiedGrid cg = nurbs::certified_grid(b, tol, nurbs::GridLimits{1'000'000});
    CAPTURE(seed);
    CAPTURE(p);
    CAPTURE(q);
    CAPTURE(weight_ratio);
    CAPTURE(cg.reason);
    CHECK(std::isfinite(cg.k_e));
    if (cg.meets_tolerance) {
      CHECK(cg.k_e <= tol);
      ++met;
      ++met_by_family[seed / 121];
    } else {
      CHECK(cg.reason.find("over the limit") != std::string::npos);
      CHECK(cg.grid.samples() <= 1'000'000);
      CHECK(cg.k_e > tol);
    }
    CHECK(cg.k <= cg.k_e);
    non_c1 += b.c1() ? 0 : 1;
    // The old uniform grid of the same sample count has cells across the C^0 lines: K = +infinity.
    const nurbs::ParamGrid uniform =
        nurbs::uniform_param_grid(b.domain_u, b.domain_v, cg.grid.cells_u() + 1, cg.grid.cells_v() + 1);
    if (!b.c1()) uniform_infinite += std::isinf(nurbs::grid_k(b, uniform, nurbs::KNorm::Euclidean)) ? 1 : 0;
    // Cells to check: a spread of indices, and the cell with the largest K_e.
    const int nu = cg.grid.cells_u(), nv = cg.grid.cells_v();
    std::vector<std::pair<int, int>> cells;
    double worst = -1;
    std::pair<int, int> worst_cell{0, 0};
    for (int j = 0; j < nv && nu * nv <= 100'000; ++j) {
      for (int i = 0; i < nu; ++i) {
        const double k = nurbs::grid_cell_k(b, cg.grid, i, j, nurbs::KNorm::Euclidean);
        if (k > worst) worst = k, worst_cell = {i, j};
      }
    }
    if (nu * nv <= 100'000) CHECK(worst == doctest::Approx(cg.k_e).epsilon(1e-12));  // grouping = per-cell max
    cells.push_back(worst_cell);
    const long long total = static_cast<long long>(nu) * nv;
    for (int c = 0; c < kCellsPerSurface && c < total; ++c) {
      const long long idx = total <= kCellsPerSurface ? c : (c * 7919LL) % total;
      cells.emplace_back(int(idx % nu), int(idx / nu));
    }
    double max_dev = 0.0;
    for (const auto& [i, j] : cells) {
      const grid_check::Deviation d = grid_check::cell_deviation(s, cg.grid, i, j, 6);
      CHECK(within(d.coord, nurbs::grid_cell_k(b, cg.grid, i, j), scale));
      CHECK(within(d.norm, nurbs::grid_cell_k(b, cg.grid, i, j, nurbs::KNorm::Euclidean), scale));
      max_dev = std::max(max_dev, d.norm);
      ++cells_checked;
    }
    // Bound / sampled: the sampled derivatives are a lower estimate of the true suprema.
    const nurbs::FilipBound sampled = nurbs::sampled_bound(s, b);
    const double k_sampled = nurbs::grid_k(sampled, cg.grid, nurbs::KNorm::Euclidean);
    CHECK(k_sampled <= cg.k_e * (1 + 1e-9));
    if (k_sampled > 0) ratios.push_back(cg.k_e / k_sampled);
    samples_total += cg.grid.samples();
    samples_ratio.push_back(double(cg.grid.samples()));
  }
  CHECK(met > kSurfaces * 9 / 10);
  CHECK(non_c1 > 100);           // the family exercises C^0 knot lines
  CHECK(uniform_infinite > 50);  // ... where uniform grids have no bound
  MESSAGE("certified grids: ", kSurfaces, " surfaces, ", met, " within 1e6 samples (", non_c1,
          " not C1; uniform grid K_e = inf on ", uniform_infinite, "), ", cells_checked, " cells checked densely, ",
          samples_total, " samples in all");
  MESSAGE("met by weight family 1, 10, 1e3: ", met_by_family[0], " ", met_by_family[1], " ", met_by_family[2]);
  MESSAGE("K_e bound / K_e sampled: median ", quantile(ratios, 0.5), ", 90% ", quantile(ratios, 0.9), ", max ",
          quantile(ratios, 1.0));
}

TEST_CASE("certified grid: C0 piecewise Bézier surface gets a finite K where the uniform grid has none") {
  // Bicubic, every interior knot of multiplicity 3 (VDA-FS style), with a kink at each.
  nurbs::Surface s;
  s.degree_u = s.degree_v = 3;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3};
  s.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  s.count_u = 10;
  s.count_v = 4;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 10; ++i) s.points.emplace_back(i, j, (i % 3 == 0 ? 1.0 : 0.0) + 0.1 * j * j);
  const nurbs::FilipBound b = nurbs::filip_bound(s);
  REQUIRE_FALSE(b.c1());
  CHECK(std::isinf(nurbs::filip_k_grid(b, 64, 64, nurbs::KNorm::Euclidean)));  // 64 cells miss the knots at 1/3, 2/3
  const nurbs::CertifiedGrid cg = nurbs::certified_grid(b, 1e-3);
  CHECK(cg.meets_tolerance);
  CHECK(cg.k_e <= 1e-3);
  CHECK(cg.lines_u == std::vector<double>{0, 1, 2, 3});
  for (double knot : {1.0, 2.0}) CHECK(std::count(cg.grid.u.begin(), cg.grid.u.end(), knot) == 1);
}

TEST_CASE("certified grid: the paper's 100 x 105 surface needs no more samples than the best uniform grid") {
  const nurbs::FilipBound b = nurbs::filip_bound(models::wavy_surface_100x105());
  for (double tol : {1e-2, 1e-3, 1e-4}) {
    CAPTURE(tol);
    const nurbs::GridChoice uniform = nurbs::choose_grid(b, tol, 1 << 16, nurbs::KNorm::Euclidean);
    const long long uniform_samples = static_cast<long long>(uniform.n + 1) * (uniform.m + 1);
    const nurbs::CertifiedGrid cg = nurbs::certified_grid(b, tol);
    CHECK(cg.meets_tolerance);
    CHECK(cg.grid.samples() <= uniform_samples);
    MESSAGE("tolerance ", tol, ": uniform ", uniform.n + 1, "x", uniform.m + 1, " = ", uniform_samples,
            " samples, knot-aligned ", cg.grid.u.size(), "x", cg.grid.v.size(), " = ", cg.grid.samples());
  }
}

TEST_CASE("certified grid: limits and bad tolerances are reported, not hidden") {
  const nurbs::FilipBound b = nurbs::filip_bound(models::wavy_surface_100x105());
  const nurbs::CertifiedGrid capped = nurbs::certified_grid(b, 1e-9, nurbs::GridLimits{100'000});
  CHECK_FALSE(capped.meets_tolerance);
  CHECK(capped.grid.samples() <= 100'000);
  CHECK(capped.reason.find("over the limit of 100000") != std::string::npos);
  CHECK(capped.k_e > 1e-9);
  for (double bad : {0.0, -1.0, std::nan("")}) {
    const nurbs::CertifiedGrid g = nurbs::certified_grid(b, bad);
    CHECK_FALSE(g.meets_tolerance);
    CHECK(g.reason.find("not positive") != std::string::npos);
  }
}

TEST_CASE("certified grid: per-segment K_e, its maximum is the grid's") {
  for (uint64_t seed = 0; seed < 40; ++seed) {
    const nurbs::Surface s = models::random_kinked_surface(seed + 900, 1 + int(seed % 5), 1 + int(seed / 5 % 4), 10.0);
    const nurbs::FilipBound b = nurbs::filip_bound(s);
    const nurbs::CertifiedGrid cg = nurbs::certified_grid(b, 1e-2, nurbs::GridLimits{1'000'000});
    const std::vector<double> k = nurbs::segment_k(b, cg);
    CAPTURE(seed);
    REQUIRE(k.size() == cg.cells_u.size() * cg.cells_v.size());
    CHECK(*std::max_element(k.begin(), k.end()) == doctest::Approx(cg.k_e).epsilon(1e-9));
    // The same grid described as one segment each way crosses the C0 lines: no bound.
    nurbs::CertifiedGrid one = cg;
    one.lines_u = {cg.lines_u.front(), cg.lines_u.back()};
    one.lines_v = {cg.lines_v.front(), cg.lines_v.back()};
    one.cells_u = {cg.grid.cells_u()};
    one.cells_v = {cg.grid.cells_v()};
    if (!b.c1()) CHECK(std::isinf(nurbs::segment_k(b, one).front()));
  }
}
