// §5 "Trimming Loops" of Balázs, Guthe, Klein 2004: ε_line, subdivision, simplification and the
// crossing correction (trim_polyline.h, loop_repair.h), checked against dense samples of S(c(t)).
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <random>
#include <string>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/loop_repair.h"
#include "nurbs/tessellation/trim_polyline.h"
#include "nurbs/tessellation/trim_thinning.h"
#include "shared_models.h"

using namespace nurbs;
using namespace nurbs::tess;

namespace {

double seg_dist(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 d = b - a;
  const double l2 = glm::dot(d, d);
  const double t = l2 > 0 ? std::clamp(glm::dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
  return glm::length(p - a - t * d);
}

double to_polyline(glm::dvec3 p, const LoopPolyline& l) {
  double d = HUGE_VAL;
  for (size_t k = 0; k < l.xyz.size(); ++k) d = std::min(d, seg_dist(p, l.xyz[k], l.xyz[(k + 1) % l.xyz.size()]));
  return d;
}

/// Dense samples of S(c(t)) along one trim loop (clamped uv) and the largest gap between neighbours.
struct Dense {
  std::vector<glm::dvec3> pts;
  double gap = 0.0;
};
Dense dense_loop(const Surface& s, const TrimLoop& loop, int per_curve) {
  Dense d;
  for (const auto& c : loop.curves) {
    const Interval r = curve_domain(c);
    for (int k = 0; k <= per_curve; ++k) {
      const glm::dvec2 uv = piece_uv(s, c, r.min + r.width() * k / per_curve);
      const glm::dvec3 p = surface_point(s, uv.x, uv.y);
      if (k > 0) d.gap = std::max(d.gap, glm::length(p - d.pts.back()));
      d.pts.push_back(p);
    }
  }
  return d;
}

/// Two-sided Hausdorff distance (sampled) between each loop's curves and its polyline: returns the
/// excess over eps, allowing half a sampling gap in the polyline -> curve direction.
double hausdorff_excess(const TrimmedSurface& face, const std::vector<LoopPolyline>& out, double eps, int per_curve) {
  const std::vector<TrimLoop> loops = loops_to_approximate(face);
  REQUIRE(loops.size() == out.size());
  double excess = -HUGE_VAL;
  for (size_t l = 0; l < loops.size(); ++l) {
    const Dense d = dense_loop(face.surface, loops[l], per_curve);
    for (const auto& p : d.pts) excess = std::max(excess, to_polyline(p, out[l]) - eps);
    const auto& x = out[l].xyz;
    for (size_t k = 0; k < x.size(); ++k)
      for (double a : {0.0, 0.25, 0.5, 0.75}) {
        const glm::dvec3 q = x[k] + a * (x[(k + 1) % x.size()] - x[k]);
        double m = HUGE_VAL;
        for (const auto& p : d.pts) m = std::min(m, glm::length(p - q));
        excess = std::max(excess, m - eps - 0.5 * d.gap);
      }
  }
  return excess;
}

double net_size(const Surface& s) {
  glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (const auto& p : s.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

/// A planar degree-3 surface S(u, v) = (100 u, 100 v, 0) with 10 x 10 spans (control points at the
/// Greville abscissae: linear precision).
Surface flat_bicubic() {
  Surface s;
  s.degree_u = s.degree_v = 3;
  s.count_u = s.count_v = 13;
  s.knots_u = s.knots_v = models::clamped_uniform_knots(3, 13);
  for (int j = 0; j < 13; ++j)
    for (int i = 0; i < 13; ++i) {
      auto g = [&](int k) { return 100.0 * (s.knots_u[k + 1] + s.knots_u[k + 2] + s.knots_u[k + 3]) / 3.0; };
      s.points.push_back({g(i), g(j), 0.0});
    }
  return s;
}

TrimLoop polygon(const std::vector<glm::dvec2>& p, bool outer) {
  TrimLoop l{{}, outer};
  for (size_t k = 0; k < p.size(); ++k) l.curves.push_back(models::trim_line(p[k], p[(k + 1) % p.size()]));
  return l;
}

}  // namespace

TEST_CASE("trim: ε_line bounds the two-sided distance of random Bézier curves to their chords") {
  std::mt19937_64 rng(42);
  auto rnd = [&] { return double(rng() >> 11) * 0x1p-53; };
  int rational_cases = 0;
  for (int c = 0; c < 400; ++c) {
    const int n = 1 + int(rng() % 9);
    const bool rational = c % 2 == 1;
    HomogeneousCurve b{n, {}, {}};
    b.knots.assign(size_t(n + 1), 0.0), b.knots.insert(b.knots.end(), size_t(n + 1), 1.0);
    for (int i = 0; i <= n; ++i) {
      const double w = rational ? 0.2 + 4.8 * rnd() : 1.0;
      b.points.push_back({w * (2 * rnd() - 1), w * (2 * rnd() - 1), w * (2 * rnd() - 1), w});
    }
    rational_cases += rational;
    const double bound = line_error_bound(b);
    std::vector<glm::dvec3> pts;
    double gap = 0.0;
    for (int k = 0; k <= 4000; ++k) {
      pts.push_back(bezier_point3(b, k / 4000.0));
      if (k) gap = std::max(gap, glm::length(pts[size_t(k)] - pts[size_t(k - 1)]));
    }
    const glm::dvec3 a = pts.front(), e = pts.back();
    double to_chord = 0.0, from_chord = 0.0;
    for (const auto& p : pts) to_chord = std::max(to_chord, seg_dist(p, a, e));
    for (int k = 0; k <= 200; ++k) {
      const glm::dvec3 q = a + (k / 200.0) * (e - a);
      double m = HUGE_VAL;
      for (const auto& p : pts) m = std::min(m, glm::length(p - q));
      from_chord = std::max(from_chord, m);
    }
    CHECK(to_chord <= bound + 1e-12);                // 1e-12: rounding of coordinates of size <= 5
    CHECK(from_chord <= bound + 0.5 * gap + 1e-12);  // half a sampling gap: nearest dense sample
  }
  CHECK(rational_cases == 200);
  // Rational quadratics with every weight pattern (the shoulder-point value, beyond the paper): a
  // quarter circle of radius 1 reaches exactly 1 - cos 45 deg from its chord, and the random ones
  // above include 22 rational quadratics checked both ways against dense samples.
  const double c45 = std::sqrt(0.5);
  HomogeneousCurve arc{2, {0, 0, 0, 1, 1, 1}, {{1, 0, 0, 1}, {c45, c45, 0, c45}, {0, 1, 0, 1}}};
  CHECK(line_error_bound(arc) == doctest::Approx(1.0 - c45).epsilon(1e-12));
  HomogeneousCurve scaled = arc;  // the same arc reparametrised projectively: point i times 3 / sqrt(6)^i
  for (int i = 0; i < 3; ++i) scaled.points[size_t(i)] *= 3.0 * std::pow(1.0 / std::sqrt(6.0), i);
  CHECK(line_error_bound(scaled) == doctest::Approx(1.0 - c45).epsilon(1e-12));
  // Tight for a symmetric polynomial quadratic: the curve reaches half of P1's distance at t = 1/2.
  HomogeneousCurve q{2, {0, 0, 0, 1, 1, 1}, {{0, 0, 0, 1}, {1, 2, 0, 1}, {2, 0, 0, 1}}};
  CHECK(line_error_bound(q) == doctest::Approx(1.0).epsilon(1e-15));  // exact value 2 * (1 - 2^-1)
}

TEST_CASE("trim: random faces, midpoint and arbitrary split, with and without simplification, meet eps") {
  size_t edges[2][2] = {{0, 0}, {0, 0}};
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    const TrimmedSurface face = models::random_trimmed_surface(seed);
    const double eps = 2e-3 * net_size(face.surface);  // a typical rendering tolerance, relative to size
    for (int split = 0; split < 2; ++split)
      for (int simplify = 0; simplify < 2; ++simplify) {
        TrimApproxOptions opt;
        opt.eps = eps;
        opt.split = split ? CurveSplit::Arbitrary : CurveSplit::Midpoint;
        opt.simplify = simplify;
        TrimApproxStats st;
        const auto out = approximate_trim_loops(face, opt, &st);
        CHECK(st.crossings_fixed == 0);  // generated loops never cross
        edges[split][simplify] += st.edges_after;
        // 1e-9 eps: rounding of the bound's arithmetic; the sampling allowance is inside.
        CHECK(hausdorff_excess(face, out, eps * (1 + 1e-9), 300) <= 0.0);
        for (const auto& l : out)
          for (size_t k = 0; k < l.uv.size(); ++k) CHECK(l.xyz[k] == surface_point(face.surface, l.uv[k].x, l.uv[k].y));
      }
  }
  MESSAGE("edges: midpoint ", edges[0][0], " -> ", edges[0][1], " simplified; arbitrary ", edges[1][0], " -> ",
          edges[1][1]);
  CHECK(edges[0][1] < edges[0][0]);
  CHECK(edges[1][1] < edges[1][0]);
}

TEST_CASE("trim: the paper's trimmed wavy surface, eps = 0.05 mm, both split rules") {
  const TrimmedSurface face = models::trimmed_wavy_surface_100x105();
  for (CurveSplit split : {CurveSplit::Midpoint, CurveSplit::Arbitrary}) {
    TrimApproxOptions opt;
    opt.eps = 0.05;  // mm, a quarter of the paper's 0.2 mm
    opt.split = split;
    TrimApproxStats st;
    const auto out = approximate_trim_loops(face, opt, &st);
    MESSAGE(std::string(split == CurveSplit::Midpoint ? "midpoint" : "arbitrary"), ": pieces ", st.curve_pieces,
            ", edges ", st.edges_before, " -> ", st.edges_after, ", lifted degree max ", st.lifted_degree_max,
            " reduced to ", st.reduced_degree_max);
    CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 400) <= 0.0);  // rounding, as above
  }
}

