// Filip bound K (Krishnamurthy et al. §2.2, Eqs. 1-4) is a true bound: on 1000 random surfaces
// (degrees 1-5, rational and not, fixed seeds) the sampled deviation of the surface from the
// piecewise linear interpolant of an (n+1) x (m+1) grid never exceeds K, and M1-M3 bound the sampled
// second derivatives.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <vector>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/filip_bound.h"
#include "nurbs/surface_eval.h"

namespace {

double max_coord(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

/// Slack for comparing a sampled quantity with its bound: both are computed in double from data of
/// size ~1 (random nets in [-1.3, 1.3]^3), and polynomial bounds can be attained exactly (e.g. a
/// quadratic in u has constant S_uu equal to its net), so allow relative 1e-9 plus absolute 1e-12.
bool within(double sampled, double bound) { return sampled <= bound * (1 + 1e-9) + 1e-12; }

struct Stats {
  std::vector<double> ratios;
  double quantile(double q) {
    if (ratios.empty()) return 0.0;
    std::sort(ratios.begin(), ratios.end());
    return ratios[static_cast<size_t>(q * static_cast<double>(ratios.size() - 1))];
  }
};

}  // namespace

TEST_CASE("Filip K bounds the deviation from the grid triangles on 1000 random surfaces") {
  constexpr int kSamples = 6;  // samples per cell edge: (6n+1) x (6m+1) dense points per surface
  Stats poly, rat, m_ratio;
  int surfaces = 0, non_c1 = 0, cells_checked = 0, cells_infinite = 0;
  for (int seed = 0; seed < 1000; ++seed) {
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const bool rational = (seed / 25) % 2 == 1;
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed) + 7000, p, q, rational);
    const auto bound = nurbs::filip_bound(s);
    const int n = 2 + seed % 4, m = 2 + (seed / 4) % 5;
    const double k_grid = nurbs::filip_k_grid(bound, n, m);
    non_c1 += bound.c1() ? 0 : 1;
    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const int W = n * kSamples + 1, H = m * kSamples + 1;
    std::vector<nurbs::SurfaceDerivatives> grid(static_cast<size_t>(W * H));
    double max_d2[3] = {0, 0, 0};
    for (int j = 0; j < H; ++j) {
      for (int i = 0; i < W; ++i) {
        // Grid parameters exactly as a GPU grid would compute them: min + width * index / count.
        const double u = du.min + du.width() * i / (W - 1), v = dv.min + dv.width() * j / (H - 1);
        const auto d = nurbs::surface_derivatives(s, u, v);
        grid[static_cast<size_t>(j * W + i)] = d;
        max_d2[0] = std::max(max_d2[0], max_coord(d.suu));
        max_d2[1] = std::max(max_d2[1], max_coord(d.suv));
        max_d2[2] = std::max(max_d2[2], max_coord(d.svv));
      }
    }
    CAPTURE(seed);
    CHECK(within(max_d2[0], bound.whole.m1));
    CHECK(within(max_d2[1], bound.whole.m2));
    CHECK(within(max_d2[2], bound.whole.m3));
    if (bound.whole.m1 > 0) m_ratio.ratios.push_back(max_d2[0] / bound.whole.m1);
    double max_dev = 0.0;
    for (int cj = 0; cj < m; ++cj) {
      for (int ci = 0; ci < n; ++ci) {
        const double k_cell = nurbs::filip_k_cell(bound, n, m, ci, cj);
        CHECK(k_cell <= k_grid * (1 + 1e-12));  // the per-cell K is never looser than the whole one
        if (!std::isfinite(k_cell)) {
          ++cells_infinite;
          continue;
        }
        auto at = [&](int a, int b) {
          return grid[static_cast<size_t>((cj * kSamples + b) * W + ci * kSamples + a)].s;
        };
        const glm::dvec3 p00 = at(0, 0), p10 = at(kSamples, 0), p01 = at(0, kSamples), p11 = at(kSamples, kSamples);
        double dev = 0.0;
        for (int b = 0; b <= kSamples; ++b) {
          for (int a = 0; a <= kSamples; ++a) {
            const double x = static_cast<double>(a) / kSamples, y = static_cast<double>(b) / kSamples;
            // Two triangles split along the (0,0)-(1,1) diagonal, and the bilinear interpolant.
            const glm::dvec3 tri =
                x >= y ? p00 + x * (p10 - p00) + y * (p11 - p10) : p00 + y * (p01 - p00) + x * (p11 - p01);
            const glm::dvec3 bil = (1 - y) * ((1 - x) * p00 + x * p10) + y * ((1 - x) * p01 + x * p11);
            dev = std::max({dev, max_coord(at(a, b) - tri), max_coord(at(a, b) - bil)});
          }
        }
        CHECK(within(dev, k_cell));
        max_dev = std::max(max_dev, dev);
        ++cells_checked;
      }
    }
    if (std::isfinite(k_grid) && k_grid > 0) (rational ? rat : poly).ratios.push_back(max_dev / k_grid);
    ++surfaces;
  }
  CHECK(surfaces == 1000);
  CHECK(cells_checked > 10000);
  MESSAGE("Filip K: ", surfaces, " surfaces (", non_c1, " not C1), ", cells_checked, " cells checked, ", cells_infinite,
          " cells straddling a C0 knot line");
  MESSAGE("sampled max deviation / K, polynomial: median ", poly.quantile(0.5), ", 90% ", poly.quantile(0.9), ", max ",
          poly.quantile(1.0));
  MESSAGE("sampled max deviation / K, rational:   median ", rat.quantile(0.5), ", 90% ", rat.quantile(0.9), ", max ",
          rat.quantile(1.0));
  MESSAGE("sampled max |S_uu| / M1: median ", m_ratio.quantile(0.5), ", max ", m_ratio.quantile(1.0));
}

