#include "nurbs/distance/filip_bound.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <thread>

#include "nurbs/bernstein_poly.h"
#include "nurbs/bezier_extraction.h"
#include "nurbs/knot_insertion.h"
#include "nurbs/surface_eval.h"

namespace nurbs {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Max over a set of vectors of each |coordinate| (Eqs. 1-3) and of the Euclidean norm (K_e).
/// The norm is kept squared while adding (one square root per set, in finish(); a square root per
/// vector made it a third of the bound's time).
struct MaxAbs {
  glm::dvec3 coord{0.0};
  double norm = 0.0;
  void add(const glm::dvec3& v) {
    coord = glm::max(coord, glm::abs(v));
    norm = std::max(norm, glm::dot(v, v));
  }
  MaxAbs& finish() {
    norm = std::sqrt(norm);
    return *this;
  }
};

/// The largest coordinate of a vector of magnitudes.
double largest(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }

/// Bounds of a Bézier patch split into parts x parts equal sub-patches (max over the pieces): the
/// difference nets of smaller pieces converge to the derivatives, tightening mostly the rational bound.
SecondDerivativeBounds split_patch_bounds(const BezierPatch& patch, int parts) {
  if (parts <= 1) return bezier_patch_bounds(patch.surface, patch.range_u.width(), patch.range_v.width());
  Surface r = patch.surface;
  for (int k = 1; k < parts; ++k)
    r = insert_knot_u(r, patch.range_u.min + patch.range_u.width() * k / parts, r.degree_u);
  for (int k = 1; k < parts; ++k)
    r = insert_knot_v(r, patch.range_v.min + patch.range_v.width() * k / parts, r.degree_v);
  SecondDerivativeBounds mx;
  for (const auto& piece : extract_bezier_patches(r))
    mx = max_of(mx, bezier_patch_bounds(piece.surface, piece.range_u.width(), piece.range_v.width()));
  return mx;
}

/// The four halves of a Bézier patch (split at the middle of both parameter ranges).
std::vector<BezierPatch> split_2x2(const BezierPatch& patch) {
  Surface r = insert_knot_u(patch.surface, patch.range_u.min + 0.5 * patch.range_u.width(), patch.surface.degree_u);
  r = insert_knot_v(r, patch.range_v.min + 0.5 * patch.range_v.width(), r.degree_v);
  return extract_bezier_patches(r);
}

}  // namespace

SecondDerivativeBounds adaptive_patch_bounds(const BezierPatch& patch, const AdaptiveRefinement& rule) {
  // Branch and bound on the piece that sets the bound: its score is K_e of one cell the size of the
  // whole patch (the weights of M1e, M2e, M3e are the patch widths), so pieces compare on one scale.
  const double wu = patch.range_u.width(), wv = patch.range_v.width();
  auto score = [&](const SecondDerivativeBounds& m) { return filip_k(m, wu, wv, KNorm::Euclidean); };
  struct Leaf {
    BezierPatch patch;
    SecondDerivativeBounds m;
    double score;
  };
  auto by_score = [](const Leaf& a, const Leaf& b) { return a.score < b.score; };
  std::vector<Leaf> heap;  // max-heap on score
  const SecondDerivativeBounds root = bezier_patch_bounds(patch.surface, wu, wv);
  heap.push_back({patch, root, score(root)});
  SecondDerivativeBounds settled;  // pieces that stopped improving
  int leaves = 1;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), by_score);
    Leaf worst = std::move(heap.back());
    heap.pop_back();
    if (leaves + 3 > rule.max_pieces || !(worst.score > 0.0)) {
      settled = max_of(settled, worst.m);
      break;
    }
    std::vector<Leaf> children;
    double child_score = 0.0;
    for (auto& piece : split_2x2(worst.patch)) {
      const SecondDerivativeBounds m = bezier_patch_bounds(piece.surface, piece.range_u.width(), piece.range_v.width());
      child_score = std::max(child_score, score(m));
      children.push_back({std::move(piece), m, score(m)});
    }
    if (child_score > rule.min_gain * worst.score) {  // no longer improving: this piece's bound stays
      SecondDerivativeBounds mc;
      for (const auto& c : children) mc = max_of(mc, c.m);
      // Either bound holds for the piece; keep the field-wise smaller of the two.
      settled = max_of(settled, {std::min(worst.m.m1, mc.m1), std::min(worst.m.m2, mc.m2), std::min(worst.m.m3, mc.m3),
                                 std::min(worst.m.m1_norm, mc.m1_norm), std::min(worst.m.m2_norm, mc.m2_norm),
                                 std::min(worst.m.m3_norm, mc.m3_norm)});
      break;
    }
    leaves += 3;
    for (auto& c : children) {
      heap.push_back(std::move(c));
      std::push_heap(heap.begin(), heap.end(), by_score);
    }
  }
  for (const auto& l : heap) settled = max_of(settled, l.m);
  return settled;
}

