#include "nurbs/knot_vector.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>

namespace nurbs {

std::vector<std::string> validate_knots(const std::vector<double>& knots, int degree, int count) {
  std::vector<std::string> problems;
  if (degree < 1) problems.push_back(fmt::format("degree {} < 1", degree));
  if (count < degree + 1) problems.push_back(fmt::format("{} control points < degree + 1 = {}", count, degree + 1));
  const auto expected = static_cast<long long>(count) + degree + 1;
  if (static_cast<long long>(knots.size()) != expected) {
    problems.push_back(fmt::format("{} knots, expected count + degree + 1 = {}", knots.size(), expected));
  }
  bool finite = true;
  for (size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) {
      problems.push_back(fmt::format("knot {} is not finite", i));
      finite = false;
    }
  }
  // The remaining checks compare values: meaningless on NaN or a wrongly sized vector.
  if (!finite || !problems.empty()) return problems;
  for (size_t i = 1; i < knots.size(); ++i) {
    if (knots[i] < knots[i - 1]) {
      problems.push_back(fmt::format("knots decrease at index {} ({} < {})", i, knots[i], knots[i - 1]));
    }
  }
  if (!problems.empty()) return problems;
  const double lo = knots[static_cast<size_t>(degree)];
  const double hi = knots[static_cast<size_t>(count)];
  if (!(lo < hi)) problems.push_back(fmt::format("empty domain [U[p], U[n+1]] = [{}, {}]", lo, hi));
  for (size_t i = 0; i < knots.size();) {
    size_t j = i;
    while (j < knots.size() && knots[j] == knots[i]) ++j;
    const int mult = static_cast<int>(j - i);
    if (mult > degree + 1) {
      problems.push_back(fmt::format("knot {} has multiplicity {} > degree + 1 = {}", knots[i], mult, degree + 1));
    } else if (knots[i] > lo && knots[i] < hi && mult > degree) {
      // Inside the domain, multiplicity p+1 would make the curve discontinuous (two curves in one).
      problems.push_back(fmt::format("interior knot {} has multiplicity {} > degree = {}", knots[i], mult, degree));
    }
    i = j;
  }
  return problems;
}

bool is_clamped(const std::vector<double>& knots, int degree) {
  const size_t p = static_cast<size_t>(degree);
  if (knots.size() < 2 * (p + 1)) return false;
  for (size_t i = 1; i <= p; ++i) {
    if (knots[i] != knots[0] || knots[knots.size() - 1 - i] != knots.back()) return false;
  }
  return true;
}

Interval knot_domain(const std::vector<double>& knots, int degree, int count) {
  return {knots[static_cast<size_t>(degree)], knots[static_cast<size_t>(count)]};
}

int knot_multiplicity(const std::vector<double>& knots, double u) {
  return static_cast<int>(std::count(knots.begin(), knots.end(), u));
}

int find_span(const std::vector<double>& knots, int degree, int count, double u) {
  const int n = count - 1;
  const double lo = knots[static_cast<size_t>(degree)];
  const double hi = knots[static_cast<size_t>(n + 1)];
  if (!(u > lo)) u = lo;  // also maps NaN to the domain start rather than reading out of range
  if (u >= hi) {
    // Domain end: the last span with U[i] < U[i+1] (A2.1 returns n, which is empty if U[n] == U[n+1]).
    int i = n;
    while (i > degree && !(knots[static_cast<size_t>(i)] < knots[static_cast<size_t>(i + 1)])) --i;
    return i;
  }
  // upper_bound gives the first knot > u; the span starts one before it.
  const auto first = knots.begin() + degree;
  const auto last = knots.begin() + n + 2;
  const auto it = std::upper_bound(first, last, u);
  return static_cast<int>(it - knots.begin()) - 1;
}

void basis_functions(const std::vector<double>& knots, int degree, int span, double u, double* out) {
  SmallBuffer<double, 16> scratch(2 * (static_cast<size_t>(degree) + 1));
  basis_functions(knots, degree, span, u, out, scratch.data());
}

