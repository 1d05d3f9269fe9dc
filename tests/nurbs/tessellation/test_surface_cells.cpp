// §5 surface cells (surface_cells.h): exact shapes with known answers, the proven bounds against
// dense sampling on random polynomial and rational patches, tiling, and the kd-tree vs quadtree figures.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <string>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/knot_vector.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/surface_cells.h"
#include "test_suites.h"

using nurbs::Interval;
using nurbs::Surface;
using nurbs::tess::Cell;
using nurbs::tess::CellOptions;
using nurbs::tess::CellStats;
using nurbs::tess::Subdivision;
using nurbs::tess::SurfaceError;

namespace {

// Roundoff allowance for the bound checks: the net of a leaf comes from repeated knot insertion and
// the surface points from A2.2 evaluation, both ~1e-15 relative on coordinates of size <= ~5.
constexpr double kRoundoff = 1e-12;

/// The corners of a cell on the surface.
struct Corners {
  glm::dvec3 c00, c10, c01, c11;
};
Corners corners(const Surface& s, const Cell& c) {
  return {nurbs::surface_point(s, c.u.min, c.v.min), nurbs::surface_point(s, c.u.max, c.v.min),
          nurbs::surface_point(s, c.u.min, c.v.max), nurbs::surface_point(s, c.u.max, c.v.max)};
}

/// The two-triangle interpolant of the corners at local (a, b) in [0, 1]^2; `diagonal` 0 splits
/// along (0,0)-(1,1), 1 along (1,0)-(0,1).
glm::dvec3 two_triangles(const Corners& k, double a, double b, int diagonal) {
  if (diagonal == 0)
    return a >= b ? k.c00 + a * (k.c10 - k.c00) + b * (k.c11 - k.c10)
                  : k.c00 + b * (k.c01 - k.c00) + a * (k.c11 - k.c01);
  return a + b <= 1 ? k.c00 + a * (k.c10 - k.c00) + b * (k.c01 - k.c00)
                    : k.c11 + (1 - a) * (k.c01 - k.c11) + (1 - b) * (k.c10 - k.c11);
}

double point_segment(glm::dvec3 x, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 ab = b - a;
  const double l2 = glm::dot(ab, ab);
  const double t = l2 > 0 ? std::clamp(glm::dot(x - a, ab) / l2, 0.0, 1.0) : 0.0;
  return glm::length(x - a - t * ab);
}

/// Distance from x to the triangle abc: to the plane when the projection is inside, else to the edges.
double point_triangle(glm::dvec3 x, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (n2 > 0) {
    const glm::dvec3 p = x - glm::dot(x - a, n) / n2 * n;
    const double la = glm::dot(glm::cross(c - b, p - b), n), lb = glm::dot(glm::cross(a - c, p - c), n),
                 lc = glm::dot(glm::cross(b - a, p - a), n);
    if (la >= 0 && lb >= 0 && lc >= 0) return std::abs(glm::dot(x - a, n)) / std::sqrt(n2);
  }
  return std::min({point_segment(x, a, b), point_segment(x, b, c), point_segment(x, c, a)});
}

/// Distance from x to the cell's two triangles (either diagonal).
double point_mesh(glm::dvec3 x, const Corners& k, int diagonal) {
  if (diagonal == 0) return std::min(point_triangle(x, k.c00, k.c10, k.c11), point_triangle(x, k.c00, k.c11, k.c01));
  return std::min(point_triangle(x, k.c00, k.c10, k.c01), point_triangle(x, k.c11, k.c01, k.c10));
}

double lerp(Interval i, double t) { return i.min + t * (i.max - i.min); }

std::vector<double> greville(const Surface& net, bool along_u) {
  const auto& U = along_u ? net.knots_u : net.knots_v;
  const int p = along_u ? net.degree_u : net.degree_v, n = along_u ? net.count_u : net.count_v;
  std::vector<double> g;
  for (int i = 0; i < n; ++i) {
    double sum = 0;
    for (int k = 1; k <= p; ++k) sum += U[size_t(i + k)];
    g.push_back((sum / p - U[size_t(p)]) / (U[size_t(n)] - U[size_t(p)]));
  }
  return g;
}

/// The rational lemma of surface_cells.h: |S(u, v) - S~(σ(u, v))| for σ = Σ β_ij g_ij.
double sigma_witness(const Surface& net, double u, double v) {
  const auto gu = greville(net, true), gv = greville(net, false);
  const int su = nurbs::find_span(net.knots_u, net.degree_u, net.count_u, u);
  const int sv = nurbs::find_span(net.knots_v, net.degree_v, net.count_v, v);
  const auto nu = nurbs::basis_functions(net.knots_u, net.degree_u, su, u);
  const auto nv = nurbs::basis_functions(net.knots_v, net.degree_v, sv, v);
  double wsum = 0, a = 0, b = 0;
  for (int j = 0; j <= net.degree_v; ++j)
    for (int i = 0; i <= net.degree_u; ++i) {
      const int ci = su - net.degree_u + i, cj = sv - net.degree_v + j;
      const double beta = net.weight(ci, cj) * nu[size_t(i)] * nv[size_t(j)];
      wsum += beta;
      a += beta * gu[size_t(ci)];
      b += beta * gv[size_t(cj)];
    }
  a /= wsum;
  b /= wsum;
  const int m = net.count_u - 1, n = net.count_v - 1;
  const glm::dvec3 bilin = (1 - b) * ((1 - a) * net.point(0, 0) + a * net.point(m, 0)) +
                           b * ((1 - a) * net.point(0, n) + a * net.point(m, n));
  return glm::length(nurbs::surface_point(net, u, v) - bilin);
}

/// An upper bound of the distance from x to the surface over the cell: the nearest of 5 x 5
/// samples, then 5 x 5 samples over the quarter-size window around it, four times (a pattern
/// search: Newton alone stops at once on a pole, where S_u vanishes), improved by clamped
/// Gauss-Newton steps (any surface point found bounds the distance).
double surface_distance(const Surface& s, const Cell& c, glm::dvec3 x) {
  glm::dvec2 best(c.u.min, c.v.min);
  double dist = 1e300;
  Interval wu = c.u, wv = c.v;
  for (int round = 0; round < 5; ++round) {
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) {
        const glm::dvec2 q(lerp(wu, i / 4.0), lerp(wv, j / 4.0));
        const double d = glm::length(nurbs::surface_point(s, q.x, q.y) - x);
        if (d < dist) dist = d, best = q;
      }
    const double hu = wu.width() / 4, hv = wv.width() / 4;
    wu = {std::max(c.u.min, best.x - hu), std::min(c.u.max, best.x + hu)};
    wv = {std::max(c.v.min, best.y - hv), std::min(c.v.max, best.y + hv)};
  }
  for (int it = 0; it < 12; ++it) {
    const auto d = nurbs::surface_derivatives(s, best.x, best.y);
    const glm::dvec3 r = d.s - x;
    const double a = glm::dot(d.su, d.su), b = glm::dot(d.su, d.sv), e = glm::dot(d.sv, d.sv);
    const double det = a * e - b * b;
    if (!(det > 0)) break;
    const double gu = glm::dot(d.su, r), gv = glm::dot(d.sv, r);
    const glm::dvec2 q(std::clamp(best.x - (e * gu - b * gv) / det, c.u.min, c.u.max),
                       std::clamp(best.y - (a * gv - b * gu) / det, c.v.min, c.v.max));
    const double dq = glm::length(nurbs::surface_point(s, q.x, q.y) - x);
    if (!(dq < dist)) break;
    dist = dq, best = q;
  }
  return dist;
}

