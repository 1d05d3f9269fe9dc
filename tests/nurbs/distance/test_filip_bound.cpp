// Filip bound K (Krishnamurthy et al. §2.2, Eqs. 1-4) is a true bound: on 1000 random surfaces
// (degrees 1-5, rational and not, fixed seeds) the sampled deviation of the surface from the
// piecewise linear interpolant of an (n+1) x (m+1) grid never exceeds K, and M1-M3 bound the sampled
// second derivatives. The Euclidean K_e bounds the vector distance on the same surfaces, and the
// paper's component K does not (a (1, 1, 1) bulge reaches sqrt(3) K and breaks Theorem 1).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/distance/filip_bound.h"
#include "nurbs/surface_eval.h"
#include "test_suites.h"

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

TEST_CASE("Filip K bounds the deviation from the grid triangles on 1000 random surfaces" * test::sweep()) {
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
  CHECK(cells_checked > 10000);
  // The family exercises what the bound must handle (C0 knot lines), and the bound is not vacuous:
  // somewhere the sampled deviation comes close to K (measured max 0.91 polynomial, 0.66 rational)
  // and |S_uu| close to M1 (measured max 1: quadratics attain it).
  CHECK(non_c1 > 100);
  CHECK(cells_infinite > 0);
  CHECK(poly.quantile(1.0) > 0.5);
  CHECK(rat.quantile(1.0) > 0.3);
  CHECK(m_ratio.quantile(1.0) > 0.99);
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
  // S_uv = (0, 0, 1) lies along an axis: the Euclidean bounds equal the component ones.
  CHECK(b.whole.m2_norm == b.whole.m2);
  CHECK(b.whole.m1_norm == 0.0);
  CHECK(nurbs::filip_k_grid(b, 4, 5, nurbs::KNorm::Euclidean) == nurbs::filip_k_grid(b, 4, 5));

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
    const auto ge = nurbs::choose_grid(paper, tol, 4096, nurbs::KNorm::Euclidean);
    CHECK(ge.k <= tol);
    CHECK(ge.k == nurbs::filip_k_grid(paper, ge.n, ge.m, nurbs::KNorm::Euclidean));
    if (ge.n > 1) CHECK(nurbs::filip_k_grid(paper, ge.n - 1, ge.m, nurbs::KNorm::Euclidean) > tol);
    CHECK(static_cast<long long>(ge.n) * ge.m >= static_cast<long long>(g.n) * g.m);  // K_e >= K needs more cells
  }
  // The sphere (double knots, degree 2) is C1 in its parametrisation: the check must find that.
  CHECK(nurbs::filip_bound(models::rational_sphere(1.0)).c1());
}