TEST_CASE("Filip K on closed forms and the paper pair") {
  // Bilinear patch z = u v on [0,1]^2: M1 = M3 = 0, M2 = 1, so K = (1/8)(2 / (n m)); the maximum
  // deviation of u v from the two triangles of a cell is h_u h_v / 4 at the cell centre — exactly K.
  nurbs::Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
  const auto b = nurbs::filip_bound(s);
  CHECK(b.whole.m1 == 0.0);
  CHECK(b.whole.m2 == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(b.whole.m3 == 0.0);
  CHECK(nurbs::filip_k_grid(b, 4, 5) == doctest::Approx(0.25 / 20).epsilon(1e-15));

  // Units: the same surface on the domain [0, 10] x [0, 10] has M2 = 1/100 and the same K per cell count.
  s.knots_u = s.knots_v = {0, 0, 10, 10};
  const auto b10 = nurbs::filip_bound(s);
  CHECK(b10.whole.m2 == doctest::Approx(0.01).epsilon(1e-15));
  CHECK(nurbs::filip_k_grid(b10, 4, 5) == doctest::Approx(0.25 / 20).epsilon(1e-14));

  // choose_grid meets the tolerance with the fewest cells for the paper's 100 x 105 surface.
  const auto paper = nurbs::filip_bound(models::wavy_surface_100x105());
  for (double tol : {1.0, 0.1, 0.01}) {
    const auto g = nurbs::choose_grid(paper, tol);
    CAPTURE(tol);
    CHECK(g.k <= tol);
    CHECK(g.k == nurbs::filip_k_grid(paper, g.n, g.m));
    if (g.n > 1) CHECK(nurbs::filip_k_grid(paper, g.n - 1, g.m) > tol);
  }
  // The sphere (double knots, degree 2) is C1 in its parametrisation: the check must find that.
  CHECK(nurbs::filip_bound(models::rational_sphere(1.0)).c1());
}
