#include "nurbs/curve_eval.h"

#include <glm/vec4.hpp>

namespace nurbs {

template <int D>
glm::vec<D, double> curve_point(const Curve<D>& curve, double u) {
  // curve_derivatives' order 0 without its tables: the same sums in the same order (A4.1).
  using V = glm::vec<D, double>;
  const int p = curve.degree;
  const int span = find_span(curve.knots, p, static_cast<int>(curve.points.size()), u);
  const Interval dom = curve_domain(curve);
  u = u < dom.min ? dom.min : (u > dom.max ? dom.max : u);
  SmallBuffer<double, 16> n(static_cast<size_t>(p) + 1);
  basis_functions(curve.knots, p, span, u, n.data());
  V a(0.0);
  double wd = 0.0;
  for (int j = 0; j <= p; ++j) {
    const size_t idx = static_cast<size_t>(span - p + j);
    const double weight = curve.rational() ? curve.weights[idx] : 1.0;
    a += (n[static_cast<size_t>(j)] * weight) * curve.points[idx];
    wd += n[static_cast<size_t>(j)] * weight;
  }
  return a / wd;
}

template <int D>
std::vector<glm::vec<D, double>> curve_derivatives(const Curve<D>& curve, double u, int order) {
  using V = glm::vec<D, double>;
  const int p = curve.degree;
  const int count = static_cast<int>(curve.points.size());
  const int span = find_span(curve.knots, p, count, u);
  const Interval dom = curve_domain(curve);
  u = u < dom.min ? dom.min : (u > dom.max ? dom.max : u);
  const size_t w = static_cast<size_t>(p) + 1;
  std::vector<double> ders((static_cast<size_t>(order) + 1) * w);
  basis_function_derivatives(curve.knots, p, span, u, order, ders.data());
  // Homogeneous derivatives A^(k) (coordinates 0..D-1) and w^(k) (A3.2 on P^w).
  std::vector<V> a(static_cast<size_t>(order) + 1, V(0.0));
  std::vector<double> wd(static_cast<size_t>(order) + 1, 0.0);
  for (int k = 0; k <= order; ++k) {
    for (int j = 0; j <= p; ++j) {
      const size_t idx = static_cast<size_t>(span - p + j);
      const double weight = curve.rational() ? curve.weights[idx] : 1.0;
      const double n = ders[static_cast<size_t>(k) * w + static_cast<size_t>(j)];
      a[static_cast<size_t>(k)] += (n * weight) * curve.points[idx];
      wd[static_cast<size_t>(k)] += n * weight;
    }
  }
  std::vector<V> out(static_cast<size_t>(order) + 1);
  for (int k = 0; k <= order; ++k) {
    V v = a[static_cast<size_t>(k)];
    for (int i = 1; i <= k; ++i) v -= (binomial(k, i) * wd[static_cast<size_t>(i)]) * out[static_cast<size_t>(k - i)];
    out[static_cast<size_t>(k)] = v / wd[0];
  }
  return out;
}

template glm::vec<2, double> curve_point(const Curve<2>&, double);
template glm::vec<3, double> curve_point(const Curve<3>&, double);
template std::vector<glm::vec<2, double>> curve_derivatives(const Curve<2>&, double, int);
template std::vector<glm::vec<3, double>> curve_derivatives(const Curve<3>&, double, int);

}  // namespace nurbs