TEST_CASE("Euclidean K_e bounds the distance to the grid triangles on the same 1000 random surfaces" * test::sweep()) {
  using nurbs::KNorm;
  constexpr int kSamples = 8;  // samples per cell edge: 9 x 9 points per cell
  const double sqrt3 = std::sqrt(3.0);
  Stats ke_over_k_poly, ke_over_k_rat, me_over_m, dev_over_ke, dev_over_k;
  int cells_checked = 0, cells_over_k = 0;
  double max_dev_over_k_grid = 0.0;
  for (int seed = 0; seed < 1000; ++seed) {
    // The surfaces and grids of the component test above.
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const bool rational = (seed / 25) % 2 == 1;
    const auto s = models::random_surface(static_cast<std::uint64_t>(seed) + 7000, p, q, rational);
    const auto bound = nurbs::filip_bound(s);
    const int n = 2 + seed % 4, m = 2 + (seed / 4) % 5;
    CAPTURE(seed);
    // m*_norm >= m* exactly (guaranteed by construction, see the header); <= sqrt(3) m*
    // up to a few ulps of the norm of the per-coordinate bounds and of sqrt(3) (relative 1e-14).
    auto check_m = [&](const nurbs::SecondDerivativeBounds& b) {
      CHECK(b.m1_norm >= b.m1);
      CHECK(b.m2_norm >= b.m2);
      CHECK(b.m3_norm >= b.m3);
      CHECK(b.m1_norm <= sqrt3 * b.m1 * (1 + 1e-14));
      CHECK(b.m2_norm <= sqrt3 * b.m2 * (1 + 1e-14));
      CHECK(b.m3_norm <= sqrt3 * b.m3 * (1 + 1e-14));
    };
    check_m(bound.whole);
    for (const auto& pb : bound.patches) check_m(pb);
    if (bound.whole.m1 > 0) me_over_m.ratios.push_back(bound.whole.m1_norm / bound.whole.m1);

    const double k_grid = nurbs::filip_k_grid(bound, n, m),
                 ke_grid = nurbs::filip_k_grid(bound, n, m, KNorm::Euclidean);
    CHECK(ke_grid >= k_grid);  // exact: same formula with larger M's
    if (std::isfinite(k_grid) && k_grid > 0)
      (rational ? ke_over_k_rat : ke_over_k_poly).ratios.push_back(ke_grid / k_grid);

    const auto du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const int W = n * kSamples + 1, H = m * kSamples + 1;
    std::vector<glm::dvec3> grid(static_cast<size_t>(W * H));
    double max_d2[3] = {0, 0, 0};
    for (int j = 0; j < H; ++j) {
      for (int i = 0; i < W; ++i) {
        const double u = du.min + du.width() * i / (W - 1), v = dv.min + dv.width() * j / (H - 1);
        const auto d = nurbs::surface_derivatives(s, u, v);
        grid[static_cast<size_t>(j * W + i)] = d.s;
        max_d2[0] = std::max(max_d2[0], glm::length(d.suu));
        max_d2[1] = std::max(max_d2[1], glm::length(d.suv));
        max_d2[2] = std::max(max_d2[2], glm::length(d.svv));
      }
    }
    CHECK(within(max_d2[0], bound.whole.m1_norm));
    CHECK(within(max_d2[1], bound.whole.m2_norm));
    CHECK(within(max_d2[2], bound.whole.m3_norm));

    double max_dev = 0.0;
    for (int cj = 0; cj < m; ++cj) {
      for (int ci = 0; ci < n; ++ci) {
        const double k_cell = nurbs::filip_k_cell(bound, n, m, ci, cj);
        const double ke_cell = nurbs::filip_k_cell(bound, n, m, ci, cj, KNorm::Euclidean);
        CHECK(std::isfinite(k_cell) == std::isfinite(ke_cell));  // the same C^0 cells are infinite
        if (!std::isfinite(ke_cell)) continue;
        CHECK(ke_cell >= k_cell);                 // exact, as for the grid
        CHECK(ke_cell <= ke_grid * (1 + 1e-12));  // never looser than the whole-surface K_e
        auto at = [&](int a, int b) { return grid[static_cast<size_t>((cj * kSamples + b) * W + ci * kSamples + a)]; };
        const glm::dvec3 p00 = at(0, 0), p10 = at(kSamples, 0), p01 = at(0, kSamples), p11 = at(kSamples, kSamples);
        double dev = 0.0;
        for (int b = 0; b <= kSamples; ++b) {
          for (int a = 0; a <= kSamples; ++a) {
            const double x = static_cast<double>(a) / kSamples, y = static_cast<double>(b) / kSamples;
            const glm::dvec3 tri =
                x >= y ? p00 + x * (p10 - p00) + y * (p11 - p10) : p00 + y * (p01 - p00) + x * (p11 - p01);
            const glm::dvec3 bil = (1 - y) * ((1 - x) * p00 + x * p10) + y * ((1 - x) * p01 + x * p11);
            dev = std::max({dev, glm::length(at(a, b) - tri), glm::length(at(a, b) - bil)});
          }
        }
        CHECK(within(dev, ke_cell));
        if (ke_cell > 0) dev_over_ke.ratios.push_back(dev / ke_cell);
        if (k_cell > 0) {
          dev_over_k.ratios.push_back(dev / k_cell);
          cells_over_k += dev > k_cell ? 1 : 0;
        }
        max_dev = std::max(max_dev, dev);
        ++cells_checked;
      }
    }
    if (std::isfinite(k_grid) && k_grid > 0) max_dev_over_k_grid = std::max(max_dev_over_k_grid, max_dev / k_grid);
  }
  CHECK(cells_checked > 10000);
  MESSAGE("Euclidean: ", cells_checked, " cells; sampled ||S - L|| / K_e per cell: median ", dev_over_ke.quantile(0.5),
          ", max ", dev_over_ke.quantile(1.0));
  MESSAGE("sampled ||S - L|| / component K per cell: median ", dev_over_k.quantile(0.5), ", 99% ",
          dev_over_k.quantile(0.99), ", max ", dev_over_k.quantile(1.0), "; cells above 1: ", cells_over_k,
          "; max over surfaces of max ||S - L|| / grid K: ", max_dev_over_k_grid);
  MESSAGE("K_e / K (grid), polynomial: median ", ke_over_k_poly.quantile(0.5), ", max ", ke_over_k_poly.quantile(1.0),
          "; rational: median ", ke_over_k_rat.quantile(0.5), ", max ", ke_over_k_rat.quantile(1.0),
          "; M1e / M1: median ", me_over_m.quantile(0.5), ", max ", me_over_m.quantile(1.0));
}

