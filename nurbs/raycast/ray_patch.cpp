#include "nurbs/raycast/ray_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <glm/geometric.hpp>

#include "nurbs/surface_eval.h"

namespace nurbs::ray {
namespace {

/// Möller-Trumbore; (b1, b2) barycentrics of v1, v2. False when parallel or outside (with slack).
bool ray_triangle(const Ray& ray, const glm::dvec3& v0, const glm::dvec3& v1, const glm::dvec3& v2, double& t,
                  double& b1, double& b2) {
  const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0, p = glm::cross(ray.direction, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-300) return false;
  const glm::dvec3 s = ray.origin - v0, q = glm::cross(s, e1);
  b1 = glm::dot(s, p) / det;
  b2 = glm::dot(ray.direction, q) / det;
  t = glm::dot(e2, q) / det;
  constexpr double kSlack = 1e-9;  // a ray through a shared triangle edge must find one of the two
  return b1 >= -kSlack && b2 >= -kSlack && b1 + b2 <= 1.0 + kSlack;
}

/// Solves J x = r for 2 x 2 J; false when singular.
bool solve2(double a, double b, double c, double d, glm::dvec2 r, glm::dvec2& x) {
  const double det = a * d - b * c;
  const double scale = std::abs(a * d) + std::abs(b * c);
  if (!(std::abs(det) > 1e-14 * scale) || !std::isfinite(det)) return false;
  x = {(d * r.x - b * r.y) / det, (a * r.y - c * r.x) / det};
  return true;
}

}  // namespace

RayPlanes ray_planes(const Ray& ray) {
  const glm::dvec3 d = ray.direction;
  glm::dvec3 axis(0.0);  // the coordinate axis least aligned with d
  const glm::dvec3 a = glm::abs(d);
  axis[a.x <= a.y && a.x <= a.z ? 0 : (a.y <= a.z ? 1 : 2)] = 1.0;
  RayPlanes p;
  p.n1 = glm::normalize(glm::cross(d, axis));
  p.n2 = glm::cross(d, p.n1);
  p.d1 = -glm::dot(p.n1, ray.origin);
  p.d2 = -glm::dot(p.n2, ray.origin);
  return p;
}

int initial_guesses(const BicubicPatch& patch, const Ray& ray, glm::dvec2* out, int max_out) {
  struct Start {
    double t;
    glm::dvec2 st;
  };
  std::array<Start, 18> found{};
  int n = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const glm::dvec3 &p00 = patch.p[4 * j + i], &p10 = patch.p[4 * j + i + 1];
      const glm::dvec3 &p01 = patch.p[4 * (j + 1) + i], &p11 = patch.p[4 * (j + 1) + i + 1];
      double t, b1, b2;
      // Triangle (p00, p10, p11): local (a, b) = (b1 + b2, b2); triangle (p00, p11, p01): (b1, b1 + b2).
      if (ray_triangle(ray, p00, p10, p11, t, b1, b2)) found[n++] = {t, {(i + b1 + b2) / 3.0, (j + b2) / 3.0}};
      if (ray_triangle(ray, p00, p11, p01, t, b1, b2)) found[n++] = {t, {(i + b1) / 3.0, (j + b1 + b2) / 3.0}};
    }
  std::sort(found.begin(), found.begin() + n, [](const Start& a, const Start& b) { return a.t < b.t; });
  int m = 0;
  for (int k = 0; k < n && m < max_out; ++k) {
    bool dup = false;  // a crossing on a shared triangle edge is found twice
    for (int q = 0; q < m; ++q) dup = dup || glm::length(out[q] - found[k].st) < 1e-6;
    if (!dup) out[m++] = glm::clamp(found[k].st, 0.0, 1.0);
  }
  if (m == 0 && max_out > 0) out[m++] = glm::dvec2(0.5);  // §3.3 fallback: the patch centre
  return m;
}

