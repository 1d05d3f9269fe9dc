#pragma once
/// \file placement.h
/// Where model B sits: rotated by `deg` degrees about `axis` through the origin, then moved by
/// `move`, exactly the motion `nurbsgl clearance A B --rotate-b AX,AY,AZ,DEG --move-b DX,DY,DZ`
/// builds (nurbs/rigid_motion.h, shared with cli/cmd_clearance.cpp), so the viewer's readout can be
/// checked against the CLI.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <string>

#include "nurbs/rigid_motion.h"

namespace viewer {

struct Placement {
  glm::dvec3 move{0.0};
  glm::dvec3 axis{0.0, 0.0, 1.0};  ///< any length > 0
  double deg = 0.0;

  /// translate(move) * rotate(deg, axis), built as the CLI builds it (bit for bit the same matrix).
  [[nodiscard]] glm::dmat4 matrix() const;
  /// Turns B by `deg` degrees about `axis` through the point `pivot` of B's own frame (e.g. its
  /// centre), keeping that point where it is.
  void rotate_about(const glm::dvec3& pivot, const glm::dvec3& axis, double deg);
  /// The CLI options giving this placement: "--rotate-b AX,AY,AZ,DEG --move-b DX,DY,DZ" (the
  /// rotation left out at 0 degrees), numbers with `digits` significant digits (17: exact doubles).
  [[nodiscard]] std::string cli_arguments(int digits = 9) const;
};

using nurbs::parse_numbers;  // "X,Y,Z" (or with spaces), exactly `count` finite numbers

}  // namespace viewer
