#include "models/random_surfaces.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"

namespace models {
namespace {

/// Knot vector on [a, b]: clamped or not, with random simple interior knots.
std::vector<double> random_knots(Random& rng, int degree, int count, double a, double b, bool clamped) {
  const int size = count + degree + 1;
  std::vector<double> k(static_cast<size_t>(size));
  if (clamped) {
    std::vector<double> inner;
    for (int i = 0; i < count - degree - 1; ++i) inner.push_back(rng.uniform(0.05, 0.95));
    std::sort(inner.begin(), inner.end());
    for (int i = 0; i <= degree; ++i) {
      k[static_cast<size_t>(i)] = a;
      k[static_cast<size_t>(size - 1 - i)] = b;
    }
    for (size_t i = 0; i < inner.size(); ++i) k[static_cast<size_t>(degree + 1) + i] = a + (b - a) * inner[i];
  } else {
    // Increasing knots with random gaps, then scaled so that [U[p], U[count]] = [a, b].
    double t = 0.0;
    for (auto& x : k) {
      x = t;
      t += rng.uniform(0.3, 1.0);
    }
    const double lo = k[static_cast<size_t>(degree)], hi = k[static_cast<size_t>(count)];
    for (auto& x : k) x = a + (b - a) * (x - lo) / (hi - lo);
  }
  return k;
}

}  // namespace

nurbs::Surface random_surface(std::uint64_t seed, int degree_u, int degree_v, bool rational) {
  Random rng(seed * 0x9E3779B97F4A7C15ull + 1);
  nurbs::Surface s;
  s.degree_u = degree_u;
  s.degree_v = degree_v;
  s.count_u = degree_u + 1 + rng.integer(0, 4);
  s.count_v = degree_v + 1 + rng.integer(0, 4);
  const bool clamped = rng.integer(0, 3) != 0;
  const double au = rng.uniform(-2, 2), av = rng.uniform(-2, 2);
  s.knots_u = random_knots(rng, degree_u, s.count_u, au, au + rng.uniform(0.5, 3), clamped);
  s.knots_v = random_knots(rng, degree_v, s.count_v, av, av + rng.uniform(0.5, 3), clamped);
  for (int j = 0; j < s.count_v; ++j) {
    for (int i = 0; i < s.count_u; ++i) {
      const double x = -1 + 2.0 * i / (s.count_u - 1) + rng.uniform(-0.3, 0.3);
      const double y = -1 + 2.0 * j / (s.count_v - 1) + rng.uniform(-0.3, 0.3);
      s.points.emplace_back(x, y, rng.uniform(-1, 1));
      if (rational) s.weights.push_back(rng.uniform(0.2, 5.0));
    }
  }
  return s;
}

namespace {

/// Clamped knots on [0, w] with 1-4 distinct interior knots (one of them maybe 1e-4 w from another),
/// each repeated 1..degree times; returns the knots and sets `count`.
std::vector<double> kinked_knots(Random& rng, int degree, double w, int& count) {
  std::vector<double> inner;
  const int distinct = rng.integer(1, 4);
  for (int i = 0; i < distinct; ++i) inner.push_back(rng.uniform(0.05, 0.95));
  if (rng.integer(0, 2) == 0) inner.push_back(inner.front() + 1e-4);  // a sliver span
  std::sort(inner.begin(), inner.end());
  std::vector<double> k(static_cast<size_t>(degree + 1), 0.0);
  for (double t : inner) {
    const int mult = rng.integer(0, 1) == 0 ? degree : rng.integer(1, degree);
    for (int r = 0; r < mult; ++r) k.push_back(w * t);
  }
  for (int i = 0; i <= degree; ++i) k.push_back(w);
  count = static_cast<int>(k.size()) - degree - 1;
  return k;
}

}  // namespace

nurbs::Surface random_kinked_surface(std::uint64_t seed, int degree_u, int degree_v, double weight_ratio) {
  Random rng(seed * 0xBF58476D1CE4E5B9ull + 3);
  nurbs::Surface s;
  s.degree_u = degree_u;
  s.degree_v = degree_v;
  s.knots_u = kinked_knots(rng, degree_u, rng.uniform(0.5, 3), s.count_u);
  s.knots_v = kinked_knots(rng, degree_v, rng.uniform(0.5, 3), s.count_v);
  // Weights: ratio^t with t a random tilted plane over the net plus 5 % jitter, spanning [0, 1]: the
  // whole ratio across the face, as in CAD data, not between neighbours.
  const double tilt = rng.uniform(0, 1);
  std::vector<double> t;
  for (int j = 0; j < s.count_v; ++j) {
    for (int i = 0; i < s.count_u; ++i) {
      const double x = -1 + 2.0 * i / (s.count_u - 1) + rng.uniform(-0.3, 0.3);
      const double y = -1 + 2.0 * j / (s.count_v - 1) + rng.uniform(-0.3, 0.3);
      s.points.emplace_back(x, y, rng.uniform(-1, 1));
      t.push_back(tilt * i / (s.count_u - 1) + (1 - tilt) * j / (s.count_v - 1) + rng.uniform(0, 0.05));
    }
  }
  if (weight_ratio > 1) {
    const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
    for (double x : t) s.weights.push_back(std::pow(weight_ratio, (x - *lo) / (*hi - *lo)));
  }
  return s;
}

nurbs::TrimmedSurface random_trimmed_surface(std::uint64_t seed) {
  Random rng(seed ^ 0xD1B54A32D192ED03ull);
  nurbs::TrimmedSurface t;
  t.surface = random_surface(seed, rng.integer(1, 4), rng.integer(1, 4), rng.integer(0, 1) == 1);
  t.face_id = static_cast<int>(seed % 1000);
  const auto& ku = t.surface.knots_u;
  const auto& kv = t.surface.knots_v;
  const glm::dvec2 lo(ku[static_cast<size_t>(t.surface.degree_u)], kv[static_cast<size_t>(t.surface.degree_v)]);
  const glm::dvec2 hi(ku[static_cast<size_t>(t.surface.count_u)], kv[static_cast<size_t>(t.surface.count_v)]);
  const glm::dvec2 size = hi - lo, mid = 0.5 * (lo + hi);
  if (rng.integer(0, 3) != 0) {
    // Star-shaped polygon around the centre, radii 0.42-0.48 of the domain, 4-7 corners with angular
    // jitter of 0.2 sector: its inradius is >= 0.42 cos(63 deg) = 0.19 > 0.143, the reach of the holes.
    const int sides = rng.integer(4, 7);
    std::vector<glm::dvec2> corners;
    for (int i = 0; i < sides; ++i) {
      const double ang = 2.0 * std::numbers::pi * (i + rng.uniform(-0.2, 0.2)) / sides + 0.3;
      const double r = rng.uniform(0.42, 0.48);
      corners.push_back(mid + glm::dvec2(r * std::cos(ang) * size.x, r * std::sin(ang) * size.y) * 1.0);
    }
    nurbs::TrimLoop outer;
    for (int i = 0; i < sides; ++i)
      outer.curves.push_back(trim_line(corners[static_cast<size_t>(i)], corners[static_cast<size_t>((i + 1) % sides)]));
    t.loops.push_back(std::move(outer));
  }
  // Holes: circles in distinct cells of a 3x3 grid of spacing 0.08 about the centre, radius <= 0.03
  // (< half the spacing), all relative to the domain size.
  const int holes = rng.integer(0, 3);
  int cells[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  for (int h = 0; h < holes; ++h) {
    std::swap(cells[h], cells[h + rng.integer(0, 8 - h)]);
    const int cx = cells[h] % 3, cy = cells[h] / 3;
    const glm::dvec2 c = mid + glm::dvec2((cx - 1) * 0.08 * size.x, (cy - 1) * 0.08 * size.y);
    const double r = rng.uniform(0.01, 0.03) * std::min(size.x, size.y);
    t.loops.push_back({{rational_circle_2d(c, r, false)}, false});
  }
  return t;
}

}  // namespace models