TEST_CASE("trim: simplification removes the collinear vertices of the knot-line cuts") {
  TrimmedSurface face;
  face.surface = flat_bicubic();
  face.loops.push_back(polygon({{0.05, 0.05}, {0.95, 0.12}, {0.4, 0.93}}, true));
  TrimApproxOptions opt;
  opt.eps = 0.01;
  TrimApproxStats st;
  const auto out = approximate_trim_loops(face, opt, &st);
  CHECK(st.curve_pieces > 30);        // every edge is cut at ~10 u and v lines
  CHECK(st.reduced_degree_max == 1);  // linear precision: each lifted piece reduces to a line
  CHECK(st.edges_before == st.curve_pieces);
  REQUIRE(out.size() == 1);
  CHECK(out[0].uv.size() == 3);  // the triangle's corners only
  CHECK(st.edges_after == 3);
  CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 100) <= 0.0);  // rounding, as above
}

TEST_CASE("trim: with B-rep edges recorded, the simplification keeps the vertices where the edge changes") {
  // A square whose top side is two collinear curves of different edges (3 and 4): the plain
  // simplification drops their joint (0.5, 0.9); with opt.edges it stays, and every segment carries
  // the edge of the curve it lies on.
  TrimmedSurface face;
  face.surface = flat_bicubic();
  face.loops.push_back(polygon({{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.5, 0.9}, {0.1, 0.9}}, true));
  const std::vector<int> edge_ids{1, 2, 3, 4, 5};
  for (size_t c = 0; c < 5; ++c) face.loops[0].curves[c].edge = edge_ids[c];
  TrimApproxOptions opt;
  opt.eps = 0.01;
  const auto plain = approximate_trim_loops(face, opt);
  REQUIRE(plain.size() == 1);
  CHECK(plain[0].uv.size() == 4);
  CHECK(plain[0].edge.empty());
  opt.edges = true;
  TrimApproxStats st;
  const auto out = approximate_trim_loops(face, opt, &st);
  REQUIRE(out.size() == 1);
  CHECK(st.curve_pieces > 20);  // cut at the knot lines: the simplification has work to do
  REQUIRE(out[0].uv.size() == 5);
  REQUIRE(out[0].edge.size() == 5);
  for (size_t k = 0; k < 5; ++k) {
    // Vertex k starts the segment along curve c: its start point is the vertex, its edge the segment's.
    size_t c = 0;
    while (c < 5 && glm::length(start_point(face.loops[0].curves[c]) - out[0].uv[k]) > 1e-12) ++c;
    REQUIRE(c < 5);
    CHECK(out[0].edge[k] == edge_ids[c]);
  }
  CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 100) <= 0.0);
}

