#include "nurbs/surface_eval.h"

#include <algorithm>
#include <limits>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <vector>

namespace nurbs {

Interval surface_domain_u(const Surface& s) { return knot_domain(s.knots_u, s.degree_u, s.count_u); }
Interval surface_domain_v(const Surface& s) { return knot_domain(s.knots_v, s.degree_v, s.count_v); }

namespace {

/// Homogeneous derivatives A[k][l] = d^{k+l} P^w / du^k dv^l for k + l <= order (A3.6).
void homogeneous_derivatives(const Surface& s, double u, double v, int order, glm::dvec4 (&a)[3][3]) {
  const int p = s.degree_u, q = s.degree_v;
  const int su = find_span(s.knots_u, p, s.count_u, u);
  const int sv = find_span(s.knots_v, q, s.count_v, v);
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  u = std::clamp(u, du.min, du.max);
  v = std::clamp(v, dv.min, dv.max);
  const size_t wu = static_cast<size_t>(p) + 1, wv = static_cast<size_t>(q) + 1;
  SmallBuffer<double, 24> nu((static_cast<size_t>(order) + 1) * wu), nv((static_cast<size_t>(order) + 1) * wv);
  if (order == 0) {  // the same values without the derivative tables (A2.2)
    basis_functions(s.knots_u, p, su, u, nu.data());
    basis_functions(s.knots_v, q, sv, v, nv.data());
  } else {
    basis_function_derivatives(s.knots_u, p, su, u, order, nu.data());
    basis_function_derivatives(s.knots_v, q, sv, v, order, nv.data());
  }
  // temp[k][i] = sum_l Nv^(l)_j P^w_{i,j}: contract v first, then u (A3.6 ordering).
  SmallBuffer<glm::dvec4, 8> temp(wu);
  for (int l = 0; l <= order; ++l) {
    for (int i = 0; i <= p; ++i) {
      glm::dvec4 acc(0.0);
      for (int j = 0; j <= q; ++j) {
        const int ci = su - p + i, cj = sv - q + j;
        const double w = s.weight(ci, cj);
        acc += nv[static_cast<size_t>(l) * wv + static_cast<size_t>(j)] * glm::dvec4(w * s.point(ci, cj), w);
      }
      temp[static_cast<size_t>(i)] = acc;
    }
    for (int k = 0; k + l <= order; ++k) {
      glm::dvec4 acc(0.0);
      for (int i = 0; i <= p; ++i)
        acc += nu[static_cast<size_t>(k) * wu + static_cast<size_t>(i)] * temp[static_cast<size_t>(i)];
      a[k][l] = acc;
    }
  }
}

/// A4.4: Euclidean derivatives from homogeneous ones, for k + l <= order.
void rational_derivatives(const glm::dvec4 (&a)[3][3], int order, glm::dvec3 (&skl)[3][3]) {
  for (int k = 0; k <= order; ++k) {
    for (int l = 0; k + l <= order; ++l) {
      glm::dvec3 v(a[k][l]);
      for (int j = 1; j <= l; ++j) v -= binomial(l, j) * a[0][j].w * skl[k][l - j];
      for (int i = 1; i <= k; ++i) {
        v -= binomial(k, i) * a[i][0].w * skl[k - i][l];
        glm::dvec3 v2(0.0);
        for (int j = 1; j <= l; ++j) v2 += binomial(l, j) * a[i][j].w * skl[k - i][l - j];
        v -= binomial(k, i) * v2;
      }
      skl[k][l] = v / a[0][0].w;
    }
  }
}

}  // namespace

glm::dvec3 surface_point(const Surface& s, double u, double v) {
  glm::dvec4 a[3][3];
  homogeneous_derivatives(s, u, v, 0, a);
  return glm::dvec3(a[0][0]) / a[0][0].w;
}

SurfaceDerivatives surface_derivatives(const Surface& s, double u, double v) {
  glm::dvec4 a[3][3];
  glm::dvec3 skl[3][3];
  homogeneous_derivatives(s, u, v, 2, a);
  rational_derivatives(a, 2, skl);
  return {skl[0][0], skl[1][0], skl[0][1], skl[2][0], skl[1][1], skl[0][2]};
}

SurfaceTangents surface_tangents(const Surface& s, double u, double v) {
  glm::dvec4 a[3][3];
  glm::dvec3 skl[3][3];
  homogeneous_derivatives(s, u, v, 1, a);
  rational_derivatives(a, 1, skl);
  return {skl[0][0], skl[1][0], skl[0][1]};
}

glm::dvec3 surface_normal(const Surface& s, double u, double v) {
  return surface_normal(s, surface_derivatives(s, u, v), u, v);
}

glm::dvec3 surface_normal(const Surface& s, const SurfaceDerivatives& d, double u, double v) {
  // Relative threshold: a cross product this small against |Su||Sv| is roundoff, not a direction.
  const double scale = std::max({glm::length(d.su), glm::length(d.sv), 1e-300});
  const double eps = 1e-12 * scale;
  glm::dvec3 n = glm::cross(d.su, d.sv);
  if (glm::length(n) <= eps * scale) {
    // Taylor from inside the domain: Su(u, v0 + dv) ~ dv Suv, with dv > 0 at the start of the
    // domain and dv < 0 at its end, hence the sign.
    const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
    const double sv_side = v < 0.5 * (dv.min + dv.max) ? 1.0 : -1.0;
    const double su_side = u < 0.5 * (du.min + du.max) ? 1.0 : -1.0;
    if (glm::length(d.su) <= eps)
      n = sv_side * glm::cross(d.suv, d.sv);
    else if (glm::length(d.sv) <= eps)
      n = su_side * glm::cross(d.su, d.suv);
  }
  const double len = glm::length(n);
  return len > 0.0 ? n / len : glm::dvec3(0.0);
}

glm::dvec2 speed_bounds(const Surface& s) {
  const double inf = std::numeric_limits<double>::infinity();
  if (s.points.empty() || s.count_u < 1 || s.count_v < 1) return glm::dvec2(inf);
  if (s.rational() && !(*std::min_element(s.weights.begin(), s.weights.end()) > 0.0)) return glm::dvec2(inf);
  // Per knot span (k, l) of the domain, only the control points (i, j) in [k - p, k] x [l - q, l]
  // act there: the differences between them, and for a rational surface their box's diagonal
  // (S lies in their hull) and their weights. Direction d = 0 differentiates along u.
  const auto along = [&](int d) {
    const int p = d == 0 ? s.degree_u : s.degree_v, q = d == 0 ? s.degree_v : s.degree_u;
    const int n = d == 0 ? s.count_u : s.count_v, m = d == 0 ? s.count_v : s.count_u;
    const std::vector<double>& knots = d == 0 ? s.knots_u : s.knots_v;
    const std::vector<double>& across = d == 0 ? s.knots_v : s.knots_u;
    const auto point = [&](int i, int j) { return d == 0 ? s.point(i, j) : s.point(j, i); };
    const auto weight = [&](int i, int j) { return !s.rational() ? 1.0 : d == 0 ? s.weight(i, j) : s.weight(j, i); };
    double bound = 0.0;
    for (int k = p; k < n; ++k) {
      if (!(knots[size_t(k + 1)] > knots[size_t(k)])) continue;
      for (int l = q; l < m; ++l) {
        if (!(across[size_t(l + 1)] > across[size_t(l)])) continue;
        glm::dvec3 lo(inf), hi(-inf);
        double w_min = inf, w_max = 0.0;
        for (int i = k - p; i <= k; ++i)
          for (int j = l - q; j <= l; ++j) {
            lo = glm::min(lo, point(i, j)), hi = glm::max(hi, point(i, j));
            w_min = std::min(w_min, weight(i, j)), w_max = std::max(w_max, weight(i, j));
          }
        for (int i = k - p; i < k; ++i) {
          const double span = knots[size_t(i + p + 1)] - knots[size_t(i + 1)];
          double step = 0.0;
          for (int j = l - q; j <= l; ++j)
            step = std::max(step, s.rational() ? 2.0 * w_max / w_min * glm::length(hi - lo)
                                               : glm::length(point(i + 1, j) - point(i, j)));
          if (step == 0.0) continue;
          if (!(span > 0.0)) return inf;
          bound = std::max(bound, p * step / span);
        }
      }
    }
    return bound;
  };
  return glm::dvec2(along(0), along(1));
}

}  // namespace nurbs