PatchHit newton_patch(const BicubicPatch& patch, const Ray& ray, const RayPlanes& planes, glm::dvec2 start,
                      const RayPatchOptions& options) {
  const double scale = options.param_scale;
  glm::dvec2 x = scale * start;  // (U, V) = scale (s, t)
  PatchHit hit;
  PatchPoint e = evaluate_patch(patch, start.x, start.y);
  glm::dvec2 r(glm::dot(planes.n1, e.s) + planes.d1, glm::dot(planes.n2, e.s) + planes.d2);
  for (int it = 0; it < options.iterations; ++it) {
    // Eq. 4 wrt (U, V): the (s, t) Jacobian divided by the scale.
    glm::dvec2 dx;
    if (!solve2(glm::dot(planes.n1, e.ss) / scale, glm::dot(planes.n1, e.st) / scale, glm::dot(planes.n2, e.ss) / scale,
                glm::dot(planes.n2, e.st) / scale, r, dx))
      break;
    x = glm::clamp(x - dx, -scale, 2.0 * scale);  // keep the polynomial evaluation bounded
    e = evaluate_patch(patch, x.x / scale, x.y / scale);
    r = {glm::dot(planes.n1, e.s) + planes.d1, glm::dot(planes.n2, e.s) + planes.d2};
  }
  hit.st = x / scale;
  hit.point = e.s;
  hit.t = glm::dot(e.s - ray.origin, ray.direction);
  const double diag = glm::length(patch.box_max - patch.box_min);
  if (!(glm::length(r) <= options.residual * std::max(diag, 1e-300))) {
    hit.outcome = PatchOutcome::NoConvergence;
  } else {
    const double m = options.edge_margin;
    const bool inside = hit.st.x >= -m && hit.st.x <= 1.0 + m && hit.st.y >= -m && hit.st.y <= 1.0 + m;
    hit.outcome = inside ? PatchOutcome::Converged : PatchOutcome::Outside;
  }
  return hit;
}

int intersect_patch(const BicubicPatch& patch, const Ray& ray, const RayPatchOptions& options, double t_min,
                    std::array<PatchHit, 4>& out) {
  std::array<glm::dvec2, 4> starts;
  const int ns = initial_guesses(patch, ray, starts.data(), 4);
  const RayPlanes planes = ray_planes(ray);
  const double diag = glm::length(patch.box_max - patch.box_min);
  int n = 0;
  for (int k = 0; k < ns; ++k) {
    const PatchHit h = newton_patch(patch, ray, planes, starts[k], options);
    if (h.outcome != PatchOutcome::Converged || !(h.t > t_min)) continue;
    bool dup = false;
    for (int q = 0; q < n; ++q) dup = dup || std::abs(out[q].t - h.t) <= 1e-9 * diag;
    if (!dup) out[n++] = h;
  }
  std::sort(out.begin(), out.begin() + n, [](const PatchHit& a, const PatchHit& b) { return a.t < b.t; });
  return n;
}

namespace {

/// x in [d.min, d.max]: across a seam on the other side, else clamped.
double into(double x, const Interval& d, bool seam) {
  if (seam && (x < d.min || x > d.max) && d.width() > 0.0) x -= std::floor((x - d.min) / d.width()) * d.width();
  return std::clamp(x, d.min, d.max);
}

/// refine_on_surface with `eval(u, v)` giving S, Su, Sv.
template <class Eval>
ExactHit refine_with(const Eval& eval, const Surface& surface, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv,
                     int iterations, double tolerance, Seams seams) {
  const Interval du = surface_domain_u(surface), dv = surface_domain_v(surface);
  const auto inside = [&](glm::dvec2 p) { return glm::dvec2(into(p.x, du, seams.u), into(p.y, dv, seams.v)); };
  ExactHit out;
  uv = inside(uv);
  SurfaceTangents d = eval(uv.x, uv.y);
  glm::dvec2 r(glm::dot(planes.n1, d.s) + planes.d1, glm::dot(planes.n2, d.s) + planes.d2);
  double norm = glm::length(r);
  for (int it = 0; it < iterations && norm > 1e-6 * tolerance; ++it) {
    glm::dvec2 dx;
    if (!solve2(glm::dot(planes.n1, d.su), glm::dot(planes.n1, d.sv), glm::dot(planes.n2, d.su),
                glm::dot(planes.n2, d.sv), r, dx))
      break;
    const glm::dvec2 next = inside(uv - dx);
    const SurfaceTangents e = eval(next.x, next.y);
    const glm::dvec2 re(glm::dot(planes.n1, e.s) + planes.d1, glm::dot(planes.n2, e.s) + planes.d2);
    const double next_norm = glm::length(re);
    // Within the tolerance, a step that no longer halves |R| has reached the rounding floor: the
    // better point stays. (Farther out, Newton may still be on its way.)
    const bool floor = norm <= tolerance && !(next_norm <= 0.5 * norm);
    if (!floor || next_norm < norm) uv = next, d = e, r = re, norm = next_norm;
    if (floor) break;
  }
  out.uv = uv;
  out.point = d.s;
  out.t = glm::dot(d.s - ray.origin, ray.direction);
  out.ok = norm <= tolerance;
  return out;
}

}  // namespace