namespace {

/// The curve as a degree-1 polyline of `points` points at equally spaced parameters (each point at
/// its own parameter, ends exact): how B-rep writers often store pcurves.
Curve2 as_polyline(const Curve2& c, int points) {
  const Interval r = curve_domain(c);
  Curve2 out;
  out.degree = 1;
  out.edge = c.edge;
  out.knots.push_back(r.min);
  for (int k = 0; k < points; ++k) {
    const double t = k == points - 1 ? r.max : r.min + r.width() * k / (points - 1);
    out.points.push_back(k == 0 ? start_point(c) : (k == points - 1 ? end_point(c) : curve_point(c, t)));
    out.knots.push_back(t);
  }
  out.knots.push_back(r.max);
  return out;
}

double to_polyline_uv(glm::dvec2 p, const std::vector<glm::dvec2>& line) {
  double d = HUGE_VAL;
  for (size_t k = 0; k + 1 < line.size(); ++k)
    d = std::min(d, seg_dist(glm::dvec3(p, 0.0), glm::dvec3(line[k], 0.0), glm::dvec3(line[k + 1], 0.0)));
  return d;
}

}  // namespace

TEST_CASE("trim: thin_polyline keeps the ends and the kept points' parameters, within tol_uv both ways") {
  // A quarter circle of radius 0.4 sampled at 400 points, then a straight run of 200 points with
  // 1e-9 of noise across it.
  Curve2 c;
  c.degree = 1;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> noise(-1e-9, 1e-9);
  c.knots.push_back(0.0);
  for (int k = 0; k < 400; ++k) {
    const double a = 0.5 * M_PI * k / 399;
    c.points.push_back({0.5 + 0.4 * std::cos(a), 0.1 + 0.4 * std::sin(a)});
    c.knots.push_back(double(k));
  }
  for (int k = 1; k <= 200; ++k) {
    c.points.push_back({0.5 - 0.4 * k / 200.0, 0.5 + noise(rng)});
    c.knots.push_back(double(399 + k));
  }
  c.knots.push_back(c.knots.back());
  c.edge = 7;
  for (double tol : {1e-2, 1e-4, 1e-6}) {
    size_t removed = 0;
    const Curve2 t = thin_polyline(c, tol, &removed);
    CAPTURE(tol);
    CHECK(t.edge == 7);
    CHECK(removed == c.points.size() - t.points.size());
    CHECK(t.points.size() + 199 <= c.points.size());  // the straight run is one segment at any of them
    if (tol >= 1e-2) CHECK(t.points.size() < 20);
    CHECK(t.points.front() == c.points.front());
    CHECK(t.points.back() == c.points.back());
    REQUIRE(t.knots.size() == t.points.size() + 2);
    for (size_t k = 0; k < t.points.size(); ++k) CHECK(curve_point(c, t.knots[k + 1]) == t.points[k]);
    for (const glm::dvec2& p : c.points) CHECK(to_polyline_uv(p, t.points) <= tol);
    for (size_t k = 0; k + 1 < t.points.size(); ++k)
      for (double a : {0.1, 0.3, 0.5, 0.7, 0.9})
        CHECK(to_polyline_uv(t.points[k] + a * (t.points[k + 1] - t.points[k]), c.points) <= tol);
    MESSAGE("tol_uv ", tol, ": ", c.points.size(), " -> ", t.points.size(), " points");
  }
  // Curves of other degrees, and rational ones, are left as they are.
  const Curve2 cubic = models::trim_line({0.1, 0.1}, {0.9, 0.2});
  Curve2 rational = c;
  rational.weights.assign(c.points.size(), 1.0);
  CHECK(thin_polyline(rational, 1e-2).points.size() == c.points.size());
  CHECK(thin_polyline(cubic, 1e-2).points.size() == cubic.points.size());
}