TEST_CASE("A bulge along (1, 1, 1) reaches sqrt(3) K and breaks Theorem 1 for the component K") {
  // S = u a + v b + u (1 - u) e on [0,1]^2, e = (1, 1, 1), a and b orthonormal and orthogonal to e:
  // one cell, L = u a + v b (linear, reproduced by both triangles), S - L = u (1 - u) e. S_uu = -2 e,
  // so M1 = 2, M1e = 2 sqrt(3), M2 = M3 = 0: K = 1/4, K_e = sqrt(3) / 4, both attained at u = 1/2.
  const glm::dvec3 a = glm::dvec3(1, -1, 0) / std::sqrt(2.0), b = glm::dvec3(1, 1, -2) / std::sqrt(6.0);
  const glm::dvec3 e(1, 1, 1);
  nurbs::Surface s;
  s.degree_u = 2;
  s.degree_v = 1;
  s.count_u = 3;
  s.count_v = 2;
  s.knots_u = {0, 0, 0, 1, 1, 1};
  s.knots_v = {0, 0, 1, 1};
  // Bernstein coefficients: u -> (0, 1/2, 1), u (1 - u) -> (0, 1/2, 0), v -> (0, 1).
  for (double y : {0.0, 1.0}) {
    s.points.push_back(y * b);
    s.points.push_back(0.5 * a + y * b + 0.5 * e);
    s.points.push_back(a + y * b);
  }
  const auto bound = nurbs::filip_bound(s);
  const double k = nurbs::filip_k_grid(bound, 1, 1), ke = nurbs::filip_k_grid(bound, 1, 1, nurbs::KNorm::Euclidean);
  // 1e-14 here and below: the data (a, b, e / sqrt(3), A4.3 evaluation) are of size ~1 and exact to a
  // few ulps (2.2e-16 each), e.g. the net 2 (P2 - 2 P1 + P0) = -2 e.
  CHECK(k == doctest::Approx(0.25).epsilon(1e-14));
  CHECK(ke == doctest::Approx(std::sqrt(3.0) / 4).epsilon(1e-14));
  const glm::dvec3 dev = nurbs::surface_point(s, 0.5, 0.5) - (0.5 * a + 0.5 * b);
  CHECK(max_coord(dev) == doctest::Approx(k).epsilon(1e-14));     // Filip's K is attained per coordinate
  CHECK(glm::length(dev) == doctest::Approx(ke).epsilon(1e-14));  // and K_e in the Euclidean norm

  // Theorem 1: from O = S(1/2, 1/2) + e / sqrt(3), the surface is 1 away (all of S lies on the near
  // side of the plane through S(1/2, 1/2) normal to e) and the triangles 1 + sqrt(3) / 4 (O projects
  // to L(1/2, 1/2), inside the cell): |d - d*| = sqrt(3) / 4 > K. The sampled d* is >= the true one
  // and equals it at the sampled (1/2, 1/2).
  const glm::dvec3 en = e / std::sqrt(3.0), O = nurbs::surface_point(s, 0.5, 0.5) + en;
  const double d_triangles = glm::dot(O, en);                    // the plane of L passes through the origin, normal e
  CHECK(glm::dot(O, a) == doctest::Approx(0.5).epsilon(1e-14));  // the projection is L(1/2, 1/2)
  CHECK(glm::dot(O, b) == doctest::Approx(0.5).epsilon(1e-14));
  double d_surface = 1e300;
  for (int j = 0; j <= 40; ++j) {
    for (int i = 0; i <= 40; ++i)
      d_surface = std::min(d_surface, glm::length(O - nurbs::surface_point(s, i / 40.0, j / 40.0)));
  }
  CHECK(d_surface == doctest::Approx(1.0).epsilon(1e-14));
  CHECK(d_triangles - d_surface > k);            // Theorem 1 with the paper's K fails (by 0.18)
  CHECK(d_triangles - d_surface <= ke + 1e-14);  // K_e holds, with equality up to roundoff
  MESSAGE("(1,1,1) bulge: |d - d*| = ", d_triangles - d_surface, ", K = ", k, ", K_e = ", ke);
}