ExactHit refine_on_surface(const Surface& surface, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv,
                           int iterations, double tolerance, Seams seams) {
  return refine_with([&](double u, double v) { return surface_tangents(surface, u, v); }, surface, ray, planes, uv,
                     iterations, tolerance, seams);
}

ExactHit refine_on_surface(const BezierForm& form, const Surface& surface, const Ray& ray, const RayPlanes& planes,
                           glm::dvec2 uv, int iterations, double tolerance, Seams seams) {
  if (form.empty()) return refine_on_surface(surface, ray, planes, uv, iterations, tolerance, seams);
  return refine_with([&](double u, double v) { return form.tangents(u, v); }, surface, ray, planes, uv, iterations,
                     tolerance, seams);
}

Seams surface_seams(const Surface& s, double tolerance) {
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  Seams out{true, true};
  for (int k = 0; k <= 8; ++k) {
    const double u = du.min + du.width() * k / 8.0, v = dv.min + dv.width() * k / 8.0;
    out.u = out.u && glm::length(surface_point(s, du.min, v) - surface_point(s, du.max, v)) <= tolerance;
    out.v = out.v && glm::length(surface_point(s, u, dv.min) - surface_point(s, u, dv.max)) <= tolerance;
  }
  return out;
}

glm::dvec2 uv_rate(const glm::dvec3& su, const glm::dvec3& sv, const glm::dvec3& direction) {
  // [Su Sv] w = direction's part along the surface, in least squares (the normal part drops out).
  const double e = glm::dot(su, su), f = glm::dot(su, sv), g = glm::dot(sv, sv);
  const double det = e * g - f * f;
  if (!(std::abs(det) > 0.0)) return glm::dvec2(std::numeric_limits<double>::quiet_NaN());
  const double bu = glm::dot(su, direction), bv = glm::dot(sv, direction);
  return {(g * bu - f * bv) / det, (e * bv - f * bu) / det};
}

ExactHit earlier_root(const BezierForm& form, const Surface& surface, const Ray& ray, const RayPlanes& planes,
                      const ExactHit& found, int iterations, double tolerance, Seams seams) {
  const SurfaceDerivatives d = surface_derivatives(surface, found.uv.x, found.uv.y);
  const glm::dvec3 cross = glm::cross(d.su, d.sv);
  const double len = glm::length(cross);
  if (!(len > 0.0)) return {};
  const glm::dvec3 n = cross / len;
  const double c = glm::dot(ray.direction, n);
  const glm::dvec2 w = uv_rate(d.su, d.sv, ray.direction);
  if (!(w == w)) return {};
  // Over the tangent plane the ray rises c s and the surface (1/2) q s^2 (q: the second form on w):
  // they meet again at s = 2 c / q, before the hit when s < 0.
  const double q = glm::dot(d.suu, n) * w.x * w.x + 2.0 * glm::dot(d.suv, n) * w.x * w.y + glm::dot(d.svv, n) * w.y * w.y;
  if (!(q != 0.0)) return {};
  const double s = 2.0 * c / q;
  if (!(s < 0.0)) return {};
  ExactHit best;
  for (const double k : {1.0, 0.5, 1.5}) {
    const glm::dvec2 start = found.uv + k * s * w;
    const ExactHit h = refine_on_surface(form, surface, ray, planes, start, iterations, tolerance, seams);
    if (h.ok && h.t < found.t - 1e-9 * std::abs(s) && (!best.ok || h.t < best.t)) best = h;
  }
  return best;
}

}  // namespace nurbs::ray