TEST_CASE("trim: faces whose trims are dense polylines meet eps with and without the thinning") {
  // Random trimmed faces (rational and not) with every trim curve written as a 150-point polyline:
  // the loops against the polylines' images, the thinning's share charged to the budget.
  size_t pieces[2] = {0, 0}, thinned = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    TrimmedSurface face = models::random_trimmed_surface(seed);
    for (TrimLoop& l : face.loops)
      for (Curve2& c : l.curves) c = as_polyline(c, 150);
    const double eps = 2e-3 * net_size(face.surface);
    for (int thin = 0; thin < 2; ++thin) {
      TrimApproxOptions opt;
      opt.eps = eps;
      opt.thinning = thin ? 0.25 : 0.0;
      TrimApproxStats st;
      const auto out = approximate_trim_loops(face, opt, &st);
      CAPTURE(seed);
      CAPTURE(thin);
      CHECK(hausdorff_excess(face, out, eps * (1 + 1e-9), 600) <= 0.0);  // rounding, as above
      pieces[thin] += st.curve_pieces;
      if (thin) thinned += st.thinned_points;
      else CHECK(st.thinned_points == 0);
    }
  }
  MESSAGE("pieces lifted: ", pieces[0], " as written, ", pieces[1], " thinned (", thinned, " points dropped)");
  CHECK(thinned > 0);
  CHECK(pieces[1] * 2 < pieces[0]);
}