TEST_CASE("filip_bound reads each patch in place: the bounds of the extracted patches, polynomial fast path included") {
  // The one-piece bounds read the refined net in place (BezierNet); polynomial patches take the
  // second-difference nets alone. Both must give what the general formula gives on the extracted
  // patches: the same surface with explicit unit weights goes through the quotient rule.
  int compared = 0;
  for (int seed = 0; seed < 60; ++seed) {
    const int p = 1 + seed % 4, q = 1 + (seed / 4) % 4;
    const bool rational = seed % 3 == 0;
    const nurbs::Surface s = models::random_surface(static_cast<std::uint64_t>(seed) + 9100, p, q, rational);
    const nurbs::FilipBound b = nurbs::filip_bound(s, 1);
    const auto patches = nurbs::extract_bezier_patches(s);
    REQUIRE(b.patches.size() == patches.size());
    for (size_t k = 0; k < patches.size(); ++k) {
      nurbs::Surface general = patches[k].surface;
      if (general.weights.empty()) general.weights.assign(general.points.size(), 1.0);
      const nurbs::SecondDerivativeBounds want =
          nurbs::bezier_patch_bounds(general, patches[k].range_u.width(), patches[k].range_v.width());
      const nurbs::SecondDerivativeBounds& got = b.patches[k];
      for (auto [g, w] : {std::pair{got.m1, want.m1},
                          {got.m2, want.m2},
                          {got.m3, want.m3},
                          {got.m1_norm, want.m1_norm},
                          {got.m2_norm, want.m2_norm},
                          {got.m3_norm, want.m3_norm}}) {
        CHECK(g == doctest::Approx(w).epsilon(1e-12).scale(1.0));
        ++compared;
      }
    }
  }
  MESSAGE(compared, " bounds compared");
  CHECK(compared > 1000);
}

TEST_CASE("first_derivative_bounds bound the sampled |S_u| and |S_v| of random surfaces, and the Lipschitz step") {
  // Degrees 1-5, rational and not: every Bézier patch's bounds against |S_u|, |S_v| sampled on a
  // 9 x 9 grid of it (inset by 1e-9 of its widths: on a knot line the evaluation takes the next
  // span's one-sided derivative, which differs where the surface is only C0), and
  // |S(a) - S(b)| <= L |a - b| for random point pairs of the patch.
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int patches = 0;
  double tightest = 0.0;  // the largest sampled / bound: the bound is not vacuous
  for (int seed = 0; seed < 200; ++seed) {
    const int p = 1 + seed % 5, q = 1 + (seed / 5) % 5;
    const bool rational = seed % 2 == 0;
    const nurbs::Surface s = models::random_surface(static_cast<std::uint64_t>(seed) + 9300, p, q, rational);
    for (const nurbs::BezierPatch& patch : nurbs::extract_bezier_patches(s)) {
      const nurbs::FirstDerivativeBounds b = nurbs::first_derivative_bounds(
          nurbs::BezierNet::of(patch.surface), patch.range_u.width(), patch.range_v.width());
      auto at = [&](double a, double c) {
        return glm::dvec2(patch.range_u.min + a * patch.range_u.width(), patch.range_v.min + c * patch.range_v.width());
      };
      for (int j = 0; j <= 8; ++j)
        for (int i = 0; i <= 8; ++i) {
          const glm::dvec2 uv = at(1e-9 + (1 - 2e-9) * i / 8.0, 1e-9 + (1 - 2e-9) * j / 8.0);
          const nurbs::SurfaceDerivatives d = nurbs::surface_derivatives(s, uv.x, uv.y);
          CHECK(within(glm::length(d.su), b.su));
          CHECK(within(glm::length(d.sv), b.sv));
          tightest = std::max({tightest, glm::length(d.su) / b.su, glm::length(d.sv) / b.sv});
        }
      for (int k = 0; k < 20; ++k) {
        const glm::dvec2 a = at(unit(rng), unit(rng)), c = at(unit(rng), unit(rng));
        const double moved = glm::length(nurbs::surface_point(s, a.x, a.y) - nurbs::surface_point(s, c.x, c.y));
        CHECK(within(moved, b.lipschitz() * glm::length(a - c)));
      }
      ++patches;
    }
  }
  MESSAGE(patches, " patches, largest sampled / bound ", tightest);
  CHECK(patches > 500);
  CHECK(tightest > 0.5);
}
