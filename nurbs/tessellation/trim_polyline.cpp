#include "nurbs/tessellation/trim_polyline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <utility>

#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/douglas_peucker.h"
#include "nurbs/tessellation/loop_repair.h"
#include "nurbs/tessellation/trim_thinning.h"

namespace nurbs::tess {
namespace {

/// de Casteljau split of a homogeneous Bézier curve at local parameter s in (0, 1).
std::pair<HomogeneousCurve, HomogeneousCurve> split_bezier(const HomogeneousCurve& b, double s) {
  const size_t n = b.points.size();
  const double t0 = b.knots.front(), t1 = b.knots.back(), tm = t0 + s * (t1 - t0);
  HomogeneousCurve left{b.degree, {}, std::vector<glm::dvec4>(n)}, right = left;
  std::vector<glm::dvec4> w = b.points;
  for (size_t k = 0; k < n; ++k) {
    left.points[k] = w[0];
    right.points[n - 1 - k] = w[n - 1 - k];
    for (size_t j = 0; j + 1 < n - k; ++j) w[j] = (1.0 - s) * w[j] + s * w[j + 1];
  }
  left.knots.assign(n, t0), left.knots.insert(left.knots.end(), n, tm);
  right.knots.assign(n, tm), right.knots.insert(right.knots.end(), n, t1);
  return {std::move(left), std::move(right)};
}

void subdivide(const Surface& surface, const TrimCurve3& piece, const HomogeneousCurve& bez, double tol, double floor,
               CurveSplit split, int depth, std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& xyz) {
  int far = 0;
  const double e = line_error_bound(bez, &far);
  // `floor` (1e-13 of the coordinates) is where ε_line is rounding noise: eps below it cannot be met.
  if (e <= tol || e <= floor || depth >= 48) {
    const glm::dvec2 p = piece_uv(surface, piece.uv, bez.knots.front());
    uv.push_back(p);
    xyz.push_back(surface_point(surface, p.x, p.y));
    return;
  }
  const double s = split == CurveSplit::Midpoint ? 0.5 : double(far) / bez.degree;
  const auto [l, r] = split_bezier(bez, s);
  subdivide(surface, piece, l, tol, floor, split, depth + 1, uv, xyz);
  subdivide(surface, piece, r, tol, floor, split, depth + 1, uv, xyz);
}

}  // namespace

double line_error_bound(const HomogeneousCurve& bezier, int* farthest) {
  const int n = bezier.degree;
  std::vector<glm::dvec3> p;
  bool polynomial = true;
  for (const auto& q : bezier.points) {
    // The hull argument needs positive weights. Lifted weights can be <= 0 where the 2D piece's control
    // polygon leaves its patch (negative Bernstein factors), though the weight function is positive;
    // subdivision then makes them positive (control points converge to curve points).
    if (!(q.w > 0.0)) {
      if (farthest) *farthest = std::max(1, n / 2);
      return HUGE_VAL;
    }
    p.emplace_back(glm::dvec3(q) / q.w);
    polynomial = polynomial && q.w == bezier.points.front().w;
  }
  const glm::dvec3 d = p.back() - p.front();
  const double l2 = glm::dot(d, d);
  double best = 0.0;
  if (farthest) *farthest = std::max(1, n / 2);
  if (n == 2 && !polynomial && l2 > 0.0) {  // a rational quadratic: its shoulder point (header comment)
    const glm::dvec3 v = p[1] - p.front();
    const double lam = glm::dot(v, d) / l2;
    if (lam >= 0.0 && lam <= 1.0) {
      const double w = bezier.points[1].w / std::sqrt(bezier.points[0].w * bezier.points[2].w);
      return w / (1.0 + w) * glm::length(v - lam * d);
    }
  }
  for (int i = 1; i < n; ++i) {
    const glm::dvec3 v = p[size_t(i)] - p.front();
    const double lam = l2 > 0.0 ? std::clamp(glm::dot(v, d) / l2, 0.0, 1.0) : 0.0;
    const double e = glm::length(v - lam * d);
    if (e > best) {
      best = e;
      if (farthest) *farthest = i;
    }
  }
  return (polynomial ? 1.0 - std::ldexp(1.0, 1 - n) : 1.0) * best;
}

void approximate_piece(const Surface& surface, const TrimCurve3& piece, double tol, CurveSplit split,
                       std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& xyz) {
  double mag = 0.0;
  for (const auto& q : piece.xyz.points)  // weights <= 0 (see line_error_bound) carry no size information
    if (q.w > 0.0) mag = std::max(mag, glm::length(glm::dvec3(q) / q.w));
  subdivide(surface, piece, piece.xyz, tol, 1e-13 * mag, split, 0, uv, xyz);
}

void add(TrimApproxStats& a, const TrimApproxStats& b) {
  a.faces += b.faces;
  a.curve_pieces += b.curve_pieces;
  a.composed_pieces += b.composed_pieces;
  a.lifted_degree_max = std::max(a.lifted_degree_max, b.lifted_degree_max);
  a.reduced_degree_max = std::max(a.reduced_degree_max, b.reduced_degree_max);
  a.lift_error_max = std::max(a.lift_error_max, b.lift_error_max);
  a.edges_before += b.edges_before;
  a.edges_after += b.edges_after;
  a.crossings_fixed += b.crossings_fixed;
  a.crossing_refined_faces += b.crossing_refined_faces;
  a.thinned_points += b.thinned_points;
  a.rectangle_faces += b.rectangle_faces;
  a.seconds_conversion += b.seconds_conversion;
  a.seconds_approximation += b.seconds_approximation;
}

size_t simplify_loop(LoopPolyline& loop, double tol, double tol_uv) {
  const size_t m = loop.uv.size();
  if (m < 4 || !(tol > 0.0)) return 0;
  size_t f = 0;
  double fd = 0.0;
  for (size_t k = 1; k < m; ++k) {
    const double d = glm::length(loop.xyz[k] - loop.xyz[0]);
    if (d > fd) fd = d, f = k;
  }
  if (f == 0) f = m / 2;
  std::vector<bool> keep(m, false);
  keep[0] = keep[f] = true;
  const bool edges = loop.edge.size() == m;
  if (edges)
    for (size_t k = 0; k < m; ++k) keep[k] = keep[k] || loop.edge[k] != loop.edge[(k + m - 1) % m];
  douglas_peucker(keep, true, [&](size_t k, size_t a, size_t b) {
    const double d3 = segment_distance(loop.xyz[k], loop.xyz[a], loop.xyz[b]) / tol;
    const double duv = segment_distance(loop.uv[k], loop.uv[a], loop.uv[b]);
    return std::max(d3, tol_uv > 0.0 ? duv / tol_uv : (duv > 0.0 ? HUGE_VAL : 0.0));
  });
  if (std::count(keep.begin(), keep.end(), true) < 3) return 0;  // would collapse the loop's area
  LoopPolyline out;
  out.outer = loop.outer;
  for (size_t k = 0; k < m; ++k)
    if (keep[k]) {
      out.uv.push_back(loop.uv[k]), out.xyz.push_back(loop.xyz[k]);
      if (edges) out.edge.push_back(loop.edge[k]);
    }
  const size_t removed = m - out.uv.size();
  loop = std::move(out);
  return removed;
}

std::vector<TrimLoop> loops_to_approximate(const TrimmedSurface& face) {
  std::vector<TrimLoop> loops = face.loops;
  if (std::none_of(loops.begin(), loops.end(), [](const TrimLoop& l) { return l.outer; }))
    loops.push_back(domain_loop(face.surface));
  return loops;
}

namespace {

/// §4 + §5 without the crossing correction: the loops within opt.eps, simplified; st gets the figures.
std::vector<LoopPolyline> approximate_loops_at(const TrimmedSurface& face, const TrimApproxOptions& opt,
                                               TrimApproxStats& st) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const Surface& s = face.surface;
  const auto patches = extract_bezier_patches(s);
  const std::vector<TrimLoop> loops = loops_to_approximate(face);
  LiftOptions lift;
  lift.max_degree = opt.max_degree;
  lift.method = opt.lift;
  std::vector<std::vector<TrimCurve3>> pieces(loops.size());
  std::vector<std::vector<int>> piece_edge(loops.size());  // Curve::edge of each piece's trim curve
  const auto given = [&](size_t l) { return opt.outer_polyline && loops[l].outer; };
  const double thinning = opt.thinning * (1.0 - opt.gamma) * opt.eps;  // in space (trim_thinning.h)
  double tol_thin = -1.0;  // in (u, v); found when a curve needs it
  for (size_t l = 0; l < loops.size(); ++l) {
    if (given(l)) continue;
    for (const Curve2& file_curve : loops[l].curves) {
      const bool thin = thinning > 0.0 && file_curve.degree == 1 && file_curve.points.size() > 2;
      if (thin && tol_thin < 0.0) {
        const double lip = uv_lipschitz(patches);
        tol_thin = lip > 0.0 && std::isfinite(lip) ? thinning / lip : 0.0;
      }
      const Curve2 c = thin ? thin_polyline(file_curve, tol_thin, &st.thinned_points) : file_curve;
      for (TrimCurve3& p : convert_trim_curve(s, patches, c, lift)) {
        st.lifted_degree_max = std::max(st.lifted_degree_max, p.lifted_degree);
        st.reduced_degree_max = std::max(st.reduced_degree_max, p.xyz.degree);
        st.lift_error_max = std::max(st.lift_error_max, p.error);
        st.composed_pieces += p.composed ? 1 : 0;
        pieces[l].push_back(std::move(p));
        piece_edge[l].push_back(c.edge);
      }
    }
    st.curve_pieces += pieces[l].size();
  }
  const auto t1 = clock::now();
  std::vector<LoopPolyline> out;
  for (size_t l = 0; l < loops.size(); ++l) {
    if (given(l)) {
      out.push_back(*opt.outer_polyline);
      st.edges_before += out.back().uv.size();
      st.rectangle_faces = 1;
      continue;
    }
    LoopPolyline pl;
    pl.outer = loops[l].outer;
    std::vector<glm::dvec2> uv;
    std::vector<glm::dvec3> xyz;
    std::vector<int> edge;  // per vertex: its piece's edge (the segment after it lies on that piece)
    for (size_t k = 0; k < pieces[l].size(); ++k) {
      approximate_piece(s, pieces[l][k], opt.gamma * opt.eps, opt.split, uv, xyz);
      edge.resize(uv.size(), piece_edge[l][k]);
    }
    for (size_t k = 0; k < uv.size(); ++k) {  // drop exact repeats (joints of pieces and curves)
      if (!pl.uv.empty() && uv[k] == pl.uv.back()) {
        if (opt.edges) pl.edge.back() = edge[k];  // the segment after it is the later piece's
        continue;
      }
      pl.uv.push_back(uv[k]), pl.xyz.push_back(xyz[k]);
      if (opt.edges) pl.edge.push_back(edge[k]);
    }
    while (pl.uv.size() > 1 && pl.uv.back() == pl.uv.front()) {
      pl.uv.pop_back(), pl.xyz.pop_back();
      if (opt.edges) pl.edge.pop_back();
    }
    st.edges_before += pl.uv.size();
    out.push_back(std::move(pl));
  }
  const double simplify_tol = (1.0 - opt.gamma) * opt.eps - (tol_thin > 0.0 ? thinning : 0.0);
  if (opt.simplify && simplify_tol > 0.0) {
    // uv safeguard: the 3D tolerance over the largest 3D / uv stretch seen on the loops' edges.
    double stretch = 0.0;
    for (size_t l = 0; l < out.size(); ++l) {
      if (given(l)) continue;
      const LoopPolyline& pl = out[l];
      for (size_t k = 0; k < pl.uv.size(); ++k) {
        const size_t k1 = (k + 1) % pl.uv.size();
        const double duv = glm::length(pl.uv[k1] - pl.uv[k]);
        if (duv > 0.0) stretch = std::max(stretch, glm::length(pl.xyz[k1] - pl.xyz[k]) / duv);
      }
    }
    const double tol_uv = stretch > 0.0 ? simplify_tol / stretch : 0.0;
    for (size_t l = 0; l < out.size(); ++l)
      if (!given(l)) simplify_loop(out[l], simplify_tol, tol_uv);
  }
  const auto t2 = clock::now();
  st.seconds_conversion += std::chrono::duration<double>(t1 - t0).count();
  st.seconds_approximation += std::chrono::duration<double>(t2 - t1).count();
  return out;
}

}  // namespace