TEST_CASE("trim: crossing loops get a vertex at each crossing") {
  TrimmedSurface face;
  face.surface = flat_bicubic();
  face.loops.push_back(polygon({{0.1, 0.1}, {0.6, 0.1}, {0.6, 0.6}, {0.1, 0.6}}, true));
  face.loops.push_back(polygon({{0.4, 0.4}, {0.9, 0.4}, {0.9, 0.9}, {0.4, 0.9}}, true));
  TrimApproxOptions opt;
  opt.eps = 0.01;
  opt.repair = false;
  const auto raw = approximate_trim_loops(face, opt);
  CHECK(count_crossings(raw) == 2);
  opt.repair = true;
  TrimApproxStats st;
  const auto out = approximate_trim_loops(face, opt, &st);
  CHECK(st.crossings_fixed == 2);
  CHECK(count_crossings(out) == 0);
  CHECK(out[0].uv.size() == 6);  // 4 corners + 2 crossings
  bool found = false;
  for (size_t k = 0; k < out[0].uv.size(); ++k) {
    found = found || glm::length(out[0].uv[k] - glm::dvec2(0.6, 0.4)) < 1e-15;  // exact crossing, rounding
    CHECK(out[0].xyz[k] == surface_point(face.surface, out[0].uv[k].x, out[0].uv[k].y));
  }
  CHECK(found);
}