/// Checks every leaf against its proven bound (dense samples; random triangles for bilinear_factor
/// 2; rational: both directions of the set distance) and returns the max over leaves of observed
/// error / bound, surface to mesh (how tight the bound is).
double check_leaves(const Surface& s, const std::vector<Cell>& cells, double eps, models::Random& rng) {
  const bool rational = s.rational();
  double worst_ratio = 0;
  for (const Cell& c : cells) {
    CHECK(proven_cell_bound(c, rational, false) <= eps * (1 + 1e-12));  // the leaf test itself
    const Corners k = corners(s, c);
    const Surface net = rational ? nurbs::restrict_surface(s, c.u, c.v) : Surface{};
    double err = 0, witness = 0;
    constexpr int kN = 8;  // 9 x 9 samples per leaf, corners and edges included
    for (int j = 0; j <= kN; ++j)
      for (int i = 0; i <= kN; ++i) {
        const double a = double(i) / kN, b = double(j) / kN;
        const glm::dvec3 x = nurbs::surface_point(s, lerp(c.u, a), lerp(c.v, b));
        for (int d = 0; d < 2; ++d)  // Polynomial: at equal parameters. Rational: set distance.
          err = std::max(err, rational ? point_mesh(x, k, d) : glm::length(x - two_triangles(k, a, b, d)));
        if (rational) witness = std::max(witness, sigma_witness(net, lerp(c.u, a), lerp(c.v, b)));
      }
    const double bound = proven_cell_bound(c, rational, false);
    CHECK(err <= bound + kRoundoff);
    worst_ratio = std::max(worst_ratio, err / bound);
    if (rational) CHECK(witness <= c.bilinear + 0.25 * c.twist + kRoundoff);  // the lemma behind it
    // Rational: the other direction, mesh points T(a, b) to the surface over the cell.
    for (int t = 0; rational && t < 2; ++t) {
      const glm::dvec3 x = two_triangles(k, rng.uniform(), rng.uniform(), t % 2);
      CHECK(surface_distance(s, c, x) <= bound + kRoundoff);
    }
    // bilinear_factor 2 bound: any triangle inside the cell, any barycentric point.
    double any_err = 0;
    for (int t = 0; t < (rational ? 2 : 8); ++t) {
      glm::dvec3 mesh(0.0);
      glm::dvec2 mean(0.0);
      const double l[3] = {rng.uniform(), rng.uniform(), rng.uniform()}, lsum = l[0] + l[1] + l[2];
      for (int r = 0; r < 3; ++r) {
        const glm::dvec2 q(lerp(c.u, rng.uniform()), lerp(c.v, rng.uniform()));
        mesh += l[r] / lsum * nurbs::surface_point(s, q.x, q.y);
        mean += l[r] / lsum * q;
      }
      any_err = std::max(any_err, rational ? surface_distance(s, c, mesh)
                                           : glm::length(mesh - nurbs::surface_point(s, mean.x, mean.y)));
    }
    CHECK(any_err <= proven_cell_bound(c, rational, true) + kRoundoff);
  }
  return worst_ratio;
}

