#include "nurbs/distance/certified_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace nurbs {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// M1-M3 (or M1e-M3e) of one set of bounds.
struct Ms {
  double m1, m2, m3;
};
Ms pick(const SecondDerivativeBounds& m, KNorm norm) {
  return norm == KNorm::Euclidean ? Ms{m.m1_norm, m.m2_norm, m.m3_norm} : Ms{m.m1, m.m2, m.m3};
}

/// Largest step h with (1/8)(h^2 a + 2 h g b + g^2 c) <= tol for the other step g (0 if none, +inf
/// if any h will do).
double max_step(double a, double b, double c, double g, double tol) {
  const double rest = 8.0 * tol - c * g * g;
  if (rest < 0) return 0.0;
  if (a > 0) return (-b * g + std::sqrt(b * b * g * g + a * rest)) / a;
  if (b * g > 0) return rest / (2.0 * b * g);
  return kInf;
}

/// Segments along one direction: groups of consecutive knot spans.
struct Segments {
  std::vector<size_t> first;  ///< first span of each segment, then the span count as sentinel
  std::vector<double> lines;  ///< segment ends (breaks), size = segments + 1
  [[nodiscard]] size_t size() const { return lines.size() - 1; }
  [[nodiscard]] double width(size_t a) const { return lines[a + 1] - lines[a]; }
};

Segments segments(const std::vector<double>& breaks, const std::vector<bool>& c1, bool every_knot) {
  Segments s;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    if (k == 0 || every_knot || !c1[k]) {
      s.first.push_back(k);
      s.lines.push_back(breaks[k]);
    }
  }
  s.first.push_back(breaks.size() - 1);
  s.lines.push_back(breaks.back());
  return s;
}

/// Counts per segment for one segmentation, and the M's of every segment pair.
struct Plan {
  Segments su, sv;
  std::vector<Ms> m;  ///< m[b * su.size() + a]
  std::vector<double> n, mm;
  double samples = kInf;
};

/// Cells per segment: ceil(width / step), at least 1 (capped so a hopeless tolerance cannot overflow).
double count_for(double width, double step) {
  if (!(step > 0)) return 1e18;
  return std::clamp(std::ceil(width / step), 1.0, 1e18);
}

/// Given the counts along the other direction, the fewest counts along this one (exact per pair).
/// transpose: solve for v given u (M1 and M3 swap roles).
void best_counts(Plan& p, bool solve_u, double tol) {
  const size_t A = p.su.size(), B = p.sv.size();
  const size_t own = solve_u ? A : B, other = solve_u ? B : A;
  std::vector<double>& out = solve_u ? p.n : p.mm;
  const std::vector<double>& fixed = solve_u ? p.mm : p.n;
  const Segments& so = solve_u ? p.sv : p.su;
  const Segments& ss = solve_u ? p.su : p.sv;
  for (size_t a = 0; a < own; ++a) {
    double h = kInf;
    for (size_t b = 0; b < other; ++b) {
      const Ms& M = solve_u ? p.m[b * A + a] : p.m[a * A + b];
      const double g = so.width(b) / fixed[b];
      h = std::min(h, solve_u ? max_step(M.m1, M.m2, M.m3, g, tol) : max_step(M.m3, M.m2, M.m1, g, tol));
    }
    out[a] = count_for(ss.width(a), h);
  }
}

double total_samples(const Plan& p) {
  double nu = 1, nv = 1;
  for (double c : p.n) nu += c;
  for (double c : p.mm) nv += c;
  return nu * nv;
}

