#include "queries/distance/intersection.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "nurbs/surface_eval.h"

namespace queries {

std::optional<SurfaceIntersection> find_intersection(const nurbs::TrimmedSurface& a, const nurbs::TrimPolygons& trim_a,
                                                     glm::dvec2 uv_a, const nurbs::TrimmedSurface& b,
                                                     const nurbs::TrimPolygons& trim_b, glm::dvec2 uv_b,
                                                     const glm::dmat4& motion_b, double tolerance) {
  const nurbs::Interval dua = nurbs::surface_domain_u(a.surface), dva = nurbs::surface_domain_v(a.surface);
  const nurbs::Interval dub = nurbs::surface_domain_u(b.surface), dvb = nurbs::surface_domain_v(b.surface);
  const glm::dmat3 rotation(motion_b);
  for (int step = 0; step < 30; ++step) {
    const nurbs::SurfaceDerivatives sa = nurbs::surface_derivatives(a.surface, uv_a.x, uv_a.y);
    const nurbs::SurfaceDerivatives sb = nurbs::surface_derivatives(b.surface, uv_b.x, uv_b.y);
    const glm::dvec3 pb(motion_b * glm::dvec4(sb.s, 1.0));
    const glm::dvec3 f = sa.s - pb;
    const double residual = glm::length(f);
    if (residual <= tolerance) {
      const bool material = (a.loops.empty() || nurbs::is_material(trim_a, uv_a)) &&
                            (b.loops.empty() || nurbs::is_material(trim_b, uv_b));
      if (!material) return std::nullopt;
      return SurfaceIntersection{0.5 * (sa.s + pb), uv_a, uv_b, residual};
    }
    // J = [S_a,u  S_a,v  -R S_b,u  -R S_b,v] (3 x 4); the minimum-norm step dx = -J^T (J J^T)^-1 f.
    const glm::dvec3 cols[4] = {sa.su, sa.sv, -(rotation * sb.su), -(rotation * sb.sv)};
    glm::dmat3 jjt(0.0);
    for (const glm::dvec3& c : cols) jjt += glm::outerProduct(c, c);
    if (std::abs(glm::determinant(jjt)) < 1e-300) return std::nullopt;  // parallel tangent planes
    const glm::dvec3 y = glm::inverse(jjt) * f;
    uv_a -= glm::dvec2(glm::dot(cols[0], y), glm::dot(cols[1], y));
    uv_b -= glm::dvec2(glm::dot(cols[2], y), glm::dot(cols[3], y));
    uv_a = {std::clamp(uv_a.x, dua.min, dua.max), std::clamp(uv_a.y, dva.min, dva.max)};
    uv_b = {std::clamp(uv_b.x, dub.min, dub.max), std::clamp(uv_b.y, dvb.min, dvb.max)};
  }
  return std::nullopt;
}

}  // namespace queries