namespace {

/// The exact-form bound of a rational patch: w^3 S_uu, w^3 S_uv, w^3 S_vv are polynomials (N = w (P - c))
///   w^3 S_uu = w^2 N_uu - 2 w w_u N_u - w w_uu N + 2 w_u^2 N
///   w^3 S_uv = w^2 N_uv - w w_v N_u - w w_u N_v - w w_uv N + 2 w_u w_v N
/// (and S_vv like S_uu), built in Bernstein form, so the convex hull of their coefficients over the
/// lower bound of w^3 (its smallest Bernstein coefficient, or w_min^3) bounds the derivatives. Unlike
/// the quotient rule's triangle inequality it keeps the cancellations (an extruded arc has S_uv = 0
/// while its quotient-rule bound stays 2 |w_u| |S_v| / w at any piece size), and converges to the
/// true maximum as pieces shrink. Returns false when w^3 has no positive lower bound.
bool numerator_bounds(const BezierNet& patch, double du, double dv, glm::dvec3 c, SecondDerivativeBounds& out) {
  const int p = patch.p, q = patch.q;
  BernsteinScalar w{p, q, {}};
  BernsteinVector N{p, q, {}};
  for (int j = 0; j <= q; ++j)
    for (int i = 0; i <= p; ++i) {
      w.c.push_back(patch.weight(i, j));
      N.c.push_back(patch.weight(i, j) * (patch.point(i, j) - c));
    }
  const BernsteinScalar wu = derivative(w, true, du), wv = derivative(w, false, dv);
  const BernsteinVector Nu = derivative(N, true, du), Nv = derivative(N, false, dv);
  const BernsteinScalar w2 = multiply(w, w);
  double w3_low = std::pow(*std::min_element(w.c.begin(), w.c.end()), 3);
  const BernsteinScalar w3 = multiply(w2, w);
  w3_low = std::max(w3_low, *std::min_element(w3.c.begin(), w3.c.end()));
  if (!(w3_low > 0)) return false;
  auto sum = [](std::initializer_list<std::pair<double, BernsteinVector>> terms) {
    BernsteinVector r = terms.begin()->second;
    for (auto& x : r.c) x *= terms.begin()->first;
    for (auto it = terms.begin() + 1; it != terms.end(); ++it) add_scaled(r, it->first, it->second);
    return r;
  };
  // Second derivatives along one direction (S_uu, or S_vv with along_u = false).
  auto pure = [&](bool along_u) {
    const int deg = along_u ? p : q;
    const double width = along_u ? du : dv;
    const BernsteinScalar& wd = along_u ? wu : wv;
    const BernsteinVector& Nd = along_u ? Nu : Nv;
    BernsteinVector r = sum({{-2.0, multiply(multiply(w, wd), Nd)}, {2.0, multiply(multiply(wd, wd), N)}});
    if (deg >= 2) {
      add_scaled(r, 1.0, multiply(w2, derivative(Nd, along_u, width)));
      add_scaled(r, -1.0, multiply(multiply(w, derivative(wd, along_u, width)), N));
    }
    return r;
  };
  const BernsteinVector Puu = pure(true), Pvv = pure(false);
  const BernsteinVector Puv = sum({{1.0, multiply(w2, derivative(Nu, false, dv))},
                                   {-1.0, multiply(multiply(w, wv), Nu)},
                                   {-1.0, multiply(multiply(w, wu), Nv)},
                                   {-1.0, multiply(multiply(w, derivative(wu, false, dv)), N)},
                                   {2.0, multiply(multiply(wu, wv), N)}});
  auto bound = [&](const BernsteinVector& P, double& coord, double& norm) {
    MaxAbs m;
    for (const auto& x : P.c) m.add(x);
    m.finish();
    coord = std::max({m.coord.x, m.coord.y, m.coord.z}) / w3_low;
    norm = m.norm / w3_low;
  };
  bound(Puu, out.m1, out.m1_norm);
  bound(Puv, out.m2, out.m2_norm);
  bound(Pvv, out.m3, out.m3_norm);
  return true;
}

/// One-sided first derivatives agree along the common edge of two patches (see FilipBound::c1_u).
bool c1_across(const Surface& left, const Surface& right, bool along_u, double at, Interval edge, int samples) {
  for (int k = 0; k < samples; ++k) {
    const double t = edge.min + edge.width() * (k + 0.5) / samples;
    const SurfaceDerivatives l = along_u ? surface_derivatives(left, at, t) : surface_derivatives(left, t, at);
    const SurfaceDerivatives r = along_u ? surface_derivatives(right, at, t) : surface_derivatives(right, t, at);
    const glm::dvec3 dl = along_u ? l.su : l.sv, dr = along_u ? r.su : r.sv;
    // 1e-9 relative: roundoff of A4.4 is ~1e-14; a real kink is far larger.
    const double scale = std::max({glm::length(dl), glm::length(dr), 1e-300});
    if (glm::length(dl - dr) > 1e-9 * scale) return false;
  }
  return true;
}

}  // namespace