CellOptions options(double eps, SurfaceError e, Subdivision d) {
  CellOptions o;
  o.eps_surface = eps;
  o.error = e;
  o.subdivision = d;
  return o;
}

}  // namespace

TEST_CASE("surface cells: a plane is one cell") {
  // Control points affine in the Greville abscissae: S is that affine map (linear precision).
  Surface s = models::random_surface(7, 3, 2, false);
  s = nurbs::restrict_surface(s, nurbs::surface_domain_u(s), nurbs::surface_domain_v(s));  // clamped
  const auto g_u = greville(s, true), g_v = greville(s, false);
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i)
      s.points[size_t(j * s.count_u + i)] =
          glm::dvec3(1, 2, 3) + g_u[size_t(i)] * glm::dvec3(4, 1, 0.5) + g_v[size_t(j)] * glm::dvec3(-1, 3, 2);
  for (Subdivision d : {Subdivision::KdTree, Subdivision::Quadtree})
    for (SurfaceError e : {SurfaceError::Conservative, SurfaceError::Approximate}) {
      const auto cells = subdivide_surface(s, options(1e-9, e, d));
      REQUIRE(cells.size() == 1);
      CHECK(cells[0].error() < 1e-14);  // roundoff of Greville sums on coordinates ~5
    }
}

