#pragma once
/// \file knot_vector.h
/// Knot vectors: validation, clamped detection, span search and B-spline basis functions
/// (The NURBS Book, Piegl & Tiller, 2nd ed., §2.2-2.5, algorithms A2.1-A2.3).
///
/// Conventions used everywhere in nurbs/: `count` control points, `degree` p, knot vector U of size
/// count + p + 1 (m + 1 in the book with m = n + p + 1, n = count - 1). The valid parameter domain is
/// [U[p], U[count]].
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace nurbs {

/// Parameter interval [min, max] of a curve or one surface direction.
struct Interval {
  double min = 0.0;
  double max = 0.0;
  [[nodiscard]] double width() const { return max - min; }
};

/// Everything wrong with `knots` as the knot vector of a degree-`degree` B-spline with `count`
/// control points; empty when valid. Checks: degree >= 1, count >= degree + 1, size == count + degree + 1, finite
/// values, non-decreasing, multiplicity of a knot inside the domain <= degree (C0 limit), multiplicity of any value <=
/// degree + 1, and a non-degenerate domain U[p] < U[count]. Each message names the index or value at fault.
[[nodiscard]] std::vector<std::string> validate_knots(const std::vector<double>& knots, int degree, int count);

/// True when the first degree+1 knots are equal and so are the last degree+1 (the curve interpolates
/// its end control points). Assumes a valid knot vector.
[[nodiscard]] bool is_clamped(const std::vector<double>& knots, int degree);

/// Parameter domain [U[p], U[count]] of a valid knot vector.
[[nodiscard]] Interval knot_domain(const std::vector<double>& knots, int degree, int count);
/// The distinct knot values inside `domain`, its ends included when they are knots (the breaks
/// between a spline's Bézier pieces).
[[nodiscard]] std::vector<double> knot_breaks(const std::vector<double>& knots, Interval domain);

/// Number of times `u` occurs in `knots` (exact comparison: knots are data, not computed values).
[[nodiscard]] int knot_multiplicity(const std::vector<double>& knots, double u);

/// Knot span index i with U[i] <= u < U[i+1], p <= i <= count-1 (A2.1, binary search). `u` is clamped
/// to the domain; at u == U[count] (the domain end) the last non-empty span is returned, so the
/// curve end is evaluated from the left (A2.1's special case, generalised to knot vectors whose
/// last spans are empty).
[[nodiscard]] int find_span(const std::vector<double>& knots, int degree, int count, double u);

/// The degree+1 non-zero basis functions N_{span-p,p}(u) .. N_{span,p}(u) written to `out`
/// (A2.2, "inverted triangle" with left/right differences; no divisions by zero on valid input).
void basis_functions(const std::vector<double>& knots, int degree, int span, double u, double* out);
/// The same with the caller's scratch of 2 (degree + 1) doubles (no allocation per call), and, when
/// `lower` is given, the `degree` functions of degree - 1 copied there on the way (for the first
/// derivatives, The NURBS Book Eq. 2.9).
void basis_functions(const std::vector<double>& knots, int degree, int span, double u, double* out, double* scratch,
                     double* lower = nullptr);

/// Basis functions and their derivatives up to order `order` (A2.3). `out` receives (order+1) rows
/// of degree+1 values: out[k * (degree+1) + j] = d^k/du^k N_{span-p+j,p}(u). Orders above the degree
/// are zero.
void basis_function_derivatives(const std::vector<double>& knots, int degree, int span, double u, int order,
                                double* out);

/// Convenience wrappers returning vectors (tests, non-hot paths).
[[nodiscard]] std::vector<double> basis_functions(const std::vector<double>& knots, int degree, int span, double u);
[[nodiscard]] std::vector<double> basis_function_derivatives(const std::vector<double>& knots, int degree, int span,
                                                             double u, int order);

/// Zeroed scratch space of n values: on the stack up to N, else on the heap. The evaluation kernels
/// take their work arrays from it, so that low degrees allocate nothing (the allocations had been
/// a third of the time of every surface evaluation).
template <typename T, size_t N>
class SmallBuffer {
 public:
  explicit SmallBuffer(size_t n) : data_(stack_) {
    if (n > N) {
      heap_.assign(n, T{});
      data_ = heap_.data();
    } else {
      std::fill_n(stack_, n, T{});
    }
  }
  SmallBuffer(const SmallBuffer&) = delete;
  SmallBuffer& operator=(const SmallBuffer&) = delete;
  [[nodiscard]] T* data() { return data_; }
  T& operator[](size_t i) { return data_[i]; }

 private:
  T stack_[N];
  std::vector<T> heap_;
  T* data_;
};

/// Binomial coefficient C(n, k) as a double (used by A4.2/A4.4 and degree elevation).
[[nodiscard]] double binomial(int n, int k);
/// The row C(n, 0..n), computed once per n and thread; the reference stays valid for the thread's life.
[[nodiscard]] const std::vector<double>& binomial_row(int n);

}  // namespace nurbs
