// The face cull of a clearance query (queries/distance/face_cull.h): against dense material samples of
// random trimmed models under random motions, every face pair with points nearer than the bound U
// is kept; U never comes from a point of a hole.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "models/exact_shapes.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/face_cull.h"

namespace {

/// A model of `n` random trimmed faces, each moved to a random place in [-3, 3]^3.
std::vector<nurbs::TrimmedSurface> random_model(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> at(-3.0, 3.0);
  std::vector<nurbs::TrimmedSurface> out;
  for (int k = 0; k < n; ++k) {
    nurbs::TrimmedSurface f = models::random_trimmed_surface(rng());
    const glm::dvec3 t(at(rng), at(rng), at(rng));
    for (glm::dvec3& p : f.surface.points) p += t;
    out.push_back(std::move(f));
  }
  return out;
}

/// Material points of a face on a dense grid (moved by m).
std::vector<glm::dvec3> dense(const nurbs::TrimmedSurface& f, const glm::dmat4& m, int n) {
  const nurbs::Interval du = nurbs::surface_domain_u(f.surface), dv = nurbs::surface_domain_v(f.surface);
  std::vector<glm::dvec3> out;
  nurbs::TrimPolygons trim;
  if (!f.loops.empty()) trim = nurbs::flatten_trim(f, 1e-7 * std::max(du.width(), dv.width()));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const glm::dvec2 uv(du.min + du.width() * i / n, dv.min + dv.width() * j / n);
      if (!f.loops.empty() && !nurbs::is_material(trim, uv)) continue;
      out.emplace_back(m * glm::dvec4(nurbs::surface_point(f.surface, uv.x, uv.y), 1.0));
    }
  return out;
}

}  // namespace

TEST_CASE("face cull: every face pair with material points nearer than U is kept (random trimmed models)") {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  size_t culled = 0, pairs = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const auto a = random_model(rng, 6), b = random_model(rng, 6);
    const glm::dvec3 axis = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + glm::dvec3(0.0, 0.0, 1e-3));
    const glm::dmat4 m = glm::rotate(glm::translate(glm::dmat4(1.0), 6.0 * glm::dvec3(unit(rng), unit(rng), unit(rng))),
                                     3.0 * unit(rng), axis);
    const glm::dmat4 motions[] = {m};
    const queries::FaceCull cull = queries::cull_faces(a, b, motions, 0.0);
    REQUIRE(cull.keep_a.size() == a.size());
    REQUIRE(cull.keep_b.size() == b.size());
    std::vector<std::vector<glm::dvec3>> sa, sb;
    for (const auto& f : a) sa.push_back(dense(f, glm::dmat4(1.0), 24));
    for (const auto& f : b) sb.push_back(dense(f, m, 24));
    double nearest = 1e300;
    for (size_t f = 0; f < a.size(); ++f)
      for (size_t g = 0; g < b.size(); ++g) {
        double d = 1e300;
        for (const auto& p : sa[f])
          for (const auto& q : sb[g]) d = std::min(d, glm::distance(p, q));
        nearest = std::min(nearest, d);
        CAPTURE(trial);
        CAPTURE(f);
        CAPTURE(g);
        CAPTURE(d);
        if (d <= cull.upper) CHECK((cull.keep_a[f] && cull.keep_b[g]));
        culled += !(cull.keep_a[f] && cull.keep_b[g]), ++pairs;
      }
    // U is the distance of two material samples (the 5 x 5 grid's), the dense grid's nearest pair
    // at most a few of its spacings nearer.
    CHECK(cull.upper >= 0.0);
    CHECK(std::isfinite(cull.upper));
    CHECK(nearest <= cull.upper + 1.0);
  }
  MESSAGE(culled << " of " << pairs << " face pairs culled");
  CHECK(culled > 0);  // the check above had pairs to judge
}

TEST_CASE("face cull: U never comes from a point of a hole (a sphere over a holed plane)") {
  // A square with a hole of radius 0.3 (in (u, v)) under a sphere of radius 0.2 whose centre is 0.25
  // above the hole's: samples in the hole would be 0.05 away; the clearance is the rim's.
  const nurbs::TrimmedSurface square = models::cubic_square_with_hole(0.3);
  nurbs::TrimmedSurface ball;
  ball.surface = models::rational_sphere(0.2);
  const glm::dvec3 centre(1.0, 1.0, 0.25);
  double truth = 1e300;
  for (int k = 0; k < 20000; ++k) {
    const double t = 2.0 * M_PI * k / 20000;
    const glm::dvec3 p = nurbs::surface_point(square.surface, 1.0 + 0.3 * std::cos(t), 1.0 + 0.3 * std::sin(t));
    truth = std::min(truth, glm::length(p - centre) - 0.2);
  }
  for (int n : {5, 9, 16}) {
    const glm::dmat4 motions[] = {glm::translate(glm::dmat4(1.0), centre)};
    const queries::FaceCull cull = queries::cull_faces({square}, {ball}, motions, 0.0, n);
    CAPTURE(n);
    CHECK(cull.upper >= truth - 1e-9);
    CHECK(cull.kept_a() == 1);
    CHECK(cull.kept_b() == 1);
  }
}

TEST_CASE("face cull: with several motions a face is kept when some motion keeps it") {
  // Two unit squares side by side (x in [0, 1] and [3, 4]) and a small square B above one, then
  // above the other: each motion alone keeps one face of A, both together keep both.
  nurbs::TrimmedSurface left, right, small;
  left.surface = models::bilinear_square(1.0);
  right.surface = models::bilinear_square(1.0);
  for (auto& p : right.surface.points) p.x += 3.0;
  small.surface = models::bilinear_square(0.2);
  const glm::dmat4 over_left = glm::translate(glm::dmat4(1.0), {0.4, 0.4, 0.5});
  const glm::dmat4 over_right = glm::translate(glm::dmat4(1.0), {3.4, 0.4, 0.5});
  const glm::dmat4 one[] = {over_left}, both[] = {over_left, over_right};
  const queries::FaceCull c1 = queries::cull_faces({left, right}, {small}, one, 0.0);
  CHECK(c1.keep_a == std::vector<char>{1, 0});
  CHECK(c1.upper == doctest::Approx(0.5));
  const queries::FaceCull c2 = queries::cull_faces({left, right}, {small}, both, 0.0);
  CHECK(c2.keep_a == std::vector<char>{1, 1});
  CHECK(c2.keep_b == std::vector<char>{1});
}