TEST_CASE("surface cells: a cylinder splits only across its curved direction in the kd-tree") {
  const Surface cyl = models::rational_cylinder(1.0, 4.0);
  for (SurfaceError e : {SurfaceError::Conservative, SurfaceError::Approximate}) {
    CellOptions kd = options(1e-3, e, Subdivision::KdTree), quad = options(1e-3, e, Subdivision::Quadtree);
    kd.domain_u = quad.domain_u = Interval{0.0, 0.25};  // a quarter: one Bézier span around
    CellStats ks, qs;
    const auto kc = subdivide_surface(cyl, kd, &ks), qc = subdivide_surface(cyl, quad, &qs);
    for (const Cell& c : kc) CHECK((c.v.min == 0.0 && c.v.max == 1.0));  // never cut along the rulings
    CHECK(std::any_of(qc.begin(), qc.end(), [](const Cell& c) { return c.v.max - c.v.min < 1.0; }));
    CHECK(kc.size() < qc.size());
    CHECK(ks.unconverged == 0);
    MESSAGE("cylinder quarter r=1 h=4 eps=1e-3 ",
            std::string(e == SurfaceError::Conservative ? "conservative" : "approximate"), ": kd ", kc.size(),
            " leaves, quad ", qc.size());
  }
}

TEST_CASE("surface cells: proven bound holds on random polynomial and rational patches" * test::sweep()) {
  models::Random rng(2024);
  double worst_poly = 0, worst_rat = 0;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    const bool rational = seed % 3 == 2;
    const int du = seed % 5 == 0 ? 1 + int(seed / 5 % 4) : 3, dv = seed % 7 == 0 ? 2 : 3;
    const Surface s = models::random_surface(seed, du, dv, rational);
    const double eps = 0.1;  // coordinates in [-1, 1]^3: a coarse but non-trivial tolerance
    CellOptions o = options(eps, SurfaceError::Conservative, seed % 2 ? Subdivision::KdTree : Subdivision::Quadtree);
    o.bound = (seed / 2) % 2 ? nurbs::tess::CellBound::ControlNet : nurbs::tess::CellBound::Filip;
    CellStats st;
    const auto cells = subdivide_surface(s, o, &st);
    REQUIRE(st.unconverged == 0);
    const double r = check_leaves(s, cells, eps, rng);
    (rational ? worst_rat : worst_poly) = std::max(rational ? worst_rat : worst_poly, r);
  }
  MESSAGE("max observed error / proven bound: polynomial ", worst_poly, ", rational ", worst_rat);
}

TEST_CASE("surface cells: Filip's bound ends cells sooner than the control-net test, and holds") {
  // A quarter of the rational sphere and a random bicubic, any-triangle budget (bilinear_factor 2 as
  // the tessellator's guaranteed mode): the cells' Filip bound lets them grow, every leaf still
  // meets its bound on dense samples and random triangles (check_leaves).
  models::Random rng(77);
  const Surface sphere = models::rational_sphere(1.0), bicubic = models::random_surface(11, 3, 3, false);
  for (const Surface* s : {&sphere, &bicubic}) {
    size_t leaves[3] = {0, 0, 0};  // control net; Filip (cuts chosen by it); Filip with the paper's cuts
    int filip_leaves = 0;
    for (int b = 0; b < 3; ++b) {
      CellOptions o = options(1e-2, SurfaceError::Conservative, Subdivision::KdTree);
      o.bilinear_factor = 2.0;
      o.bound = b == 0 ? nurbs::tess::CellBound::ControlNet : nurbs::tess::CellBound::Filip;
      o.filip_split = b == 1;
      if (s == &sphere) o.domain_u = Interval{0.0, 0.25};
      CellStats st;
      const auto cells = subdivide_surface(*s, o, &st);
      REQUIRE(st.unconverged == 0);
      leaves[b] = cells.size();
      for (const Cell& c : cells) filip_leaves += b == 1 && c.filip <= o.eps_surface ? 1 : 0;
      (void)check_leaves(*s, cells, o.eps_surface, rng);
    }
    CAPTURE(leaves[0]);
    CAPTURE(leaves[1]);
    CAPTURE(leaves[2]);
    CHECK(filip_leaves > 0);
    CHECK(double(leaves[1]) < 0.8 * double(leaves[0]));
    if (s == &bicubic) CHECK(leaves[2] != leaves[1]);  // the cuts differ (on the sphere they meet)
    MESSAGE((s == &sphere ? "sphere quarter" : "random bicubic")
            << ": control-net " << leaves[0] << " leaves, Filip " << leaves[1] << " (" << filip_leaves
            << " ended by Filip's bound), Filip with the paper's cuts " << leaves[2]);
  }
}