/// Scan of the share beta of the tolerance given to the v^2 term, then alternating exact steps.
Plan solve(const FilipBound& b, bool every_knot, double tol, KNorm norm) {
  Plan p;
  p.su = segments(b.breaks_u, b.c1_u, every_knot);
  p.sv = segments(b.breaks_v, b.c1_v, every_knot);
  const size_t A = p.su.size(), B = p.sv.size();
  p.m.resize(A * B);
  for (size_t sb = 0; sb < B; ++sb) {
    for (size_t sa = 0; sa < A; ++sa) {
      SecondDerivativeBounds mx;
      for (size_t pv = p.sv.first[sb]; pv < p.sv.first[sb + 1]; ++pv)
        for (size_t pu = p.su.first[sa]; pu < p.su.first[sa + 1]; ++pu) mx = max_of(mx, b.patch(pu, pv));
      p.m[sb * A + sa] = pick(mx, norm);
    }
  }
  Plan trial = p;
  trial.n.assign(A, 1.0);
  trial.mm.assign(B, 1.0);
  for (int step = 1; step < 20; ++step) {
    const double beta = step / 20.0;
    for (size_t sb = 0; sb < B; ++sb) {
      double m3 = 0.0;
      for (size_t sa = 0; sa < A; ++sa) m3 = std::max(m3, p.m[sb * A + sa].m3);
      trial.mm[sb] = m3 > 0 ? count_for(p.sv.width(sb), std::sqrt(8.0 * tol * beta / m3)) : 1.0;
    }
    best_counts(trial, true, tol);
    best_counts(trial, false, tol);
    best_counts(trial, true, tol);
    const double samples = total_samples(trial);
    if (samples < p.samples) {
      p.n = trial.n;
      p.mm = trial.mm;
      p.samples = samples;
    }
  }
  // The steps come from square roots: a count may be one short by rounding. Check every pair exactly.
  for (bool changed = true; changed && p.samples < 1e18;) {
    changed = false;
    for (size_t sb = 0; sb < B; ++sb) {
      for (size_t sa = 0; sa < A; ++sa) {
        const Ms& M = p.m[sb * A + sa];
        const double h = p.su.width(sa) / p.n[sa], g = p.sv.width(sb) / p.mm[sb];
        if (0.125 * (h * h * M.m1 + 2.0 * h * g * M.m2 + g * g * M.m3) > tol) {
          p.n[sa] += 1;
          changed = true;
        }
      }
    }
    p.samples = total_samples(p);
  }
  return p;
}

std::vector<double> params(const Segments& s, const std::vector<int>& cells) {
  std::vector<double> t;
  for (size_t a = 0; a < s.size(); ++a) {
    for (int k = 0; k < cells[a]; ++k) t.push_back(s.lines[a] + s.width(a) * k / cells[a]);
  }
  t.push_back(s.lines.back());
  return t;
}

}  // namespace

double ParamGrid::min_step() const {
  double step = kInf;
  for (size_t i = 0; i + 1 < u.size(); ++i) step = std::min(step, u[i + 1] - u[i]);
  for (size_t j = 0; j + 1 < v.size(); ++j) step = std::min(step, v[j + 1] - v[j]);
  return step;
}

ParamGrid uniform_param_grid(Interval du, Interval dv, int n, int m) {
  ParamGrid g;
  for (int i = 0; i <= n; ++i) g.u.push_back(i == n ? du.max : du.min + du.width() * i / n);
  for (int j = 0; j <= m; ++j) g.v.push_back(j == m ? dv.max : dv.min + dv.width() * j / m);
  return g;
}

double grid_cell_k(const FilipBound& b, const ParamGrid& g, int i, int j, KNorm norm) {
  return filip_k_rect(b, {g.u[size_t(i)], g.u[size_t(i) + 1]}, {g.v[size_t(j)], g.v[size_t(j) + 1]}, norm);
}

double grid_k(const FilipBound& b, const ParamGrid& g, KNorm norm) {
  // Columns (rows) that overlap the same patches differ only by their step: keep the largest.
  auto groups = [](const std::vector<double>& t, const std::vector<double>& br, const std::vector<bool>& c1,
                   bool& kink) {
    std::map<std::pair<size_t, size_t>, double> out;
    for (size_t i = 0; i + 1 < t.size(); ++i) {
      const PatchRange r = patch_range(br, c1, {t[i], t[i + 1]});
      kink = kink || r.kink;
      double& h = out[{r.first, r.last}];
      h = std::max(h, t[i + 1] - t[i]);
    }
    return out;
  };
  bool kink = false;
  const auto gu = groups(g.u, b.breaks_u, b.c1_u, kink), gv = groups(g.v, b.breaks_v, b.c1_v, kink);
  if (kink) return kInf;
  double k = 0.0;
  for (const auto& [rv, hv] : gv) {
    for (const auto& [ru, hu] : gu) {
      SecondDerivativeBounds mx;
      for (size_t pv = rv.first; pv <= rv.second; ++pv)
        for (size_t pu = ru.first; pu <= ru.second; ++pu) mx = max_of(mx, b.patch(pu, pv));
      k = std::max(k, filip_k(mx, hu, hv, norm));
    }
  }
  return k;
}