TEST_CASE("trim: loops closer than the chord error are approximated finer, not cut at crossings") {
  // A ring face 0.05 wide (circles of radius 20 and 19.95) at eps 0.3: the chords of each circle
  // sag up to eps inside it, so the coarse polylines cross where the circles do not. The loops are
  // approximated again finer; every vertex stays on its own circle.
  TrimmedSurface face;
  face.surface = models::bilinear_square(50.0);
  face.loops.push_back({{models::rational_circle_2d({25, 25}, 20.0, true)}, true});
  Curve2 inner = models::rational_circle_2d({25, 25}, 19.95, false);
  for (glm::dvec2& p : inner.points) {  // turned by 20 degrees: its chords' ends fall between the outer's
    const glm::dvec2 d = p - glm::dvec2(25, 25);
    const double c = std::cos(0.349), s = std::sin(0.349);
    p = glm::dvec2(25, 25) + glm::dvec2(c * d.x - s * d.y, s * d.x + c * d.y);
  }
  face.loops.push_back({{inner}, false});
  TrimApproxOptions opt;
  opt.eps = 0.3;
  opt.repair = false;
  CHECK(count_crossings(approximate_trim_loops(face, opt)) > 0);
  opt.repair = true;
  TrimApproxStats st;
  const auto out = approximate_trim_loops(face, opt, &st);
  CHECK(st.crossing_refined_faces == 1);
  CHECK(st.crossings_fixed == 0);
  CHECK(count_crossings(out) == 0);
  REQUIRE(out.size() == 2);
  for (const double r : {20.0, 19.95}) {
    const LoopPolyline& loop = out[r == 20.0 ? 0 : 1];
    for (const glm::dvec2& uv : loop.uv) CHECK(glm::length(uv - glm::dvec2(25, 25)) == doctest::Approx(r).epsilon(1e-9));
  }
  CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 400) <= 0.0);
}

TEST_CASE("trim: a loop folded over itself is cut at its crossing and the folded lobe dropped") {
  // The outer loop runs down from (0.1, 0.9) to (0.2, 0.1), across A's first side y = 0.2: the lobe
  // below that side turns clockwise against the loop (as a polyline folded near a boundary does).
  TrimmedSurface face;
  face.surface = flat_bicubic();
  face.loops.push_back(polygon({{0.1, 0.2}, {0.9, 0.2}, {0.9, 0.9}, {0.1, 0.9}, {0.2, 0.1}, {0.1, 0.1}}, true));
  TrimApproxOptions opt;
  opt.eps = 0.01;
  TrimApproxStats st;
  const auto out = approximate_trim_loops(face, opt, &st);
  CHECK(st.crossings_fixed == 1);
  REQUIRE(out.size() == 1);
  CHECK(count_crossings(out) == 0);
  double area = 0.0;
  for (size_t k = 0; k < out[0].uv.size(); ++k) {
    const glm::dvec2 a = out[0].uv[k], b = out[0].uv[(k + 1) % out[0].uv.size()];
    area += 0.5 * (a.x * b.y - a.y * b.x);
    CHECK(a.y >= 0.2 - 1e-12);  // nothing of the lobe below y = 0.2
  }
  // The kept part: the quadrilateral (0.1875, 0.2), (0.9, 0.2), (0.9, 0.9), (0.1, 0.9).
  CHECK(area == doctest::Approx(0.5 * 0.7 * ((0.9 - 0.1875) + 0.8)).epsilon(1e-9));
}