TEST_CASE("surface cells: a rational bilinear patch needs the rational extra term") {
  // Degree (1, 1), corners of a hyperbolic paraboloid (twist h e_z, ε_bilin = 0), weights W on the
  // diagonal 00-11: S(1/2, 1/2) -> (P00 + P11) / 2 as W grows, which is h/2 = twist/2 away from the
  // triangles cut along the other diagonal 10-01, twice the polynomial bound twist/4.
  const double h = 0.1, big = 1e4;
  Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, h}};
  s.weights = {big, 1, 1, big};
  const auto cells = subdivide_surface(s, options(1.0, SurfaceError::Conservative, Subdivision::KdTree));
  REQUIRE(cells.size() == 1);
  const Cell& c = cells[0];
  CHECK(c.bilinear == 0.0);
  CHECK(std::abs(c.twist - h) < 1e-15);  // exact corner arithmetic up to one rounding
  const double d = point_mesh(nurbs::surface_point(s, 0.5, 0.5), corners(s, c), 1);
  CHECK(d > c.bilinear + 0.25 * c.twist);                                  // the polynomial bound fails
  CHECK(d <= nurbs::tess::proven_cell_bound(c, true, false) + kRoundoff);  // ours holds
  // The same patch with unit weights is the hyperbolic paraboloid: within twist/4.
  s.weights.clear();
  CHECK(glm::length(nurbs::surface_point(s, 0.5, 0.5) - two_triangles(corners(s, c), 0.5, 0.5, 1)) <=
        0.25 * h + kRoundoff);
}

TEST_CASE("surface cells: a triangle with vertices inside the cell needs bilinear_factor 2") {
  // Degree (1, 1), 5 x 2 points, z = 0, e, -e, e, 0 along u (flat corners: twist 0, ε_bilin = e).
  // The triangle (1/4, 0), (3/4, 0), (1/4, 1) has the mesh at height e over u = 1/2 where the
  // surface is at -e: 2 ε_bilin, the bound of bilinear_factor 2, attained.
  const double e = 0.3;
  Surface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = 5;
  s.count_v = 2;
  s.knots_u = {0, 0, 0.25, 0.5, 0.75, 1, 1};
  s.knots_v = {0, 0, 1, 1};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 5; ++i) s.points.emplace_back(i / 4.0, j, i % 4 == 0 ? 0.0 : (i == 2 ? -e : e));
  const auto cells = subdivide_surface(s, options(10.0, SurfaceError::Conservative, Subdivision::KdTree));
  REQUIRE(cells.size() == 1);
  CHECK(cells[0].twist == 0.0);
  CHECK(cells[0].bilinear == doctest::Approx(e).epsilon(1e-15));
  const glm::dvec3 mesh = 0.5 * (nurbs::surface_point(s, 0.25, 0.0) + nurbs::surface_point(s, 0.75, 0.0));
  const double err = glm::length(mesh - nurbs::surface_point(s, 0.5, 0.0));
  CHECK(err > nurbs::tess::proven_cell_bound(cells[0], false, false));              // factor 1 is not enough
  CHECK(err <= nurbs::tess::proven_cell_bound(cells[0], false, true) + kRoundoff);  // factor 2 holds
}

