#pragma once
/// \file intersection.h
/// Beyond the papers: whether two faces whose clearance is within its bound of zero actually meet.
/// From the clearance's closest pair, Newton steps on S_a(u_a, v_a) - M S_b(u_b, v_b) = 0 (three
/// equations in four unknowns: the minimum-norm step, J^T (J J^T)^-1), kept inside both domains;
/// the faces meet where the two points come within `tolerance` of each other and both (u, v) are
/// material by the faces' trim polygons. The point found is a point of both faces up to that
/// tolerance; no point found says nothing (the surfaces may still touch elsewhere).
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>

#include "nurbs/trim_classify.h"
#include "nurbs/trimmed_surface.h"

namespace queries {

struct SurfaceIntersection {
  glm::dvec3 point{0.0};  ///< the midpoint of the two surface points (B's in its moved position)
  glm::dvec2 uv_a{0.0}, uv_b{0.0};
  double residual = 0.0;  ///< |S_a(uv_a) - M S_b(uv_b)|
};

/// A common point of face `a` and face `b` moved by `motion_b`, sought from (uv_a, uv_b); `trim_a`
/// / `trim_b` are the faces' flattened trims (unused for untrimmed faces).
[[nodiscard]] std::optional<SurfaceIntersection> find_intersection(const nurbs::TrimmedSurface& a,
                                                                   const nurbs::TrimPolygons& trim_a, glm::dvec2 uv_a,
                                                                   const nurbs::TrimmedSurface& b,
                                                                   const nurbs::TrimPolygons& trim_b, glm::dvec2 uv_b,
                                                                   const glm::dmat4& motion_b, double tolerance);

}  // namespace queries