TEST_CASE("trim: a round notch reached through a slit whose sides cross is kept as a hole") {
  // The unit square's outline with a notch: from the top side a slit runs down to a circle of radius
  // 0.2 about (0.5, 0.6), round it clockwise and back up. The top side's two halves overlap by
  // 0.02 across the slit (as a file whose edges meet a hair apart gives them): the loop crosses
  // itself there. The circle turns against the loop and is 20 wide in space (the plane is 100 a
  // side): a hole, not a fold.
  const Surface flat = flat_bicubic();
  std::vector<glm::dvec2> uv{{0, 0}, {1, 0}, {1, 1}, {0.49, 0.999}, {0.5, 0.8}};
  for (int k = 1; k < 36; ++k) {
    const double a = kPi / 2 - 2 * kPi * k / 36;  // clockwise from the top
    uv.push_back({0.5 + 0.2 * std::cos(a), 0.6 + 0.2 * std::sin(a)});
  }
  uv.insert(uv.end(), {{0.5, 0.8}, {0.51, 0.999}, {0, 1}});
  LoopPolyline l;
  l.uv = uv;
  for (const glm::dvec2& p : uv) l.xyz.push_back(surface_point(flat, p.x, p.y));
  const auto holes = [](const std::vector<LoopPolyline>& loops) {
    int n = 0;
    for (const LoopPolyline& piece : loops) n += !piece.outer && piece.uv.size() >= 30;
    return n;
  };
  std::vector<LoopPolyline> loops{l};
  CHECK(repair_crossings(loops, flat, 0.1) == 1);
  CHECK(count_crossings(loops) == 0);
  CHECK(holes(loops) == 1);
  // Taken for a fold of the polylines' error (a fold width above 20), the circle is dropped.
  std::vector<LoopPolyline> folded{l};
  repair_crossings(folded, flat, 50.0);
  CHECK(holes(folded) == 0);
}

TEST_CASE("trim: repaired random self-crossing loops are simple and keep their orientation") {
  // Random polygons (most cross themselves many times), counter-clockwise or clockwise overall:
  // after repair_crossings no two edges cross, every piece is cut at its crossings (no vertex twice)
  // and every piece kept turns as its loop did.
  const Surface flat = flat_bicubic();
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> coord(0.05, 0.95);
  int untangled = 0;
  for (int trial = 0; trial < 300; ++trial) {
    LoopPolyline l;
    const int n = 4 + trial % 9;
    for (int k = 0; k < n; ++k) {
      l.uv.push_back({coord(rng), coord(rng)});
      l.xyz.push_back(surface_point(flat, l.uv.back().x, l.uv.back().y));
    }
    double area = 0.0;
    for (size_t k = 0; k < l.uv.size(); ++k) {
      const glm::dvec2 a = l.uv[k], b = l.uv[(k + 1) % l.uv.size()];
      area += a.x * b.y - a.y * b.x;
    }
    if (std::abs(area) < 1e-6) continue;
    l.outer = area > 0.0;
    std::vector<LoopPolyline> loops{l};
    const size_t crossings = repair_crossings(loops, flat, std::numeric_limits<double>::infinity());
    CAPTURE(trial);
    CHECK(count_crossings(loops) == 0);
    for (const LoopPolyline& piece : loops) {
      double a = 0.0;
      for (size_t k = 0; k < piece.uv.size(); ++k) {
        const glm::dvec2 p = piece.uv[k], q = piece.uv[(k + 1) % piece.uv.size()];
        a += p.x * q.y - p.y * q.x;
      }
      CHECK(a * area > 0.0);
      CHECK(piece.xyz.size() == piece.uv.size());
      // Cut at its crossings: no vertex twice in a piece (a crossing point is in two pieces).
      std::vector<glm::dvec2> sorted = piece.uv;
      std::sort(sorted.begin(), sorted.end(),
                [](const glm::dvec2& p, const glm::dvec2& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); });
      CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    }
    untangled += crossings > 0;
  }
  MESSAGE(untangled << " of the random loops crossed themselves");
  CHECK(untangled > 100);
}

