#pragma once
/// \file bernstein_poly.h
/// Tensor-product Bernstein polynomials over one parameter rectangle: sums, products and partial
/// derivatives in Bernstein form (Farin, "Curves and Surfaces for CAGD", §6 and §15.4). Used to bound
/// the second derivatives of rational patches exactly in polynomial form (filip_bound.cpp): the
/// convex hull of a polynomial's Bernstein coefficients contains its values.
#include <glm/vec3.hpp>
#include <vector>

namespace nurbs {

/// sum_ij c[j (a + 1) + i] B^a_i(s) B^b_j(t), with s, t in [0, 1] over the rectangle.
template <class T>
struct BernsteinPoly {
  int a = 0, b = 0;
  std::vector<T> c;
  [[nodiscard]] const T& at(int i, int j) const { return c[size_t(j) * size_t(a + 1) + size_t(i)]; }
  [[nodiscard]] T& at(int i, int j) { return c[size_t(j) * size_t(a + 1) + size_t(i)]; }
};
using BernsteinScalar = BernsteinPoly<double>;
using BernsteinVector = BernsteinPoly<glm::dvec3>;

/// Partial derivative along the first (u) or second (v) parameter, divided by the rectangle's width
/// `width` in that direction (so derivatives are wrt the original parameter). Degree 0 gives 0 of
/// degree 0.
template <class T>
[[nodiscard]] BernsteinPoly<T> derivative(const BernsteinPoly<T>& f, bool along_u, double width);

/// Product in Bernstein form: degree (f.a + g.a, f.b + g.b).
[[nodiscard]] BernsteinScalar multiply(const BernsteinScalar& f, const BernsteinScalar& g);
[[nodiscard]] BernsteinVector multiply(const BernsteinScalar& f, const BernsteinVector& g);

/// f += k g (same degrees).
template <class T>
void add_scaled(BernsteinPoly<T>& f, double k, const BernsteinPoly<T>& g);

}  // namespace nurbs