void basis_functions(const std::vector<double>& knots, int degree, int span, double u, double* out, double* scratch,
                     double* lower) {
  const int p = degree;
  double* left = scratch;
  double* right = scratch + (p + 1);
  out[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    if (j == p && lower) std::copy(out, out + p, lower);  // the degree p - 1 functions
    left[j] = u - knots[static_cast<size_t>(span + 1 - j)];
    right[j] = knots[static_cast<size_t>(span + j)] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = out[r] / (right[r + 1] + left[j - r]);
      out[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    out[j] = saved;
  }
}

void basis_function_derivatives(const std::vector<double>& knots, int degree, int span, double u, int order,
                                double* out) {
  const int p = degree;
  const size_t w = static_cast<size_t>(p) + 1;
  // ndu: upper triangle holds basis functions of each degree, lower triangle the knot differences.
  SmallBuffer<double, 64> ndu(w * w), a(2 * w);  // no allocation up to degree 7
  SmallBuffer<double, 8> left(w), right(w);
  auto NDU = [&](int r, int c) -> double& { return ndu[static_cast<size_t>(r) * w + static_cast<size_t>(c)]; };
  auto A = [&](int r, int c) -> double& { return a[static_cast<size_t>(r) * w + static_cast<size_t>(c)]; };
  NDU(0, 0) = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - knots[static_cast<size_t>(span + 1 - j)];
    right[j] = knots[static_cast<size_t>(span + j)] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      NDU(j, r) = right[r + 1] + left[j - r];
      const double temp = NDU(r, j - 1) / NDU(j, r);
      NDU(r, j) = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    NDU(j, j) = saved;
  }
  std::fill(out, out + (static_cast<size_t>(order) + 1) * w, 0.0);
  for (int j = 0; j <= p; ++j) out[j] = NDU(j, p);
  const int top = std::min(order, p);
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    A(0, 0) = 1.0;
    for (int k = 1; k <= top; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        A(s2, 0) = A(s1, 0) / NDU(pk + 1, rk);
        d = A(s2, 0) * NDU(rk, pk);
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        A(s2, j) = (A(s1, j) - A(s1, j - 1)) / NDU(pk + 1, rk + j);
        d += A(s2, j) * NDU(rk + j, pk);
      }
      if (r <= pk) {
        A(s2, k) = -A(s1, k - 1) / NDU(pk + 1, r);
        d += A(s2, k) * NDU(r, pk);
      }
      out[static_cast<size_t>(k) * w + static_cast<size_t>(r)] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= top; ++k) {
    for (size_t j = 0; j < w; ++j) out[static_cast<size_t>(k) * w + j] *= factor;
    factor *= p - k;
  }
}

std::vector<double> basis_functions(const std::vector<double>& knots, int degree, int span, double u) {
  std::vector<double> out(static_cast<size_t>(degree) + 1);
  basis_functions(knots, degree, span, u, out.data());
  return out;
}

std::vector<double> basis_function_derivatives(const std::vector<double>& knots, int degree, int span, double u,
                                               int order) {
  std::vector<double> out((static_cast<size_t>(order) + 1) * (static_cast<size_t>(degree) + 1));
  basis_function_derivatives(knots, degree, span, u, order, out.data());
  return out;
}

double binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

std::vector<double> knot_breaks(const std::vector<double>& knots, Interval domain) {
  std::vector<double> out;
  for (double k : knots)
    if (k >= domain.min && k <= domain.max && (out.empty() || out.back() != k)) out.push_back(k);
  return out;
}

const std::vector<double>& binomial_row(int n) {
  thread_local std::deque<std::vector<double>> rows;  // growing keeps references to earlier rows valid
  if (rows.size() <= size_t(n)) rows.resize(size_t(n + 1));
  std::vector<double>& c = rows[size_t(n)];
  if (c.empty())
    for (int k = 0; k <= n; ++k) c.push_back(binomial(n, k));
  return c;
}

}  // namespace nurbs
