#include "nurbs/surface_project.h"

#include <algorithm>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "nurbs/surface_eval.h"

namespace nurbs {

glm::dvec2 project_point(const Surface& s, const glm::dvec3& p, glm::dvec2 uv, int iterations) {
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  const glm::dvec2 lo(du.min, dv.min), hi(du.max, dv.max);
  double f = glm::length(surface_point(s, uv.x, uv.y) - p);
  for (int it = 0; it < iterations; ++it) {
    const SurfaceDerivatives d = surface_derivatives(s, uv.x, uv.y);
    const glm::dvec3 r = d.s - p;
    const double gu = glm::dot(r, d.su), gv = glm::dot(r, d.sv);
    const double huu = glm::dot(d.su, d.su) + glm::dot(r, d.suu), hvv = glm::dot(d.sv, d.sv) + glm::dot(r, d.svv);
    const double huv = glm::dot(d.su, d.sv) + glm::dot(r, d.suv), det = huu * hvv - huv * huv;
    glm::dvec2 step = det > 0 && huu > 0
                          ? glm::dvec2((hvv * gu - huv * gv) / det, (huu * gv - huv * gu) / det)
                          : glm::dvec2(gu, gv) / std::max(glm::dot(d.su, d.su) + glm::dot(d.sv, d.sv), 1e-300);
    bool moved = false;
    for (int half = 0; half < 20 && !moved; ++half, step *= 0.5) {
      const glm::dvec2 next = glm::clamp(uv - step, lo, hi);
      const double fn = glm::length(surface_point(s, next.x, next.y) - p);
      if (fn < f) uv = next, f = fn, moved = true;
    }
    if (!moved) break;
  }
  return uv;
}

}  // namespace nurbs
