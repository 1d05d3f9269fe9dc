#include "nurbs/raycast/ray_patch.h"

#include <algorithm>
#include <cmath>
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

/// refine_on_surface with `eval(u, v)` giving S, Su, Sv.
template <class Eval>
ExactHit refine_with(const Eval& eval, const Surface& surface, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv,
                     int iterations, double tolerance) {
  const Interval du = surface_domain_u(surface), dv = surface_domain_v(surface);
  const glm::dvec2 lo(du.min, dv.min), hi(du.max, dv.max);
  ExactHit out;
  uv = glm::clamp(uv, lo, hi);
  SurfaceTangents d = eval(uv.x, uv.y);
  glm::dvec2 r(glm::dot(planes.n1, d.s) + planes.d1, glm::dot(planes.n2, d.s) + planes.d2);
  double norm = glm::length(r);
  for (int it = 0; it < iterations && norm > 1e-6 * tolerance; ++it) {
    glm::dvec2 dx;
    if (!solve2(glm::dot(planes.n1, d.su), glm::dot(planes.n1, d.sv), glm::dot(planes.n2, d.su),
                glm::dot(planes.n2, d.sv), r, dx))
      break;
    const glm::dvec2 next = glm::clamp(uv - dx, lo, hi);
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
                           int iterations, double tolerance) {
  return refine_with([&](double u, double v) { return surface_tangents(surface, u, v); }, surface, ray, planes, uv,
                     iterations, tolerance);
}

ExactHit refine_on_surface(const BezierForm& form, const Surface& surface, const Ray& ray, const RayPlanes& planes,
                           glm::dvec2 uv, int iterations, double tolerance) {
  if (form.empty()) return refine_on_surface(surface, ray, planes, uv, iterations, tolerance);
  return refine_with([&](double u, double v) { return form.tangents(u, v); }, surface, ray, planes, uv, iterations,
                     tolerance);
}

}  // namespace nurbs::ray