std::vector<LoopPolyline> approximate_trim_loops(const TrimmedSurface& face, const TrimApproxOptions& opt,
                                                 TrimApproxStats* stats) {
  if (!(opt.eps > 0.0) || !(opt.gamma > 0.0 && opt.gamma <= 1.0) || !(opt.thinning >= 0.0 && opt.thinning < 1.0))
    throw std::invalid_argument("approximate_trim_loops: eps must be > 0, gamma in (0, 1] and thinning in [0, 1)");
  TrimApproxStats st;
  std::vector<LoopPolyline> out = approximate_loops_at(face, opt, st);
  if (opt.repair) {
    // Beyond the paper: polylines may cross where their curves do not, when two loops (or two parts
    // of one loop) run closer than the chord error, as the two circles of a ring face narrower than
    // eps do. The §5 correction would cut such loops at crossings that lie off both curves, with
    // vertices that belong to neither edge (and a watertight neighbour would take them). The loops
    // are approximated again at eps / 4 while that removes crossings; those that stay are the
    // file's (modelling errors), corrected as the paper does.
    const auto t0 = std::chrono::steady_clock::now();
    size_t crossings = count_crossings(out);
    TrimApproxOptions finer = opt;
    for (int k = 0; k < kCrossingRefinements && crossings > 0; ++k) {
      finer.eps *= 0.25;
      TrimApproxStats finer_st;
      std::vector<LoopPolyline> again = approximate_loops_at(face, finer, finer_st);
      const size_t n = count_crossings(again);
      if (n >= crossings) break;
      st.edges_before = finer_st.edges_before, st.thinned_points = finer_st.thinned_points;
      out = std::move(again), crossings = n, st.crossing_refined_faces = 1;
    }
    st.crossings_fixed = repair_crossings(out, face.surface, opt.eps);
    st.seconds_approximation += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  for (const auto& pl : out) st.edges_after += pl.uv.size();
  st.faces = 1;
  if (stats) add(*stats, st);
  return out;
}

}  // namespace nurbs::tess
