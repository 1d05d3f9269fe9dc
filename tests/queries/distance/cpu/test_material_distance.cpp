// The material part of a cell's triangles (queries/distance/material_distance.h, §5.3's "continue the
// search"): the exact least distance between material points of two triangles against a plain
// reference, every material sample pair of dense barycentric grids.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <vector>

#include "models/random_surfaces.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/cell_triangles.h"
#include "queries/distance/material_distance.h"
#include "queries/distance/point_distance.h"

namespace {

/// A star-shaped loop of 7 to 12 vertices around a random centre of the unit square.
std::vector<glm::dvec2> star(models::Random& rng) {
  const glm::dvec2 c(rng.uniform(0.25, 0.75), rng.uniform(0.25, 0.75));
  const int n = 7 + int(rng.uniform(0, 6));
  std::vector<glm::dvec2> loop;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * (k + rng.uniform(0.0, 0.5)) / n, r = rng.uniform(0.1, 0.45);
    loop.push_back(c + r * glm::dvec2(std::cos(a), std::sin(a)));
  }
  return loop;
}

/// One grid cell over [0, 1]^2 with random corners near the square {z = 0} moved by `offset`, and
/// a star as its hole (outer = false) or as its outer loop.
struct Cell {
  nurbs::ParamGrid grid{{0.0, 1.0}, {0.0, 1.0}};
  nurbs::TrimPolygons trim;
  glm::dvec3 corners[4];
  glm::dvec3 tri[2][3];
  glm::dvec2 uv[2][3];
  Cell(models::Random& rng, glm::dvec3 offset, double tilt) {
    trim.loops.push_back(star(rng));
    trim.outer.push_back(rng.uniform() < 0.5);
    trim.domain_u = trim.domain_v = {0.0, 1.0};
    for (int k = 0; k < 4; ++k)
      corners[k] = offset + glm::dvec3(k & 1, k >> 1, 0.0) +
                   glm::dvec3(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), tilt * rng.uniform(-1.0, 1.0));
    const queries::CellTriangles t = queries::cell_triangles(corners, 0.0, 1.0, 0.0, 1.0);
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 3; ++k) tri[i][k] = t.p[i][k], uv[i][k] = t.uv[i][k];
  }
};

/// The material samples of triangle i of a cell: barycentric grid of n steps.
std::vector<glm::dvec3> material_samples(const Cell& c, int i, int n, const nurbs::TrimPolygons* trim) {
  std::vector<glm::dvec3> out;
  for (int a = 0; a <= n; ++a)
    for (int b = 0; a + b <= n; ++b) {
      const double wa = double(a) / n, wb = double(b) / n, wc = 1.0 - wa - wb;
      const glm::dvec2 uv = wa * c.uv[i][0] + wb * c.uv[i][1] + wc * c.uv[i][2];
      if (trim && !nurbs::is_material(*trim, uv)) continue;
      out.push_back(wa * c.tri[i][0] + wb * c.tri[i][1] + wc * c.tri[i][2]);
    }
  return out;
}

/// Whether material lies within 1e-6 of (u, v) (a point on a trim edge, or at a loop's corner).
bool material_near(const nurbs::TrimPolygons& trim, glm::dvec2 uv) {
  for (int k = 0; k < 64; ++k) {
    const double a = 2.0 * M_PI * k / 64;
    if (nurbs::is_material(trim, uv + 1e-6 * glm::dvec2(std::cos(a), std::sin(a)))) return true;
  }
  return false;
}

double distance_to_triangle(const glm::dvec3& p, const glm::dvec3 t[3]) {
  glm::dvec3 w;
  return glm::length(queries::closest_on_triangle(p, t[0], t[1], t[2], w) - p);
}

}  // namespace

TEST_CASE("material distance: two trimmed triangles against every material sample pair") {
  // 40 random cell pairs (apart, stacked, crossing; B trimmed or not), their four triangle pairs.
  // The answer is the least over the closure of the material parts, so it is at most the least
  // sample pair and at least that less the samples' spacing (both sides); its points lie on their
  // triangles, material or on a trim edge with material beside.
  models::Random rng(23);
  constexpr int n = 40;
  int pairs = 0, on_edges = 0, none = 0;
  double worst_gap = 0.0;
  for (int k = 0; k < 40; ++k) {
    CAPTURE(k);
    const double tilt = k % 3 == 0 ? 0.6 : 0.1;
    const Cell a(rng, glm::dvec3(0.0), tilt);
    const Cell b(rng,
                 glm::dvec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), k % 4 == 1 ? 0.0 : rng.uniform(0.05, 1.0)),
                 tilt);
    const bool b_trimmed = k % 5 != 4;
    const queries::TrimEdges ea(a.trim, a.grid), eb(b.trim, b.grid);
    std::vector<queries::TrimPiece> pa, pb;
    ea.pieces(0, 0, a.corners, pa);
    if (b_trimmed) eb.pieces(0, 0, b.corners, pb);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const queries::MaterialPair m = queries::material_pair_distance(
            {a.tri[i], a.uv[i], i, &ea, &pa}, {b.tri[j], b.uv[j], j, b_trimmed ? &eb : nullptr, &pb}, 1e300);
        const auto sa = material_samples(a, i, n, &a.trim);
        const auto sb = material_samples(b, j, n, b_trimmed ? &b.trim : nullptr);
        double ref = 1e300;
        for (const auto& x : sa)
          for (const auto& y : sb) ref = std::min(ref, glm::length(x - y));
        if (sa.empty() || sb.empty()) {
          ++none;
          continue;
        }
        ++pairs;
        REQUIRE(m.found);
        const double spacing =
            std::max(glm::length(a.tri[i][1] - a.tri[i][0]), glm::length(a.tri[i][2] - a.tri[i][0])) +
            std::max(glm::length(b.tri[j][1] - b.tri[j][0]), glm::length(b.tri[j][2] - b.tri[j][0]));
        CHECK(m.distance <= ref + 1e-12);
        CHECK(m.distance >= ref - 2.0 * spacing / n);
        worst_gap = std::max(worst_gap, (ref - m.distance) / (spacing / n));
        CHECK(std::abs(glm::length(m.point_a - m.point_b) - m.distance) <= 1e-12);
        CHECK(distance_to_triangle(m.point_a, a.tri[i]) <= 1e-12);
        CHECK(distance_to_triangle(m.point_b, b.tri[j]) <= 1e-12);
        const bool edge_a = !nurbs::is_material(a.trim, m.uv_a);
        const bool edge_b = b_trimmed && !nurbs::is_material(b.trim, m.uv_b);
        if (edge_a) CHECK(material_near(a.trim, m.uv_a));
        if (edge_b) CHECK(material_near(b.trim, m.uv_b));
        on_edges += edge_a || edge_b;
      }
  }
  CHECK(pairs >= 100);
  CHECK(on_edges >= 20);
  MESSAGE(pairs << " triangle pairs (" << none << " without material), " << on_edges
                << " answers on a trim edge; reference - answer at most " << worst_gap << " sample spacings");
}
