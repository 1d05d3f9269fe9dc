#include "nurbs/tessellation/trim_bezier3d.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <unordered_map>

#include "nurbs/curve_eval.h"
#include "nurbs/knot_vector.h"
#include "nurbs/restrict.h"
#include "nurbs/surface_eval.h"

namespace nurbs::tess {
namespace {

using V4 = glm::dvec4;

/// Bernstein basis B^n_0..n(s) into b[0..n] by the triangular recurrence (exact partition of unity).
void bernstein(int n, double s, double* b) {
  b[0] = 1.0;
  for (int k = 1; k <= n; ++k) {
    b[k] = s * b[k - 1];
    for (int j = k - 1; j >= 1; --j) b[j] = (1.0 - s) * b[j] + s * b[j - 1];
    b[0] *= 1.0 - s;
  }
}

std::vector<double> bernstein(int n, double s) {
  std::vector<double> b(static_cast<size_t>(n + 1));
  bernstein(n, s, b.data());
  return b;
}

/// Product of two Bernstein polynomials on one interval: coefficient k of f g (degree m + n) is
/// sum_i C(m,i) C(n,k-i) / C(m+n,k) f_i g_(k-i).
template <class T>
std::vector<T> multiply(const std::vector<double>& f, const std::vector<T>& g) {
  const int m = int(f.size()) - 1, n = int(g.size()) - 1;
  const auto &cm = binomial_row(m), &cn = binomial_row(n), &cmn = binomial_row(m + n);
  std::vector<T> out(size_t(m + n + 1), T(0.0));
  for (int i = 0; i <= m; ++i)
    for (int j = 0; j <= n; ++j)
      out[size_t(i + j)] += (cm[size_t(i)] * cn[size_t(j)] / cmn[size_t(i + j)]) * f[size_t(i)] * g[size_t(j)];
  return out;
}

template <class T>
T casteljau(std::vector<T> p, double s) {
  for (size_t k = 1; k < p.size(); ++k)
    for (size_t j = 0; j + k < p.size(); ++j) p[j] = (1.0 - s) * p[j] + s * p[j + 1];
  return p[0];
}

V4 homogeneous_point(const Surface& s, int i, int j) { return V4(s.point(i, j) * s.weight(i, j), s.weight(i, j)); }

/// S^w of a Bézier patch at (u, v) in the source surface's parameters (no clamping: the patch
/// polynomial, continued slightly past its rectangle where rounding puts a piece).
V4 patch_point_w(const BezierPatch& patch, double u, double v) {
  const Surface& s = patch.surface;
  thread_local std::vector<double> bu, bv;
  bu.resize(size_t(s.degree_u + 1)), bv.resize(size_t(s.degree_v + 1));
  bernstein(s.degree_u, (u - patch.range_u.min) / patch.range_u.width(), bu.data());
  bernstein(s.degree_v, (v - patch.range_v.min) / patch.range_v.width(), bv.data());
  V4 out(0.0);
  for (int j = 0; j <= s.degree_v; ++j) {
    V4 row(0.0);
    for (int i = 0; i <= s.degree_u; ++i) row += bu[size_t(i)] * homogeneous_point(s, i, j);
    out += bv[size_t(j)] * row;
  }
  return out;
}

/// Control point i (0 <= i <= n) of the points q of a Bézier curve of degree n - 1 elevated to degree n
/// (Farin): the ends stay, inner points are (i / n) q_(i-1) + (1 - i / n) q_i.
V4 elevated_point(const std::vector<V4>& q, int i) {
  const int n = int(q.size());
  if (i == 0) return q.front();
  if (i == n) return q.back();
  return (double(i) / n) * q[size_t(i - 1)] + (1.0 - double(i) / n) * q[size_t(i)];
}

HomogeneousCurve bezier_curve(int degree, Interval range, std::vector<V4> points) {
  HomogeneousCurve h;
  h.degree = degree;
  h.knots.assign(size_t(degree + 1), range.min);
  h.knots.insert(h.knots.end(), size_t(degree + 1), range.max);
  h.points = std::move(points);
  return h;
}

double net_size(const Surface& s) {
  glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (const auto& p : s.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return std::max(glm::length(hi - lo), 1e-300);
}

/// Real roots with a sign change of the Bernstein polynomial f on (lo, hi): subdivision while the
/// coefficients change sign more than once (Descartes' rule for the Bernstein basis), then
/// bisection. |coefficient| <= tol counts as zero.
void bernstein_roots(const std::vector<double>& f, double lo, double hi, double tol, int depth,
                     std::vector<double>& out) {
  int changes = 0, last = 0;
  for (double c : f) {
    const int sg = c > tol ? 1 : (c < -tol ? -1 : 0);
    if (sg != 0 && last != 0 && sg != last) ++changes;
    if (sg != 0) last = sg;
  }
  if (changes == 0) return;
  const bool opposite = (f.front() > tol && f.back() < -tol) || (f.front() < -tol && f.back() > tol);
  if ((changes == 1 && opposite) || depth >= 48) {
    if (!opposite) return;
    double a = 0.0, b = 1.0;
    const bool rising = f.front() < 0.0;
    for (int it = 0; it < 64 && b - a > 1e-17; ++it) {
      const double m = 0.5 * (a + b);
      ((casteljau(f, m) < 0.0) == rising ? a : b) = m;
    }
    out.push_back(lo + 0.5 * (a + b) * (hi - lo));
    return;
  }
  // de Casteljau split at 1/2: left = first column, right = diagonal.
  std::vector<double> left(f.size()), right(f), work(f);
  for (size_t k = 0; k < f.size(); ++k) {
    left[k] = work[0];
    right[f.size() - 1 - k] = work[f.size() - 1 - k];
    for (size_t j = 0; j + 1 < f.size() - k; ++j) work[j] = 0.5 * (work[j] + work[j + 1]);
  }
  const double mid = 0.5 * (lo + hi);
  if (std::abs(left.back()) <= tol) out.push_back(mid);
  bernstein_roots(left, lo, mid, tol, depth + 1, out);
  bernstein_roots(right, mid, hi, tol, depth + 1, out);
}

std::vector<double> interior_breaks(const std::vector<double>& knots, int degree, int count) {
  const Interval d = knot_domain(knots, degree, count);
  std::vector<double> out;
  for (double k : knots)
    if (k > d.min && k < d.max && (out.empty() || out.back() != k)) out.push_back(k);
  return out;
}

/// Patch of (u, v): spans found by binary search in the interior break lines (patches are row-major,
/// one per non-empty span pair, extract_bezier_patches).
int find_patch(const std::vector<double>& u_lines, const std::vector<double>& v_lines, glm::dvec2 uv) {
  const auto a = std::upper_bound(u_lines.begin(), u_lines.end(), uv.x) - u_lines.begin();
  const auto b = std::upper_bound(v_lines.begin(), v_lines.end(), uv.y) - v_lines.begin();
  return int(b * (std::ssize(u_lines) + 1) + a);
}

}  // namespace

std::vector<double> knot_line_crossings(const BezierSegment<2>& seg, const std::vector<double>& u_lines,
                                        const std::vector<double>& v_lines) {
  const HomogeneousCurve h = to_homogeneous(seg.curve);
  double wmax = 0.0;
  for (const auto& p : h.points) wmax = std::max(wmax, p.w);
  std::vector<double> roots;
  for (int axis = 0; axis < 2; ++axis) {
    const auto& lines = axis == 0 ? u_lines : v_lines;
    if (lines.empty()) continue;
    const double span = std::max(std::abs(lines.back() - lines.front()), std::abs(lines.front()));
    for (double k : lines) {
      std::vector<double> f;
      for (const auto& p : h.points) f.push_back(p[axis] - k * p.w);
      // Zero threshold: a knot-line excursion of 1e-12 relative changes S by a rounding-sized amount.
      bernstein_roots(f, 0.0, 1.0, 1e-12 * std::max(span, 1.0) * wmax, 0, roots);
    }
  }
  std::sort(roots.begin(), roots.end());
  std::vector<double> out;
  const double a = seg.range.min, w = seg.range.width();
  for (double s : roots) {
    if (s < 1e-12 || s > 1.0 - 1e-12) continue;
    if (!out.empty() && s - (out.back() - a) / w < 1e-12) continue;
    out.push_back(a + s * w);
  }
  return out;
}

HomogeneousCurve lift_by_collocation(const BezierPatch& patch, const Curve2& piece) {
  const int du = patch.surface.degree_u, dv = patch.surface.degree_v, n = piece.degree * (du + dv);
  const HomogeneousCurve c = to_homogeneous(piece);
  Eigen::MatrixXd rhs(n + 1, 4);
  for (int k = 0; k <= n; ++k) {
    const double s = double(k) / n;
    const V4 h = casteljau(c.points, s);
    const V4 q = std::pow(h.w, du + dv) * patch_point_w(patch, h.x / h.w, h.y / h.w);
    for (int d = 0; d < 4; ++d) rhs(k, d) = q[d];
  }
  // Rows of A sum to 1, so translating the samples translates the solution: solving for the
  // centred samples keeps the rounding relative to the curve's extent, not its distance from 0.
  const Eigen::RowVector4d mean = rhs.colwise().mean();
  rhs.rowwise() -= mean;
  // A (Bernstein polynomials of degree n at n + 1 equally spaced parameters) depends on n alone:
  // its SVD solve of the identity once per degree and thread, then one product per piece (the
  // SVD of every piece was a tenth of a B-rep model's tessellation).
  thread_local std::unordered_map<int, Eigen::MatrixXd> inverses;
  auto it = inverses.find(n);
  if (it == inverses.end()) {
    Eigen::MatrixXd A(n + 1, n + 1);
    for (int k = 0; k <= n; ++k) {
      const auto b = bernstein(n, double(k) / n);
      for (int i = 0; i <= n; ++i) A(k, i) = b[size_t(i)];
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
    it = inverses.emplace(n, svd.solve(Eigen::MatrixXd::Identity(n + 1, n + 1))).first;
  }
  Eigen::MatrixXd x = it->second * rhs;
  x.rowwise() += mean;
  std::vector<V4> pts(size_t(n + 1));
  for (int i = 0; i <= n; ++i) pts[size_t(i)] = V4(x(i, 0), x(i, 1), x(i, 2), x(i, 3));
  return bezier_curve(n, {piece.knots.front(), piece.knots.back()}, std::move(pts));
}

HomogeneousCurve lift_by_composition(const BezierPatch& patch, const Curve2& piece) {
  const Surface& s = patch.surface;
  const int du = s.degree_u, dv = s.degree_v, d = piece.degree;
  const HomogeneousCurve c = to_homogeneous(piece);
  // Factor polynomials of the file comment, degree d, and their powers.
  auto factors = [&](int axis, Interval r, int deg) {
    std::vector<double> f0, f1;
    for (const auto& p : c.points) {
      f0.push_back((p[axis] - r.min * p.w) / r.width());
      f1.push_back((r.max * p.w - p[axis]) / r.width());
    }
    std::vector<std::vector<double>> p0{{1.0}}, p1{{1.0}}, basis;
    for (int i = 1; i <= deg; ++i) p0.push_back(multiply(p0.back(), f0)), p1.push_back(multiply(p1.back(), f1));
    for (int i = 0; i <= deg; ++i) {
      auto b = multiply(p0[size_t(i)], p1[size_t(deg - i)]);
      for (double& x : b) x *= binomial(deg, i);
      basis.push_back(std::move(b));
    }
    return basis;  // basis[i] = W^deg B^deg_i(local parameter(c(t))), degree d * deg
  };
  const auto bu = factors(0, patch.range_u, du), bv = factors(1, patch.range_v, dv);
  std::vector<V4> q(size_t(d * (du + dv) + 1), V4(0.0));
  for (int j = 0; j <= dv; ++j) {
    std::vector<V4> row(size_t(d * du + 1), V4(0.0));
    for (int i = 0; i <= du; ++i)
      for (size_t k = 0; k < row.size(); ++k) row[k] += bu[size_t(i)][k] * homogeneous_point(s, i, j);
    const auto prod = multiply(bv[size_t(j)], row);
    for (size_t k = 0; k < q.size(); ++k) q[k] += prod[k];
  }
  return bezier_curve(d * (du + dv), {piece.knots.front(), piece.knots.back()}, std::move(q));
}

HomogeneousCurve elevate_bezier(const HomogeneousCurve& b) {
  const int n = b.degree + 1;
  std::vector<V4> e(size_t(n + 1));
  for (int i = 0; i <= n; ++i) e[size_t(i)] = elevated_point(b.points, i);
  return bezier_curve(n, {b.knots.front(), b.knots.back()}, std::move(e));
}

HomogeneousCurve reduce_degree_lossless(const HomogeneousCurve& bezier, double rel_tol) {
  double scale = 0.0;
  for (const auto& p : bezier.points) scale = std::max(scale, glm::length(p));
  const Interval range{bezier.knots.front(), bezier.knots.back()};
  // P: the current control points (degree n = P.size() - 1); each step's candidate in q.
  std::vector<V4> P = bezier.points, fwd, bwd, q;
  while (P.size() > 2) {
    const int n = int(P.size()) - 1;
    const auto nn = static_cast<size_t>(n);
    fwd.resize(nn), bwd.resize(nn), q.resize(nn);
    // Farin's forward (exact near P_0) and backward (exact near P_n) inverses of degree elevation.
    fwd[0] = P[0];
    for (int i = 1; i < n; ++i)
      fwd[size_t(i)] = (double(n) * P[size_t(i)] - double(i) * fwd[size_t(i - 1)]) / double(n - i);
    bwd[size_t(n - 1)] = P[size_t(n)];
    for (int i = n - 1; i >= 1; --i)
      bwd[size_t(i - 1)] = (double(n) * P[size_t(i)] - double(n - i) * bwd[size_t(i)]) / double(i);
    for (int i = 0; i < n; ++i)  // the paper's lambda blend: forward on the first half, backward on the second
      q[size_t(i)] =
          2 * i < n - 1 ? fwd[size_t(i)] : (2 * i > n - 1 ? bwd[size_t(i)] : 0.5 * (fwd[size_t(i)] + bwd[size_t(i)]));
    // Lossless test: elevated back, the control points (hence the curve, by partition of unity) move
    // by at most rel_tol * max |P|.
    double dev = 0.0;
    for (int i = 0; i <= n; ++i) dev = std::max(dev, glm::length(elevated_point(q, i) - P[size_t(i)]));
    if (!(dev <= rel_tol * scale)) break;
    std::swap(P, q);
  }
  const int degree = int(P.size()) - 1;
  return bezier_curve(degree, range, std::move(P));
}

glm::dvec3 bezier_point3(const HomogeneousCurve& b, double t) {
  // Horner in r = s / (1 - s) (or (1 - s) / s past the middle, from the other end, so r <= 1):
  // sum C(n, i) s^i (1 - s)^(n - i) P_i = (1 - s)^n sum C(n, i) r^i P_i, O(n) where de Casteljau is
  // O(n^2) (the check of every lifted piece, up to degree 30, evaluates it 18 times). Every term is a
  // Bernstein weight times P_i, so the rounding is of the order of de Casteljau's.
  const double s = (t - b.knots.front()) / (b.knots.back() - b.knots.front());
  const int n = b.degree;
  const std::vector<double>& c = binomial_row(n);
  V4 acc;
  if (s <= 0.5) {
    const double r = s / (1.0 - s);
    acc = b.points[size_t(n)];
    for (int i = n - 1; i >= 0; --i) acc = acc * r + c[size_t(i)] * b.points[size_t(i)];
    acc *= std::pow(1.0 - s, n);
  } else {
    const double r = (1.0 - s) / s;
    acc = b.points[0];
    for (int i = 1; i <= n; ++i) acc = acc * r + c[size_t(i)] * b.points[size_t(i)];
    acc *= std::pow(s, n);
  }
  return glm::dvec3(acc) / acc.w;
}

glm::dvec2 piece_uv(const Surface& surface, const Curve2& piece, double t) {
  const Interval du = surface_domain_u(surface), dv = surface_domain_v(surface);
  const glm::dvec2 uv = curve_point(piece, t);
  return {std::clamp(uv.x, du.min, du.max), std::clamp(uv.y, dv.min, dv.max)};
}

namespace {

/// The parameters lift_error checks: both ends and `samples` offsets by 1/pi from the collocation
/// nodes i / d3d (which they never meet).
double check_parameter(const TrimCurve3& piece, int k, int samples) {
  const double s = k == 0 ? 0.0 : (k > samples ? 1.0 : (k - 1 + 1.0 / M_PI) / samples);
  return piece.range.min + s * piece.range.width();
}

/// S(uv(t)) at the check parameters of `piece`: the direct evaluation every lifted form of the
/// piece is measured against.
std::vector<glm::dvec3> direct_samples(const Surface& surface, const TrimCurve3& piece, int samples) {
  std::vector<glm::dvec3> out;
  out.reserve(size_t(samples) + 2);
  for (int k = 0; k <= samples + 1; ++k) {
    const glm::dvec2 uv = piece_uv(surface, piece.uv, check_parameter(piece, k, samples));
    out.push_back(surface_point(surface, uv.x, uv.y));
  }
  return out;
}

double lift_error(const std::vector<glm::dvec3>& direct, const TrimCurve3& piece, int samples) {
  double err = 0.0;
  for (int k = 0; k <= samples + 1; ++k)
    err = std::max(err, glm::length(bezier_point3(piece.xyz, check_parameter(piece, k, samples)) - direct[size_t(k)]));
  return err;
}

}  // namespace

double lift_error(const Surface& surface, const TrimCurve3& piece, int samples) {
  return lift_error(direct_samples(surface, piece, samples), piece, samples);
}

std::vector<TrimCurve3> convert_trim_curve(const Surface& surface, const std::vector<BezierPatch>& patches,
                                           const Curve2& curve, const LiftOptions& opt) {
  const Interval du = surface_domain_u(surface), dv = surface_domain_v(surface);
  const auto u_lines = interior_breaks(surface.knots_u, surface.degree_u, surface.count_u);
  const auto v_lines = interior_breaks(surface.knots_v, surface.degree_v, surface.count_v);
  // The domain edges are cut lines too, so that overshooting parts become separate pieces.
  std::vector<double> u_cuts{du.min}, v_cuts{dv.min};
  u_cuts.insert(u_cuts.end(), u_lines.begin(), u_lines.end());
  v_cuts.insert(v_cuts.end(), v_lines.begin(), v_lines.end());
  u_cuts.push_back(du.max), v_cuts.push_back(dv.max);
  std::vector<TrimCurve3> out;
  for (const BezierSegment<2>& seg : extract_bezier_segments(curve)) {
    std::vector<double> cuts{seg.range.min};
    for (double t : knot_line_crossings(seg, u_cuts, v_cuts)) cuts.push_back(t);
    cuts.push_back(seg.range.max);
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      TrimCurve3 piece;
      piece.range = {cuts[k], cuts[k + 1]};
      piece.uv = cuts.size() == 2 ? seg.curve : restrict_curve(seg.curve, cuts[k], cuts[k + 1]);
      // A piece beyond a domain edge (IGES overshoot) becomes its clamp exactly: x := u_min etc.
      const glm::dvec2 mid = curve_point(piece.uv, 0.5 * (cuts[k] + cuts[k + 1]));
      for (auto& q : piece.uv.points) {
        if (mid.x < du.min || mid.x > du.max) q.x = mid.x < du.min ? du.min : du.max;
        if (mid.y < dv.min || mid.y > dv.max) q.y = mid.y < dv.min ? dv.min : dv.max;
      }
      piece.patch = find_patch(u_lines, v_lines, mid);
      const BezierPatch& patch = patches[size_t(piece.patch)];
      const double tol = opt.rel_tol * net_size(patch.surface);
      piece.lifted_degree = piece.uv.degree * (patch.surface.degree_u + patch.surface.degree_v);
      const bool collocate = opt.method == LiftMethod::Collocation ||
                             (opt.method == LiftMethod::Auto && piece.lifted_degree <= opt.max_degree);
      // The surface along the piece, evaluated once for every lifted form's check.
      const std::vector<glm::dvec3> direct = direct_samples(surface, piece, opt.check_samples);
      if (collocate) {
        piece.xyz = lift_by_collocation(patch, piece.uv);
        piece.error = lift_error(direct, piece, opt.check_samples);
      }
      if (!collocate || (opt.method == LiftMethod::Auto && !(piece.error <= tol))) {
        piece.xyz = lift_by_composition(patch, piece.uv);
        piece.composed = true;
        piece.error = lift_error(direct, piece, opt.check_samples);
      }
      if (opt.reduce) {
        TrimCurve3 reduced = piece;
        reduced.xyz = reduce_degree_lossless(piece.xyz, opt.rel_tol);
        reduced.error = lift_error(direct, reduced, opt.check_samples);
        if (reduced.error <= std::max(2.0 * piece.error, tol)) piece = std::move(reduced);
      }
      out.push_back(std::move(piece));
    }
  }
  return out;
}

TrimLoop domain_loop(const Surface& surface) {
  const Interval du = surface_domain_u(surface), dv = surface_domain_v(surface);
  const glm::dvec2 c[4] = {{du.min, dv.min}, {du.max, dv.min}, {du.max, dv.max}, {du.min, dv.max}};
  TrimLoop loop;
  for (int k = 0; k < 4; ++k) loop.curves.push_back({1, {0.0, 0.0, 1.0, 1.0}, {c[k], c[(k + 1) % 4]}, {}});
  return loop;
}

}  // namespace nurbs::tess
