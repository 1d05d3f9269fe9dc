#include "nurbs/bezier_eval.h"

#include <algorithm>

#include "nurbs/bezier_extraction.h"

namespace nurbs {
namespace {

/// The distinct knots of a clamped, fully refined knot vector over its domain.
std::vector<double> breaks(const std::vector<double>& knots, int degree, int count) {
  std::vector<double> out;
  for (int i = degree; i <= count; ++i)
    if (out.empty() || knots[size_t(i)] > out.back()) out.push_back(knots[size_t(i)]);
  return out;
}

/// Bernstein values b[0..n] of degree n at s and their derivatives d[0..n] wrt s; N > 0 fixes n
/// at compile time (the loops unrolled, the same operations).
template <int N = 0>
void bernstein(int n, double s, double* b, double* d) {
  if constexpr (N > 0) n = N;
  const double r = 1.0 - s;
  b[0] = 1.0;
  for (int k = 1; k < n; ++k) {  // degree n - 1 first
    double saved = 0.0;
    for (int j = 0; j < k; ++j) {
      const double t = b[j];
      b[j] = saved + r * t;
      saved = s * t;
    }
    b[k] = saved;
  }
  if (n == 0) {
    d[0] = 0.0;
    return;
  }
  d[0] = -n * b[0];  // d/ds B^n_i = n (B^{n-1}_{i-1} - B^{n-1}_i)
  for (int i = 1; i < n; ++i) d[i] = n * (b[i - 1] - b[i]);
  d[n] = n * b[n - 1];
  double saved = 0.0;  // then degree n
  for (int j = 0; j < n; ++j) {
    const double t = b[j];
    b[j] = saved + r * t;
    saved = s * t;
  }
  b[n] = saved;
}

/// The patch holding x among breaks (the one on its right at a break, the last at the end) and
/// x's local parameter in it.
int locate(const std::vector<double>& b, double& x, double& width) {
  x = std::clamp(x, b.front(), b.back());
  int a = int(std::upper_bound(b.begin(), b.end(), x) - b.begin()) - 1;
  a = std::clamp(a, 0, int(b.size()) - 2);
  width = b[size_t(a) + 1] - b[size_t(a)];
  x = (x - b[size_t(a)]) / width;
  return a;
}

}  // namespace

BezierForm::BezierForm(const Surface& s, size_t max_points) {
  if (s.degree_u > kMaxDegree || s.degree_v > kMaxDegree) return;
  const Surface r = refine_surface_to_bezier(s);
  if (size_t(r.count_u) * size_t(r.count_v) > max_points) return;
  p_ = r.degree_u, q_ = r.degree_v;
  bu_ = breaks(r.knots_u, p_, r.count_u);
  bv_ = breaks(r.knots_v, q_, r.count_v);
  const size_t nu = bu_.size() - 1, nv = bv_.size() - 1;
  // Each patch p (q) points on from the last: anything else (a degree 0, an empty span) is left to
  // surface_tangents.
  if (p_ < 1 || q_ < 1 || bu_.size() < 2 || bv_.size() < 2 || nu * size_t(p_) + 1 != size_t(r.count_u) ||
      nv * size_t(q_) + 1 != size_t(r.count_v))
    return;
  net_.reserve(nu * nv * size_t(p_ + 1) * size_t(q_ + 1));
  for (size_t b = 0; b < nv; ++b)
    for (size_t a = 0; a < nu; ++a)
      for (int j = 0; j <= q_; ++j)
        for (int i = 0; i <= p_; ++i) {
          const BezierNet n = BezierNet::in_refined(r, int(a), int(b));
          const double w = n.weight(i, j);
          net_.emplace_back(w * n.point(i, j), w);
        }
}

namespace {

/// S, Su, Sv of one patch's net at local (u, v), Au and Av over the patch's widths; P and Q > 0 fix
/// the degrees p and q at compile time (the same operations in the same order).
template <int P = 0, int Q = 0>
SurfaceTangents contract(const glm::dvec4* net, int p, int q, double u, double v, double wu, double wv) {
  if constexpr (P > 0) p = P;
  if constexpr (Q > 0) q = Q;
  double Bu[BezierForm::kMaxDegree + 1], Du[BezierForm::kMaxDegree + 1];
  double Bv[BezierForm::kMaxDegree + 1], Dv[BezierForm::kMaxDegree + 1];
  bernstein<P>(p, u, Bu, Du);
  bernstein<Q>(q, v, Bv, Dv);
  const size_t stride = size_t(p + 1);
  glm::dvec4 A(0.0), Au(0.0), Av(0.0);
  for (int j = 0; j <= q; ++j) {
    glm::dvec4 row(0.0), row_u(0.0);
    const glm::dvec4* r = net + size_t(j) * stride;
    for (int i = 0; i <= p; ++i) row += Bu[i] * r[i], row_u += Du[i] * r[i];
    A += Bv[j] * row, Au += Bv[j] * row_u, Av += Dv[j] * row;
  }
  Au /= wu, Av /= wv;
  SurfaceTangents t;
  t.s = glm::dvec3(A) / A.w;
  t.su = (glm::dvec3(Au) - Au.w * t.s) / A.w;
  t.sv = (glm::dvec3(Av) - Av.w * t.s) / A.w;
  return t;
}

}  // namespace

SurfaceTangents BezierForm::tangents(double u, double v) const {
  double wu = 1.0, wv = 1.0;
  const int a = locate(bu_, u, wu), b = locate(bv_, v, wv);
  const glm::dvec4* net = net_.data() + (size_t(b) * (bu_.size() - 1) + size_t(a)) * size_t(p_ + 1) * size_t(q_ + 1);
  // The degrees of most faces (planes, cylinders, cones, bicubics), unrolled.
  switch (p_ * 16 + q_) {
    case 1 * 16 + 1: return contract<1, 1>(net, p_, q_, u, v, wu, wv);
    case 1 * 16 + 2: return contract<1, 2>(net, p_, q_, u, v, wu, wv);
    case 2 * 16 + 1: return contract<2, 1>(net, p_, q_, u, v, wu, wv);
    case 2 * 16 + 2: return contract<2, 2>(net, p_, q_, u, v, wu, wv);
    case 1 * 16 + 3: return contract<1, 3>(net, p_, q_, u, v, wu, wv);
    case 3 * 16 + 1: return contract<3, 1>(net, p_, q_, u, v, wu, wv);
    case 2 * 16 + 3: return contract<2, 3>(net, p_, q_, u, v, wu, wv);
    case 3 * 16 + 2: return contract<3, 2>(net, p_, q_, u, v, wu, wv);
    case 3 * 16 + 3: return contract<3, 3>(net, p_, q_, u, v, wu, wv);
    default: return contract(net, p_, q_, u, v, wu, wv);
  }
}

}  // namespace nurbs
