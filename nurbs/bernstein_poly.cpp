#include "nurbs/bernstein_poly.h"

#include <stdexcept>

#include "nurbs/knot_vector.h"

namespace nurbs {
namespace {

template <class S, class T>
BernsteinPoly<T> product(const BernsteinPoly<S>& f, const BernsteinPoly<T>& g) {
  // h_kl = sum C(a,i) C(c,i') / C(a+c,k) * C(b,j) C(d,j') / C(b+d,l) f_ij g_i'j' over i + i' = k, j + j' = l:
  // the products of scaled coefficients, then one division per output coefficient.
  BernsteinPoly<T> h;
  h.a = f.a + g.a;
  h.b = f.b + g.b;
  h.c.assign(size_t(h.a + 1) * size_t(h.b + 1), T(0.0));
  const auto &fa = binomial_row(f.a), &fb = binomial_row(f.b), &ga = binomial_row(g.a), &gb = binomial_row(g.b);
  std::vector<T> gs(g.c.size());
  for (int jj = 0; jj <= g.b; ++jj)
    for (int ii = 0; ii <= g.a; ++ii)
      gs[size_t(jj * (g.a + 1) + ii)] = (ga[size_t(ii)] * gb[size_t(jj)]) * g.at(ii, jj);
  for (int j = 0; j <= f.b; ++j)
    for (int i = 0; i <= f.a; ++i) {
      const S fij = (fa[size_t(i)] * fb[size_t(j)]) * f.at(i, j);
      for (int jj = 0; jj <= g.b; ++jj) {
        T* out = &h.at(i, j + jj);
        const T* in = &gs[size_t(jj * (g.a + 1))];
        for (int ii = 0; ii <= g.a; ++ii) out[ii] += fij * in[ii];
      }
    }
  const auto &ha = binomial_row(h.a), &hb = binomial_row(h.b);
  for (int l = 0; l <= h.b; ++l)
    for (int k = 0; k <= h.a; ++k) h.at(k, l) /= ha[size_t(k)] * hb[size_t(l)];
  return h;
}

}  // namespace

template <class T>
BernsteinPoly<T> derivative(const BernsteinPoly<T>& f, bool along_u, double width) {
  BernsteinPoly<T> d;
  const int deg = along_u ? f.a : f.b;
  if (deg == 0) {
    d.c.assign(1, T(0.0));
    return d;
  }
  d.a = along_u ? f.a - 1 : f.a;
  d.b = along_u ? f.b : f.b - 1;
  d.c.resize(size_t(d.a + 1) * size_t(d.b + 1));
  const double k = deg / width;
  for (int j = 0; j <= d.b; ++j)
    for (int i = 0; i <= d.a; ++i)
      d.at(i, j) = k * (along_u ? f.at(i + 1, j) - f.at(i, j) : f.at(i, j + 1) - f.at(i, j));
  return d;
}

BernsteinScalar multiply(const BernsteinScalar& f, const BernsteinScalar& g) { return product(f, g); }
BernsteinVector multiply(const BernsteinScalar& f, const BernsteinVector& g) { return product(f, g); }

template <class T>
void add_scaled(BernsteinPoly<T>& f, double k, const BernsteinPoly<T>& g) {
  if (f.a != g.a || f.b != g.b) throw std::logic_error("add_scaled: Bernstein degrees differ");
  for (size_t i = 0; i < f.c.size(); ++i) f.c[i] += k * g.c[i];
}

template BernsteinPoly<double> derivative(const BernsteinPoly<double>&, bool, double);
template BernsteinPoly<glm::dvec3> derivative(const BernsteinPoly<glm::dvec3>&, bool, double);
template void add_scaled(BernsteinPoly<double>&, double, const BernsteinPoly<double>&);
template void add_scaled(BernsteinPoly<glm::dvec3>&, double, const BernsteinPoly<glm::dvec3>&);

}  // namespace nurbs
