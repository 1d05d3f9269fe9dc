#include "nurbs/degree_elevation.h"

#include <algorithm>

#include "nurbs/knot_insertion.h"
#include "nurbs/knot_vector.h"

namespace nurbs {

HomogeneousCurve elevate_degree(const HomogeneousCurve& curve, int t) {
  if (t <= 0) return curve;
  const HomogeneousCurve c = clamp_curve(curve);
  const int p = c.degree;
  const int n = static_cast<int>(c.points.size()) - 1;
  const int m = n + p + 1;
  const int ph = p + t, ph2 = ph / 2;
  const auto& U = c.knots;
  const auto& Pw = c.points;
  auto idx = [](int i) { return static_cast<size_t>(i); };

  // Bézier degree elevation coefficients bezalfs[i][j] (row i of the elevated segment).
  std::vector<std::vector<double>> bezalfs(idx(ph) + 1, std::vector<double>(idx(p) + 1, 0.0));
  bezalfs[0][0] = bezalfs[idx(ph)][idx(p)] = 1.0;
  for (int i = 1; i <= ph2; ++i) {
    const double inv = 1.0 / binomial(ph, i);
    for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
      bezalfs[idx(i)][idx(j)] = inv * binomial(p, j) * binomial(t, i - j);
  }
  for (int i = ph2 + 1; i <= ph - 1; ++i) {
    for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
      bezalfs[idx(i)][idx(j)] = bezalfs[idx(ph - i)][idx(p - j)];
  }

  // Output sizes: at most (number of segments) * (ph) + 1 points; trimmed at the end.
  const size_t cap = (idx(m) + 1) * (idx(t) + 1) + idx(ph) + 2;
  std::vector<double> Uh(cap + idx(ph) + 1);
  std::vector<glm::dvec4> Qw(cap);
  std::vector<glm::dvec4> bpts(idx(p) + 1), ebpts(idx(ph) + 1), nextbpts(idx(std::max(p - 1, 0)) + 1);
  std::vector<double> alfs(idx(std::max(p - 1, 0)) + 1);

  int mh = ph, kind = ph + 1;
  int r = -1, a = p, b = p + 1, cind = 1;
  double ua = U[0];
  Qw[0] = Pw[0];
  for (int i = 0; i <= ph; ++i) Uh[idx(i)] = ua;
  for (int i = 0; i <= p; ++i) bpts[idx(i)] = Pw[idx(i)];

  while (b < m) {
    const int i0 = b;
    while (b < m && U[idx(b)] == U[idx(b + 1)]) ++b;
    const int mul = b - i0 + 1;
    mh += mul + t;
    const double ub = U[idx(b)];
    const int oldr = r;
    r = p - mul;
    // Insert u_b r times so that bpts becomes the Bézier segment [ua, ub].
    const int lbz = oldr > 0 ? (oldr + 2) / 2 : 1;
    const int rbz = r > 0 ? ph - (r + 1) / 2 : ph;
    if (r > 0) {
      const double numer = ub - ua;
      for (int k = p; k > mul; --k) alfs[idx(k - mul - 1)] = numer / (U[idx(a + k)] - ua);
      for (int j = 1; j <= r; ++j) {
        const int save = r - j, s = mul + j;
        for (int k = p; k >= s; --k) {
          bpts[idx(k)] = alfs[idx(k - s)] * bpts[idx(k)] + (1.0 - alfs[idx(k - s)]) * bpts[idx(k - 1)];
        }
        nextbpts[idx(save)] = bpts[idx(p)];
      }
    }
    // Elevate the Bézier segment.
    for (int i = lbz; i <= ph; ++i) {
      ebpts[idx(i)] = glm::dvec4(0.0);
      for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
        ebpts[idx(i)] += bezalfs[idx(i)][idx(j)] * bpts[idx(j)];
    }
    if (oldr > 1) {
      // Remove knot u = ua oldr - 1 times (it was inserted by the previous pass).
      int first = kind - 2, last = kind;
      const double den = ub - ua;
      const double bet = (ub - Uh[idx(kind - 1)]) / den;
      for (int tr = 1; tr < oldr; ++tr) {
        int i = first, j = last, kj = j - kind + 1;
        while (j - i > tr) {
          if (i < cind) {
            const double alf = (ub - Uh[idx(i)]) / (ua - Uh[idx(i)]);
            Qw[idx(i)] = alf * Qw[idx(i)] + (1.0 - alf) * Qw[idx(i - 1)];
          }
          if (j >= lbz) {
            if (j - tr <= kind - ph + oldr) {
              const double gam = (ub - Uh[idx(j - tr)]) / den;
              ebpts[idx(kj)] = gam * ebpts[idx(kj)] + (1.0 - gam) * ebpts[idx(kj + 1)];
            } else {
              ebpts[idx(kj)] = bet * ebpts[idx(kj)] + (1.0 - bet) * ebpts[idx(kj + 1)];
            }
          }
          ++i;
          --j;
          --kj;
        }
        --first;
        ++last;
      }
    }
    if (a != p) {
      for (int i = 0; i < ph - oldr; ++i) Uh[idx(kind++)] = ua;
    }
    for (int j = lbz; j <= rbz; ++j) Qw[idx(cind++)] = ebpts[idx(j)];
    if (b < m) {
      for (int j = 0; j < r; ++j) bpts[idx(j)] = nextbpts[idx(j)];
      for (int j = r; j <= p; ++j) bpts[idx(j)] = Pw[idx(b - p + j)];
      a = b;
      ++b;
      ua = ub;
    } else {
      for (int i = 0; i <= ph; ++i) Uh[idx(kind + i)] = ub;
    }
  }
  const int nh = mh - ph - 1;
  HomogeneousCurve out{ph, std::vector<double>(Uh.begin(), Uh.begin() + nh + ph + 2),
                       std::vector<glm::dvec4>(Qw.begin(), Qw.begin() + nh + 1)};
  return out;
}

Surface elevate_degree_u(const Surface& s, int t) {
  return apply_to_rows(s, [t](const HomogeneousCurve& h) { return elevate_degree(h, t); });
}

Surface elevate_degree_v(const Surface& s, int t) {
  return apply_to_columns(s, [t](const HomogeneousCurve& h) { return elevate_degree(h, t); });
}

}  // namespace nurbs
