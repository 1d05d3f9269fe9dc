#pragma once
/// \file surface_project.h
/// Local closest point of a surface to a point (point inversion, The NURBS Book §6.1), the upper-bound
/// step of the distance refinement (queries/distance/refine.h) and the deviation check of the tessellation.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "nurbs/surface.h"

namespace nurbs {

/// Local closest point of surface s to p, starting from (u, v): projected Newton on |S(u, v) - p|^2
/// (a gradient step where the Hessian is not positive definite), clamped to the domain, each step
/// halved until it lowers the distance. Every value it returns is a true surface point no farther
/// from p than the start, so it can only improve an upper bound. Returns the final (u, v).
[[nodiscard]] glm::dvec2 project_point(const Surface& s, const glm::dvec3& p, glm::dvec2 uv, int iterations);

}  // namespace nurbs