TEST_CASE("surface cells: leaves tile the rectangle exactly") {
  models::Random rng(99);
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    const Surface s = models::random_surface(seed, 1 + int(seed % 4), 1 + int(seed / 4 % 4), seed % 2 == 1);
    const Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    CellOptions o = options(0.1, seed % 3 ? SurfaceError::Conservative : SurfaceError::Approximate,
                            seed % 4 < 2 ? Subdivision::KdTree : Subdivision::Quadtree);
    o.bilinear_factor = seed % 5 == 0 ? 2.0 : 1.0;
    Interval u = du, v = dv;
    if (seed % 2 == 0) {  // a sub-rectangle, as for the bounding box of trim loops
      const double a = rng.uniform(0, 0.5), b = rng.uniform(0, 0.5);
      u = {lerp(du, a), lerp(du, a + 0.5)};
      v = {lerp(dv, b), lerp(dv, b + rng.uniform(0.1, 0.5))};
      o.domain_u = u;
      o.domain_v = v;
    }
    CellStats st;
    const auto cells = subdivide_surface(s, o, &st);
    CHECK(st.leaves == int(cells.size()));
    CHECK(st.nodes >= st.leaves);
    double area = 0;
    for (size_t i = 0; i < cells.size(); ++i) {
      const Cell& c = cells[i];
      CHECK((u.min <= c.u.min && c.u.min < c.u.max && c.u.max <= u.max));
      CHECK((v.min <= c.v.min && c.v.min < c.v.max && c.v.max <= v.max));
      area += c.u.width() * c.v.width();
      if (o.error == SurfaceError::Conservative)
        CHECK(proven_cell_bound(c, s.rational(), o.bilinear_factor == 2.0) <= 0.1 * (1 + 1e-12));
      for (size_t j = 0; j < i; ++j) {  // interiors disjoint: touching only along shared edges
        const Cell& d = cells[j];
        CHECK((c.u.max <= d.u.min || d.u.max <= c.u.min || c.v.max <= d.v.min || d.v.max <= c.v.min));
      }
    }
    // Disjoint interiors + equal area = a partition; 1e-12: the roundoff of summing the products.
    CHECK(std::abs(area - u.width() * v.width()) <= 1e-12 * u.width() * v.width());
  }
}

TEST_CASE("surface cells: counts fall as eps grows, conservative >= approximate" * test::sweep()) {
  long total_cons = 0, total_approx = 0;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const Surface s = models::random_surface(seed, 3, 3, seed % 4 == 3);
    for (Subdivision d : {Subdivision::KdTree, Subdivision::Quadtree}) {
      size_t last_cons = SIZE_MAX;
      for (double eps : {0.02, 0.05, 0.1, 0.2, 0.5}) {
        const size_t cons = subdivide_surface(s, options(eps, SurfaceError::Conservative, d)).size();
        const size_t approx = subdivide_surface(s, options(eps, SurfaceError::Approximate, d)).size();
        // The tree's splits do not depend on eps, so a larger eps prunes it: never more leaves.
        CHECK(cons <= last_cons);
        // Quadtree splits are the same in both modes and, for polynomial patches, |S(g) - S~(g)|
        // <= ε_bilin (surface_cells.h), so the approximate tree is a pruned conservative one.
        if (d == Subdivision::Quadtree && !s.rational()) CHECK(approx <= cons);
        if (d == Subdivision::KdTree) {
          total_cons += long(cons);
          total_approx += long(approx);
        }
        last_cons = cons;
      }
      CHECK(subdivide_surface(s, options(0.5, SurfaceError::Conservative, d)).size() <
            subdivide_surface(s, options(0.02, SurfaceError::Conservative, d)).size());
    }
  }
  CHECK(total_approx < total_cons);  // kd-tree splits differ between modes: compared in total only
  MESSAGE("kd-tree leaves over 40 random bicubic patches x 5 eps: conservative ", total_cons, ", approximate ",
          total_approx);
}

TEST_CASE("surface cells: max depth stops the subdivision and is reported") {
  const Surface s = models::rational_sphere(1.0);
  CellOptions o = options(1e-9, SurfaceError::Conservative, Subdivision::KdTree);
  o.max_depth = 3;
  CellStats st;
  const auto cells = subdivide_surface(s, o, &st);
  CHECK(cells.size() <= 8);  // binary splits to depth 3
  CHECK(st.max_depth == 3);
  CHECK(st.unconverged == int(cells.size()));
  CHECK(st.rational_extra == 0.25);  // bilinear_factor 1 on a rational surface
  o.max_depth = 40;
  o.eps_surface = 0.0;  // never flat enough: only the node cap ends it
  o.max_nodes = 1000;
  const auto capped = subdivide_surface(s, o, &st);
  CHECK(st.nodes <= 1000 + 40);  // the cap, plus at most one open sibling per level
  CHECK(st.unconverged == int(capped.size()));
  double area = 0;
  for (const Cell& c : capped) area += c.u.width() * c.v.width();
  CHECK(std::abs(area - 1.0) < 1e-12);  // still a tiling of the unit domain (roundoff of the sum)
}