TEST_CASE("trim: a face without loops gives its domain rectangle, counter-clockwise") {
  TrimmedSurface face;
  face.surface = models::random_surface(9, 3, 2, true);
  TrimApproxOptions opt;
  opt.eps = 1e-3 * net_size(face.surface);
  const auto out = approximate_trim_loops(face, opt);
  REQUIRE(out.size() == 1);
  CHECK(out[0].outer);
  double area = 0.0;
  for (size_t k = 0; k < out[0].uv.size(); ++k) {
    const glm::dvec2 a = out[0].uv[k], b = out[0].uv[(k + 1) % out[0].uv.size()];
    area += 0.5 * (a.x * b.y - a.y * b.x);
  }
  const Interval du = surface_domain_u(face.surface), dv = surface_domain_v(face.surface);
  CHECK(area == doctest::Approx(du.width() * dv.width()).epsilon(1e-12));  // vertices on the boundary: exact
  CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 300) <= 0.0);    // rounding, as above
}

TEST_CASE("trim: a face with holes only gets the domain rectangle as its outer loop") {
  TrimmedSurface face;
  face.surface = flat_bicubic();
  face.loops.push_back({{models::rational_circle_2d({0.4, 0.6}, 0.2, false)}, false});
  TrimApproxOptions opt;
  opt.eps = 0.01;
  const auto out = approximate_trim_loops(face, opt);
  REQUIRE(out.size() == 2);
  CHECK(!out[0].outer);
  CHECK(out[1].outer);
  CHECK(out[1].uv.size() == 4);  // the plane's boundary lines reduce to degree 1: corners only
  CHECK(hausdorff_excess(face, out, opt.eps * (1 + 1e-9), 400) <= 0.0);  // rounding, as above
}

TEST_CASE("trim: every face of the shared IGES models meets eps" * test::needs_shared_models()) {
  for (const auto& file : test::shared_iges_files()) {
    const Model model = io::read_model(file);
    const auto faces = world_faces(model);
    const double eps = 1e-3 * model_box(model).diagonal();  // 0.1 % of the model: the paper's 0.2 mm on a car
    TrimApproxOptions opt;
    opt.eps = eps;
    TrimApproxStats st;
    double worst = 0.0;
    size_t inconsistent = 0, remaining = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& face : faces) {
      std::vector<LoopPolyline> out;
      REQUIRE_NOTHROW(out = approximate_trim_loops(face, opt, &st));
      // Sampled check, curve -> polyline: 6 points per trim curve (the full two-sided check runs above).
      const std::vector<TrimLoop> loops = loops_to_approximate(face);
      for (size_t l = 0; l < loops.size(); ++l) {
        const Dense d = dense_loop(face.surface, loops[l], 5);
        // The crossing repair may cut a loop thinner than eps into several (a ring 0.05 wide at
        // eps 0.29 on the motor): each curve point is measured to the nearest output loop.
        for (const auto& p : d.pts) {
          double nearest = to_polyline(p, out[l]);
          for (const LoopPolyline& o : out) nearest = std::min(nearest, to_polyline(p, o));
          worst = std::max(worst, nearest / eps);
        }
        for (size_t k = 0; k < out[l].uv.size(); k += 7)  // xyz = S(uv) exactly, on every 7th vertex
          inconsistent += out[l].xyz[k] != surface_point(face.surface, out[l].uv[k].x, out[l].uv[k].y);
      }
      remaining += count_crossings(out);
    }
    CHECK(inconsistent == 0);
    CHECK(remaining == 0);  // the crossing correction leaves none
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE(file.filename().string(), ": ", faces.size(), " faces, pieces ", st.curve_pieces, " (composed ",
            st.composed_pieces, "), lifted degree max ", st.lifted_degree_max, " -> ", st.reduced_degree_max,
            ", lift error ", st.lift_error_max, ", edges ", st.edges_before, " -> ", st.edges_after, ", crossings ",
            st.crossings_fixed, ", conversion ", st.seconds_conversion, " s, approximation ", st.seconds_approximation,
            " s, total with checks ", secs, " s, worst distance / eps ", worst);
    CHECK(worst <= 1.0 + 1e-9);                                      // eps, rounding
    CHECK(st.lift_error_max <= 1e-9 * model_box(model).diagonal());  // exactness bar of §4, relative to size
  }
}
