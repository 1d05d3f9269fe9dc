#include "viewer/placement.h"

#include <fmt/format.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

namespace viewer {

glm::dmat4 Placement::matrix() const {
  return nurbs::rigid_motion(move, glm::length(axis) > 0.0 ? axis : glm::dvec3(0, 0, 1), deg);
}

void Placement::rotate_about(const glm::dvec3& pivot, const glm::dvec3& turn_axis, double turn_deg) {
  if (turn_deg == 0.0 || glm::length(turn_axis) == 0.0) return;
  const glm::dvec3 fixed = glm::dvec3(matrix() * glm::dvec4(pivot, 1.0));
  glm::dquat q = glm::angleAxis(deg * M_PI / 180.0, glm::length(axis) > 0 ? glm::normalize(axis) : glm::dvec3(0, 0, 1));
  q = glm::normalize(glm::angleAxis(turn_deg * M_PI / 180.0, glm::normalize(turn_axis)) * q);
  if (q.w < 0.0) q = -q;  // angle in [0, 180]
  const double angle = glm::angle(q);
  deg = angle * 180.0 / M_PI;
  axis = angle > 1e-12 ? glm::axis(q) : glm::dvec3(0.0, 0.0, 1.0);
  if (angle <= 1e-12) deg = 0.0;
  // Move so that the pivot stays: R' pivot + move' = fixed.
  move = fixed - glm::dvec3(Placement{glm::dvec3(0.0), axis, deg}.matrix() * glm::dvec4(pivot, 1.0));
}

std::string Placement::cli_arguments(int digits) const {
  std::string s;
  if (deg != 0.0)
    s = fmt::format("--rotate-b {:.{}g},{:.{}g},{:.{}g},{:.{}g} ", axis.x, digits, axis.y, digits, axis.z, digits, deg,
                    digits);
  return s + fmt::format("--move-b {:.{}g},{:.{}g},{:.{}g}", move.x, digits, move.y, digits, move.z, digits);
}

}  // namespace viewer