SecondDerivativeBounds max_of(const SecondDerivativeBounds& a, const SecondDerivativeBounds& b) {
  return {std::max(a.m1, b.m1),           std::max(a.m2, b.m2),           std::max(a.m3, b.m3),
          std::max(a.m1_norm, b.m1_norm), std::max(a.m2_norm, b.m2_norm), std::max(a.m3_norm, b.m3_norm)};
}

SecondDerivativeBounds bezier_patch_bounds(const Surface& patch, double du, double dv) {
  return bezier_patch_bounds(BezierNet::of(patch), du, dv);
}

namespace {

/// The polynomial case of bezier_patch_bounds: the second-difference nets alone (every weight 1,
/// so the quotient rule's weight terms vanish and no translation is needed).
SecondDerivativeBounds polynomial_patch_bounds(const BezierNet& patch, double du, double dv) {
  const int p = patch.p, q = patch.q;
  const double fuu = p * (p - 1) / (du * du), fvv = q * (q - 1) / (dv * dv), fuv = p * q / (du * dv);
  MaxAbs uu, uv, vv;
  for (int j = 0; j <= q; ++j) {
    for (int i = 0; i <= p; ++i) {
      const glm::dvec3& P = patch.point(i, j);
      if (i + 2 <= p) uu.add(fuu * (patch.point(i + 2, j) - 2.0 * patch.point(i + 1, j) + P));
      if (j + 2 <= q) vv.add(fvv * (patch.point(i, j + 2) - 2.0 * patch.point(i, j + 1) + P));
      if (i + 1 <= p && j + 1 <= q)
        uv.add(fuv * (patch.point(i + 1, j + 1) - patch.point(i + 1, j) - patch.point(i, j + 1) + P));
    }
  }
  // As norm_bound below: the norm over the net, never under the largest coordinate (rounding).
  auto norm = [&](MaxAbs& m) { return std::max(largest(m.coord), m.finish().norm); };
  return {largest(uu.coord), largest(uv.coord), largest(vv.coord), norm(uu), norm(uv), norm(vv)};
}

/// What the quotient rule needs of a rational patch's net: the centre c of its control-point box (a
/// translation by c changes no derivative and makes |S - c| <= R smallest), the box's half extent R,
/// the Euclidean radius Re of the points about c, and the smallest weight.
struct NetFrame {
  glm::dvec3 c{0.0}, R{0.0};
  double Re = 0.0, wmin = kInf;
};
NetFrame net_frame(const BezierNet& patch) {
  glm::dvec3 lo(kInf), hi(-kInf);
  NetFrame f;
  for (int j = 0; j <= patch.q; ++j)
    for (int i = 0; i <= patch.p; ++i) {
      lo = glm::min(lo, patch.point(i, j));
      hi = glm::max(hi, patch.point(i, j));
      f.wmin = std::min(f.wmin, patch.weight(i, j));
    }
  f.c = 0.5 * (lo + hi), f.R = 0.5 * (hi - lo);
  for (int j = 0; j <= patch.q; ++j)
    for (int i = 0; i <= patch.p; ++i) f.Re = std::max(f.Re, glm::dot(patch.point(i, j) - f.c, patch.point(i, j) - f.c));
  f.Re = std::sqrt(f.Re);
  return f;
}

/// The first-difference nets of N = w (P - c) (A_u, A_v: max |.| and norm) and of the weights
/// (W_u, W_v), scaled to derivatives wrt the parameters (p / du, q / dv). Unit weights when the
/// surface is polynomial.
struct FirstDifferences {
  MaxAbs Au, Av;
  double Wu = 0.0, Wv = 0.0;
};
FirstDifferences first_differences(const BezierNet& patch, glm::dvec3 c, double du, double dv) {
  const bool rational = patch.s->rational();
  auto N = [&](int i, int j) { return (rational ? patch.weight(i, j) : 1.0) * (patch.point(i, j) - c); };
  auto W = [&](int i, int j) { return rational ? patch.weight(i, j) : 1.0; };
  FirstDifferences d;
  const double fu = patch.p / du, fv = patch.q / dv;
  for (int j = 0; j <= patch.q; ++j)
    for (int i = 0; i <= patch.p; ++i) {
      if (i + 1 <= patch.p) {
        d.Au.add(fu * (N(i + 1, j) - N(i, j)));
        d.Wu = std::max(d.Wu, std::abs(fu * (W(i + 1, j) - W(i, j))));
      }
      if (j + 1 <= patch.q) {
        d.Av.add(fv * (N(i, j + 1) - N(i, j)));
        d.Wv = std::max(d.Wv, std::abs(fv * (W(i, j + 1) - W(i, j))));
      }
    }
  d.Au.finish(), d.Av.finish();
  return d;
}

}  // namespace