std::vector<double> segment_k(const FilipBound& b, const CertifiedGrid& g, KNorm norm) {
  std::vector<double> out;
  for (size_t sb = 0; sb + 1 < g.lines_v.size(); ++sb) {
    const double hv = (g.lines_v[sb + 1] - g.lines_v[sb]) / g.cells_v[sb];
    const PatchRange rv = patch_range(b.breaks_v, b.c1_v, {g.lines_v[sb], g.lines_v[sb + 1]});
    for (size_t sa = 0; sa + 1 < g.lines_u.size(); ++sa) {
      const double hu = (g.lines_u[sa + 1] - g.lines_u[sa]) / g.cells_u[sa];
      const PatchRange ru = patch_range(b.breaks_u, b.c1_u, {g.lines_u[sa], g.lines_u[sa + 1]});
      SecondDerivativeBounds mx;
      for (size_t pv = rv.first; pv <= rv.last; ++pv)
        for (size_t pu = ru.first; pu <= ru.last; ++pu) mx = max_of(mx, b.patch(pu, pv));
      out.push_back(ru.kink || rv.kink ? kInf : filip_k(mx, hu, hv, norm));
    }
  }
  return out;
}

CertifiedGrid certified_grid(const FilipBound& b, double tolerance, const GridLimits& limits, KNorm norm) {
  CertifiedGrid out;
  out.tolerance = tolerance;
  const SecondDerivativeBounds& w = b.whole;
  const bool finite = std::isfinite(w.m1) && std::isfinite(w.m2) && std::isfinite(w.m3) && std::isfinite(w.m1_norm) &&
                      std::isfinite(w.m2_norm) && std::isfinite(w.m3_norm);
  Plan best;
  if (finite && tolerance > 0) {
    // Every knot a line adapts per span; worth trying unless the span table is huge.
    if (b.spans_u() * b.spans_v() <= 1'000'000) best = solve(b, true, tolerance, norm);
    Plan merged = solve(b, false, tolerance, norm);
    if (merged.su.size() == 1 && merged.sv.size() == 1) {
      // One segment each way (a C^1 surface): the exhaustive uniform search is exact there.
      const int cap = static_cast<int>(std::min(std::sqrt(static_cast<double>(limits.max_samples)), 65536.0));
      const GridChoice u = choose_grid(b, tolerance, cap, norm);
      const double samples = (u.n + 1.0) * (u.m + 1.0);
      if (u.k <= tolerance && samples < merged.samples) {
        merged.n = {double(u.n)};
        merged.mm = {double(u.m)};
        merged.samples = samples;
      }
    }
    if (merged.samples < best.samples) best = std::move(merged);
  } else {
    best.su = segments(b.breaks_u, b.c1_u, false);
    best.sv = segments(b.breaks_v, b.c1_v, false);
    best.n.assign(best.su.size(), 1.0);
    best.mm.assign(best.sv.size(), 1.0);
    best.samples = total_samples(best);
    out.reason = finite ? fmt::format("tolerance {} is not positive", tolerance)
                        : "the second-derivative bound is not finite (weights near zero or coordinates overflow)";
  }
  const double limit = static_cast<double>(limits.max_samples);
  if (best.samples > limit && out.reason.empty()) {
    out.reason = fmt::format("needs {:.3g} samples, over the limit of {} per face", best.samples, limits.max_samples);
    // Scale every count down by the same factor until the grid fits.
    double f = std::sqrt(limit / best.samples);
    for (int tries = 0; tries < 60 && total_samples(best) > limit; ++tries, f *= 0.9) {
      Plan scaled = best;
      for (double& c : scaled.n) c = std::max(1.0, std::floor(c * f));
      for (double& c : scaled.mm) c = std::max(1.0, std::floor(c * f));
      if (total_samples(scaled) <= limit || tries == 59) {
        best.n = scaled.n;
        best.mm = scaled.mm;
        break;
      }
    }
  }
  out.lines_u = best.su.lines;
  out.lines_v = best.sv.lines;
  for (double c : best.n) out.cells_u.push_back(static_cast<int>(std::min(c, 1e9)));
  for (double c : best.mm) out.cells_v.push_back(static_cast<int>(std::min(c, 1e9)));
  out.grid.u = params(best.su, out.cells_u);
  out.grid.v = params(best.sv, out.cells_v);
  out.k = grid_k(b, out.grid, KNorm::Component);
  out.k_e = grid_k(b, out.grid, KNorm::Euclidean);
  const double achieved = norm == KNorm::Euclidean ? out.k_e : out.k;
  out.meets_tolerance = out.reason.empty() && achieved <= tolerance;
  if (out.reason.empty() && !out.meets_tolerance)  // rounding of the steps: should not happen
    out.reason = fmt::format("K_e {:.3g} above the tolerance {:.3g} after rounding", achieved, tolerance);
  return out;
}

}  // namespace nurbs
