#include "nurbs/tessellation/coherent_eval.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <numeric>

#include "nurbs/knot_vector.h"
#include "nurbs/surface_eval.h"

namespace nurbs::tess {

namespace {

/// One parameter direction seen by the evaluator.
struct Direction {
  const std::vector<double>* knots = nullptr;
  int degree = 0, count = 0;
  Interval domain;
};

/// The p + 1 non-zero basis functions N_{span-p+k,p}(u) (A2.2) into n0 and their first derivatives
/// N' = p (N_{i,p-1} / (U[i+p] - U[i]) - N_{i+1,p-1} / (U[i+p+1] - U[i+1])) (The NURBS Book Eq. 2.9)
/// into n1. `scratch` holds 4 (p + 1) doubles: no allocation per point, unlike A2.3's helper.
void basis_d1(const std::vector<double>& U, int p, int span, double u, double* n0, double* n1, double* scratch) {
  double* prev = scratch + 2 * (p + 1);
  basis_functions(U, p, span, u, n0, scratch, prev);  // and the degree p - 1 functions, for the derivatives
  // Both denominators span the non-empty knot span [U[span], U[span+1]], so they are > 0.
  for (int k = 0; k <= p; ++k) {
    double d = 0.0;
    if (k >= 1) d += prev[k - 1] / (U[size_t(span + k)] - U[size_t(span - p + k)]);
    if (k <= p - 1) d -= prev[k] / (U[size_t(span + k + 1)] - U[size_t(span - p + k + 1)]);
    n1[k] = p * d;
  }
}

/// Eq. 1 with first derivatives, in "slow" (outer, cached) and "fast" (inner) directions.
class Evaluator {
 public:
  Evaluator(const Surface& s, bool coherent) : s_(s), coherent_(coherent) {
    const Direction du{&s.knots_u, s.degree_u, s.count_u, surface_domain_u(s)};
    const Direction dv{&s.knots_v, s.degree_v, s.count_v, surface_domain_v(s)};
    swapped_ = s.degree_u > s.degree_v;  // §8: the fast direction gets the lower degree
    fast_ = swapped_ ? dv : du;
    slow_ = swapped_ ? du : dv;
    pw_.resize(s.points.size());
    for (size_t k = 0; k < s.points.size(); ++k) {
      const double w = s.weights.empty() ? 1.0 : s.weights[k];
      pw_[k] = glm::dvec4(w * s.points[k], w);
    }
    nf_.resize(2 * size_t(fast_.degree + 1));
    ns_.resize(2 * size_t(slow_.degree + 1));
    t0_.resize(size_t(fast_.degree + 1));
    t1_.resize(size_t(fast_.degree + 1));
    scratch_.resize(4 * size_t(std::max(fast_.degree, slow_.degree) + 1));
  }

  [[nodiscard]] bool swapped() const { return swapped_; }
  /// (fast, slow) coordinates of a (u, v) pair.
  [[nodiscard]] glm::dvec2 fast_slow(glm::dvec2 uv) const { return swapped_ ? glm::dvec2(uv.y, uv.x) : uv; }

  void eval(glm::dvec2 uv, glm::dvec3& position, glm::dvec3& normal, CoherentStats& st) {
    const glm::dvec2 fs = fast_slow(uv);
    const double f = std::clamp(fs.x, fast_.domain.min, fast_.domain.max);
    const double sl = std::clamp(fs.y, slow_.domain.min, slow_.domain.max);
    if (!coherent_ || sl != last_slow_) {
      slow_span_ = find_span(*slow_.knots, slow_.degree, slow_.count, sl);
      basis_d1(*slow_.knots, slow_.degree, slow_span_, sl, ns_.data(), ns_.data() + slow_.degree + 1, scratch_.data());
      last_slow_ = sl;
      fast_span_ = -1;
      ++st.slow_basis;
    }
    const int span = find_span(*fast_.knots, fast_.degree, fast_.count, f);
    if (span != fast_span_) {
      inner_sums(span);
      ++st.inner_sums;
    }
    if (!coherent_ || f != last_fast_) {  // a repeated u (a column of a grid) keeps its basis too
      basis_d1(*fast_.knots, fast_.degree, span, f, nf_.data(), nf_.data() + fast_.degree + 1, scratch_.data());
      last_fast_ = f;
    }
    const size_t wf = size_t(fast_.degree + 1);
    glm::dvec4 a(0.0), af(0.0), as(0.0);
    for (size_t i = 0; i < wf; ++i) {
      a += nf_[i] * t0_[i];
      af += nf_[wf + i] * t0_[i];
      as += nf_[i] * t1_[i];
    }
    // Quotient rule (The NURBS Book Eq. 4.8 in each direction): S' = (A' - w' S) / w.
    position = glm::dvec3(a) / a.w;
    const glm::dvec3 sf = (glm::dvec3(af) - af.w * position) / a.w;
    const glm::dvec3 ss = (glm::dvec3(as) - as.w * position) / a.w;
    const glm::dvec3 su = swapped_ ? ss : sf, sv = swapped_ ? sf : ss;
    normal = unit_normal(su, sv, uv);
    ++st.points;
  }