SecondDerivativeBounds bezier_patch_bounds(const BezierNet& patch, double du, double dv, bool exact_form) {
  const int p = patch.p, q = patch.q;
  if (!patch.s->rational()) return polynomial_patch_bounds(patch, du, dv);
  const auto [c, R, Re, wmin] = net_frame(patch);
  auto N = [&patch, centre = c](int i, int j) { return patch.weight(i, j) * (patch.point(i, j) - centre); };
  auto W = [&](int i, int j) { return patch.weight(i, j); };
  const auto [Au, Av, Wu, Wv] = first_differences(patch, c, du, dv);
  MaxAbs Auu, Auv, Avv;
  double Wuu = 0, Wuv = 0, Wvv = 0;
  const double fuu = p * (p - 1) / (du * du), fvv = q * (q - 1) / (dv * dv), fuv = p * q / (du * dv);
  for (int j = 0; j <= q; ++j) {
    for (int i = 0; i <= p; ++i) {
      if (i + 2 <= p) {
        Auu.add(fuu * (N(i + 2, j) - 2.0 * N(i + 1, j) + N(i, j)));
        Wuu = std::max(Wuu, std::abs(fuu * (W(i + 2, j) - 2.0 * W(i + 1, j) + W(i, j))));
      }
      if (j + 2 <= q) {
        Avv.add(fvv * (N(i, j + 2) - 2.0 * N(i, j + 1) + N(i, j)));
        Wvv = std::max(Wvv, std::abs(fvv * (W(i, j + 2) - 2.0 * W(i, j + 1) + W(i, j))));
      }
      if (i + 1 <= p && j + 1 <= q) {
        Auv.add(fuv * (N(i + 1, j + 1) - N(i + 1, j) - N(i, j + 1) + N(i, j)));
        Wuv = std::max(Wuv, std::abs(fuv * (W(i + 1, j + 1) - W(i + 1, j) - W(i, j + 1) + W(i, j))));
      }
    }
  }
  for (MaxAbs* m : {&Auu, &Auv, &Avv}) m->finish();
  const glm::dvec3 Du = (Au.coord + Wu * R) / wmin, Dv = (Av.coord + Wv * R) / wmin;
  const glm::dvec3 Muu = (Auu.coord + 2.0 * Wu * Du + Wuu * R) / wmin;
  const glm::dvec3 Muv = (Auv.coord + Wu * Dv + Wv * Du + Wuv * R) / wmin;
  const glm::dvec3 Mvv = (Avv.coord + 2.0 * Wv * Dv + Wvv * R) / wmin;
  // The same quotient rule with norms (triangle inequality), capped by the norm of the
  // per-coordinate bounds (the file comment says why both are bounds and why the cap helps). Both
  // are >= the per-coordinate bound in exact arithmetic; the outer max absorbs rounding (and FMA
  // contraction that may differ between the vector and scalar formulas): a larger number is still a bound.
  auto norm_bound = [&](double quotient, const glm::dvec3& per_coord) {
    return std::max(largest(per_coord), std::min(quotient, glm::length(per_coord)));
  };
  const double Due = (Au.norm + Wu * Re) / wmin, Dve = (Av.norm + Wv * Re) / wmin;
  const double Muu_e = (Auu.norm + 2.0 * Wu * Due + Wuu * Re) / wmin;
  const double Muv_e = (Auv.norm + Wu * Dve + Wv * Due + Wuv * Re) / wmin;
  const double Mvv_e = (Avv.norm + 2.0 * Wv * Dve + Wvv * Re) / wmin;
  const SecondDerivativeBounds quotient{largest(Muu),           largest(Muv),           largest(Mvv),
                                        norm_bound(Muu_e, Muu), norm_bound(Muv_e, Muv), norm_bound(Mvv_e, Mvv)};
  // Rational patches with varying weights: also the exact-form bound; both hold, keep the smaller.
  SecondDerivativeBounds exact;
  if (!exact_form || (Wu == 0 && Wv == 0) || !numerator_bounds(patch, du, dv, c, exact)) return quotient;
  return {std::min(quotient.m1, exact.m1),           std::min(quotient.m2, exact.m2),
          std::min(quotient.m3, exact.m3),           std::min(quotient.m1_norm, exact.m1_norm),
          std::min(quotient.m2_norm, exact.m2_norm), std::min(quotient.m3_norm, exact.m3_norm)};
}