TEST_CASE("surface cells: kd-tree vs quadtree figures (Table 3 style)" * test::sweep()) {
  struct Shape {
    const char* name;
    Surface s;
    double eps;
  };
  const Shape shapes[] = {{"sphere r=10", models::rational_sphere(10.0), 0.01},
                          {"torus 10/3", models::rational_torus(10.0, 3.0), 0.01},
                          {"cylinder r=5 h=20", models::rational_cylinder(5.0, 20.0), 0.01},
                          {"wavy 100x105 mm", models::wavy_surface_100x105(), 0.05}};
  for (const Shape& sh : shapes) {
    std::string line = std::string(sh.name) + " eps " + std::to_string(sh.eps) + ":";
    for (SurfaceError e : {SurfaceError::Conservative, SurfaceError::Approximate})
      for (Subdivision d : {Subdivision::KdTree, Subdivision::Quadtree}) {
        CellStats st;
        const auto cells = subdivide_surface(sh.s, options(sh.eps, e, d), &st);
        CHECK(st.unconverged == 0);
        char buf[160];
        std::snprintf(buf, sizeof buf, " %s/%s %d leaves (%d nodes, depth %d, %.3f s);",
                      e == SurfaceError::Conservative ? "cons" : "approx", d == Subdivision::KdTree ? "kd" : "quad",
                      st.leaves, st.nodes, st.max_depth, st.seconds);
        line += buf;
      }
    MESSAGE(line);
  }
}

TEST_CASE("surface cells: a domain end a rounding away from a knot does not drive the cuts beside the knot") {
  // Degree 5 in v with a triple knot at 0.5 (C2 there). Loops that start at v = 4.3e-16 instead of 0
  // put the midpoints at 0.5 + 2.2e-16: without the snap to the knot every node beside it held a
  // span 2.2e-16 wide, whose Filip bound grows as 1/width^2, and the kd-tree halved v to its depth
  // limit (40) with cells still above eps.
  Surface s = models::random_surface(21, 3, 5, false);
  s.knots_v = {0, 0, 0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1, 1, 1};
  s.count_v = 9;
  s.points.resize(size_t(s.count_u * s.count_v));
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i)
      s.points[size_t(j * s.count_u + i)] = {double(i), double(j) / 8.0, 0.3 * std::sin(double(i + 2 * j))};
  const Interval du = surface_domain_u(s);
  for (Subdivision method : {Subdivision::KdTree, Subdivision::Quadtree}) {
    CellOptions o = options(2e-3, SurfaceError::Conservative, method);
    CellStats exact, off;
    o.domain_u = du;
    o.domain_v = Interval{0.0, 1.0};
    const auto a = subdivide_surface(s, o, &exact);
    o.domain_v = Interval{4.316496732e-16, 1.0};
    const auto b = subdivide_surface(s, o, &off);
    CAPTURE(method == Subdivision::KdTree);
    CHECK(off.unconverged == 0);
    CHECK(off.max_depth < 20);
    CHECK(off.leaves == exact.leaves);
    CHECK(exact.unconverged == 0);
  }
}

TEST_CASE("surface cells: the certified grid's cells tile the rectangle and hold their Filip bound") {
  // Subdivision::Grid: the cells of certified_grid clipped to the rectangle asked for; each cell's
  // own K_e is its bound for any triangle inside it (check_leaves samples both).
  models::Random rng(5);
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const Surface s = models::random_surface(seed, 1 + int(seed % 3), 3, false);
    CellOptions o = options(0.05, SurfaceError::Conservative, Subdivision::Grid);
    o.bilinear_factor = 2.0;
    const Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    o.domain_u = Interval{lerp(du, 0.1), lerp(du, 0.8)};
    CellStats st;
    const auto cells = subdivide_surface(s, o, &st);
    CAPTURE(seed);
    REQUIRE(st.unconverged == 0);
    double area = 0.0;
    for (const Cell& c : cells) {
      CHECK(c.u.min >= o.domain_u->min);
      CHECK(c.u.max <= o.domain_u->max);
      CHECK(c.filip <= o.eps_surface);
      area += (c.u.max - c.u.min) * (c.v.max - c.v.min);
    }
    CHECK(area == doctest::Approx((o.domain_u->max - o.domain_u->min) * (dv.max - dv.min)).epsilon(1e-12));
    (void)check_leaves(s, cells, o.eps_surface, rng);
  }
}