 private:
  /// T0_i = Σ_j N_j(slow) P^w, T1_i = Σ_j N_j'(slow) P^w for the d_f + 1 fast indices of `span`.
  void inner_sums(int span) {
    const size_t ws = size_t(slow_.degree + 1);
    for (int i = 0; i <= fast_.degree; ++i) {
      glm::dvec4 t0(0.0), t1(0.0);
      const int fi = span - fast_.degree + i;
      for (int j = 0; j <= slow_.degree; ++j) {
        const int sj = slow_span_ - slow_.degree + j;
        const glm::dvec4& p = swapped_ ? pw_[size_t(fi) * size_t(s_.count_u) + size_t(sj)]
                                       : pw_[size_t(sj) * size_t(s_.count_u) + size_t(fi)];
        t0 += ns_[size_t(j)] * p;
        t1 += ns_[ws + size_t(j)] * p;
      }
      t0_[size_t(i)] = t0;
      t1_[size_t(i)] = t1;
    }
    fast_span_ = span;
  }

  /// normalize(Su x Sv); at degenerate points see the file comment of coherent_eval.h.
  glm::dvec3 unit_normal(glm::dvec3 su, glm::dvec3 sv, glm::dvec2 uv) const {
    const glm::dvec3 n = glm::cross(su, sv);
    const double scale = std::max(glm::length(su), glm::length(sv));
    // Same relative threshold as surface_normal: below it the cross product is roundoff.
    if (glm::length(n) > 1e-12 * scale * scale) return glm::normalize(n);
    glm::dvec3 r = surface_normal(s_, uv.x, uv.y);
    const Interval du = surface_domain_u(s_), dv = surface_domain_v(s_);
    const glm::dvec2 centre(0.5 * (du.min + du.max), 0.5 * (dv.min + dv.max));
    for (double t = 1e-7; glm::length(r) == 0.0 && t < 1.0; t *= 10.0) {
      const glm::dvec2 q = uv + t * (centre - uv);
      r = surface_normal(s_, q.x, q.y);
    }
    return r;
  }

  const Surface& s_;
  bool coherent_;
  bool swapped_ = false;
  Direction fast_, slow_;
  std::vector<glm::dvec4> pw_;
  std::vector<double> nf_, ns_, scratch_;
  std::vector<glm::dvec4> t0_, t1_;
  double last_slow_ = std::numeric_limits<double>::quiet_NaN(), last_fast_ = last_slow_;
  int slow_span_ = 0, fast_span_ = -1;
};

void evaluate(const Surface& s, const std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& position,
              std::vector<glm::dvec3>& normal, bool coherent, CoherentStats* stats) {
  Evaluator ev(s, coherent);
  CoherentStats st;
  st.swapped = ev.swapped();
  position.resize(uv.size());
  normal.resize(uv.size());
  // Lexicographic by (slow, fast); already sorted input (the §6-7 vertex order) is used as is.
  const auto before = [&](size_t a, size_t b) {
    const glm::dvec2 x = ev.fast_slow(uv[a]), y = ev.fast_slow(uv[b]);
    return x.y < y.y || (x.y == y.y && x.x < y.x);
  };
  std::vector<size_t> order(uv.size());
  std::iota(order.begin(), order.end(), size_t{0});
  bool sorted = true;
  for (size_t k = 1; k < uv.size() && sorted; ++k) sorted = !before(k, k - 1);
  if (coherent && !sorted) std::stable_sort(order.begin(), order.end(), before);
  for (const size_t k : order) ev.eval(uv[k], position[k], normal[k], st);
  if (stats) *stats = st;
}

}  // namespace

void evaluate_coherent(const Surface& s, const std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& position,
                       std::vector<glm::dvec3>& normal, CoherentStats* stats) {
  evaluate(s, uv, position, normal, true, stats);
}

void evaluate_direct(const Surface& s, const std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& position,
                     std::vector<glm::dvec3>& normal) {
  evaluate(s, uv, position, normal, false, nullptr);
}

}  // namespace nurbs::tess