double FirstDerivativeBounds::lipschitz() const { return std::sqrt(su * su + sv * sv); }

FirstDerivativeBounds first_derivative_bounds(const BezierNet& patch, double du, double dv) {
  if (!patch.s->rational()) {
    const FirstDifferences d = first_differences(patch, glm::dvec3(0.0), du, dv);
    return {d.Au.norm, d.Av.norm};
  }
  const NetFrame f = net_frame(patch);
  const FirstDifferences d = first_differences(patch, f.c, du, dv);
  return {(d.Au.norm + d.Wu * f.Re) / f.wmin, (d.Av.norm + d.Wv * f.Re) / f.wmin};
}

bool FilipBound::c1() const {
  return std::all_of(c1_u.begin(), c1_u.end(), [](bool b) { return b; }) &&
         std::all_of(c1_v.begin(), c1_v.end(), [](bool b) { return b; });
}

FilipBound filip_bound(const Surface& s, int subdivisions) {
  FilipBound b;
  b.domain_u = surface_domain_u(s);
  b.domain_v = surface_domain_v(s);
  b.breaks_u = knot_breaks(s.knots_u, b.domain_u);
  b.breaks_v = knot_breaks(s.knots_v, b.domain_v);
  const size_t nu = b.breaks_u.size() - 1, nv = b.breaks_v.size() - 1;
  // One patch per knot rectangle, read in place from the surface refined to Bézier form (patch
  // objects are copied out only for the subdivided and adaptive bounds, which split them).
  const Surface refined = refine_surface_to_bezier(s);
  if (refined.count_u != int(nu) * s.degree_u + 1 || refined.count_v != int(nv) * s.degree_v + 1)
    throw std::invalid_argument("filip_bound: a knot of the surface exceeds its degree's multiplicity");
  b.patches.resize(nu * nv);
  auto patch = [&](size_t a, size_t row) {  // a copy of patch (a, row), for the bounds that split it
    return bezier_patch(refined, int(a), int(row), {b.breaks_u[a], b.breaks_u[a + 1]},
                        {b.breaks_v[row], b.breaks_v[row + 1]});
  };
  auto bound_one = [&](size_t k) {
    const size_t a = k % nu, row = k / nu;
    const double du = b.breaks_u[a + 1] - b.breaks_u[a], dv = b.breaks_v[row + 1] - b.breaks_v[row];
    if (subdivisions == 1) return bezier_patch_bounds(BezierNet::in_refined(refined, int(a), int(row)), du, dv);
    return subdivisions > 0 ? split_patch_bounds(patch(a, row), subdivisions)
                            : adaptive_patch_bounds(patch(a, row), AdaptiveRefinement{});
  };
  // Patches are independent: bounded on every hardware thread in contiguous shares (same result
  // in any order). The one-piece bound costs a fraction of a microsecond a patch: threads only pay
  // above some thousands of patches.
  const size_t work = b.patches.size() * size_t(subdivisions == 1 ? 1 : 16);
  const size_t threads = work < 8192 ? 1 : std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  auto bound_range = [&](size_t t) {
    for (size_t k = b.patches.size() * t / threads, end = b.patches.size() * (t + 1) / threads; k < end; ++k)
      b.patches[k] = bound_one(k);
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(bound_range, t);
  bound_range(0);
  for (auto& t : pool) t.join();
  for (const auto& m : b.patches) b.whole = max_of(b.whole, m);
  // C^1 across knot lines: automatic where multiplicity < degree (C^{p - mult}), checked otherwise.
  b.c1_u.assign(b.breaks_u.size(), true);
  b.c1_v.assign(b.breaks_v.size(), true);
  for (size_t a = 1; a < nu; ++a) {
    if (knot_multiplicity(s.knots_u, b.breaks_u[a]) < s.degree_u) continue;
    for (size_t row = 0; row < nv && b.c1_u[a]; ++row) {
      const BezierPatch L = patch(a - 1, row), R = patch(a, row);
      b.c1_u[a] = c1_across(L.surface, R.surface, true, b.breaks_u[a], L.range_v, 2 * s.degree_v + 2);
    }
  }
  for (size_t c = 1; c < nv; ++c) {
    if (knot_multiplicity(s.knots_v, b.breaks_v[c]) < s.degree_v) continue;
    for (size_t col = 0; col < nu && b.c1_v[c]; ++col) {
      const BezierPatch L = patch(col, c - 1), R = patch(col, c);
      b.c1_v[c] = c1_across(L.surface, R.surface, false, b.breaks_v[c], L.range_u, 2 * s.degree_u + 2);
    }
  }
  return b;
}

namespace {

/// M1-M3 of Eqs. (1)-(3), or their Euclidean counterparts.
struct Ms {
  double m1, m2, m3;
};
Ms pick(const SecondDerivativeBounds& m, KNorm norm) {
  return norm == KNorm::Euclidean ? Ms{m.m1_norm, m.m2_norm, m.m3_norm} : Ms{m.m1, m.m2, m.m3};
}

}  // namespace

FilipBound sampled_bound(const Surface& s, const FilipBound& b, int samples) {
  if (samples <= 0) samples = std::max(s.degree_u, s.degree_v) + 3;
  FilipBound out = b;
  out.whole = {};
  for (size_t pv = 0; pv < b.spans_v(); ++pv) {
    for (size_t pu = 0; pu < b.spans_u(); ++pu) {
      MaxAbs uu, uv, vv;
      for (int j = 0; j <= samples; ++j) {
        for (int i = 0; i <= samples; ++i) {
          // Strictly inside by a hair at the patch edges, so one-sided derivatives of this patch are taken.
          const double tu = std::clamp(double(i) / samples, 1e-9, 1 - 1e-9),
                       tv = std::clamp(double(j) / samples, 1e-9, 1 - 1e-9);
          const double u = b.breaks_u[pu] + tu * (b.breaks_u[pu + 1] - b.breaks_u[pu]);
          const double v = b.breaks_v[pv] + tv * (b.breaks_v[pv + 1] - b.breaks_v[pv]);
          const SurfaceDerivatives d = surface_derivatives(s, u, v);
          uu.add(d.suu);
          uv.add(d.suv);
          vv.add(d.svv);
        }
      }
      uu.finish(), uv.finish(), vv.finish();
      SecondDerivativeBounds& m = out.patches[pv * b.spans_u() + pu];
      m = {largest(uu.coord), largest(uv.coord), largest(vv.coord), uu.norm, uv.norm, vv.norm};
      out.whole = max_of(out.whole, m);
    }
  }
  return out;
}

double filip_k(const SecondDerivativeBounds& m, double h_u, double h_v, KNorm norm) {
  const Ms M = pick(m, norm);
  return 0.125 * (h_u * h_u * M.m1 + 2.0 * h_u * h_v * M.m2 + h_v * h_v * M.m3);
}

PatchRange patch_range(const std::vector<double>& br, const std::vector<bool>& c1, Interval t) {
  const double eps = 1e-12 * (br.back() - br.front());
  PatchRange o;
  const auto it = std::upper_bound(br.begin(), br.end(), t.min + eps);
  o.first = static_cast<size_t>(std::max<std::ptrdiff_t>(it - br.begin() - 1, 0));
  o.first = std::min(o.first, br.size() - 2);
  o.last = o.first;
  while (o.last + 2 < br.size() && br[o.last + 1] < t.max - eps) {
    if (!c1[o.last + 1]) o.kink = true;
    ++o.last;
  }
  return o;
}

double filip_k_rect(const FilipBound& b, Interval u, Interval v, KNorm norm) {
  const PatchRange ou = patch_range(b.breaks_u, b.c1_u, u);
  const PatchRange ov = patch_range(b.breaks_v, b.c1_v, v);
  if (ou.kink || ov.kink) return kInf;
  SecondDerivativeBounds mx;
  for (size_t pv = ov.first; pv <= ov.last; ++pv) {
    for (size_t pu = ou.first; pu <= ou.last; ++pu) mx = max_of(mx, b.patch(pu, pv));
  }
  return filip_k(mx, u.width(), v.width(), norm);
}

double filip_k_cell(const FilipBound& b, int n, int m, int i, int j, KNorm norm) {
  const double hu = b.domain_u.width() / n, hv = b.domain_v.width() / m;
  const Interval u{b.domain_u.min + i * hu, b.domain_u.min + (i + 1) * hu};
  const Interval v{b.domain_v.min + j * hv, b.domain_v.min + (j + 1) * hv};
  return filip_k_rect(b, u, v, norm);
}

double filip_k_grid(const FilipBound& b, int n, int m, KNorm norm) {
  if (b.c1()) return filip_k(b.whole, b.domain_u.width() / n, b.domain_v.width() / m, norm);
  double k = 0.0;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) k = std::max(k, filip_k_cell(b, n, m, i, j, norm));
  }
  return k;
}

GridChoice choose_grid(const FilipBound& b, double tolerance, int max_cells, KNorm norm) {
  const double a = b.domain_u.width(), c = b.domain_v.width();
  const Ms M = pick(b.whole, norm);
  GridChoice best{max_cells, max_cells, 0.0};
  long long best_cells = static_cast<long long>(max_cells) * max_cells + 1;
  for (int n = 1; n <= max_cells && n < best_cells; ++n) {
    const double hu = a / n;
    const double c0 = 0.125 * hu * hu * M.m1 - tolerance;
    if (c0 > 0) continue;
    // (c^2 M3 / 8) t^2 + (hu c M2 / 4) t + c0 <= 0 for t = 1/m: largest admissible t.
    const double qa = 0.125 * c * c * M.m3, qb = 0.25 * hu * c * M.m2;
    double m_needed = 1.0;
    if (qa > 0 || qb > 0) {
      const double t = qa > 0 ? (-qb + std::sqrt(qb * qb - 4 * qa * c0)) / (2 * qa) : -c0 / qb;
      m_needed = t > 0 ? std::ceil(1.0 / t) : kInf;
    }
    if (!(m_needed <= max_cells)) continue;
    int m = std::max(1, static_cast<int>(m_needed));
    while (m < max_cells && filip_k(b.whole, hu, c / m, norm) > tolerance) ++m;  // guard against rounding in the root
    if (static_cast<long long>(n) * m < best_cells) {
      best_cells = static_cast<long long>(n) * m;
      best = {n, m, 0.0};
    }
  }
  best.k = filip_k_grid(b, best.n, best.m, norm);
  return best;
}

}  // namespace nurbs
