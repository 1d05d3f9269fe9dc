#pragma once
/// \file rigid_motion.h
/// The rigid motion of a second model as `nurbsgl clearance` and the viewer take it: a rotation by
/// DEG degrees about an axis through the origin, then a move; and the number lists it is written
/// in ("1,2,3" or "1 2 3").
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <string>

namespace nurbs {

/// Largest rotation angle in degrees (either sign): at 1e6 degrees one unit in the last place is
/// 1e-10 degrees; far beyond, the angle modulo 360 is rounding noise.
inline constexpr double kMaxDegrees = 1e6;

/// Rotation by `deg` degrees about `axis` (through the origin), then the move `move`. A zero axis
/// is only allowed with deg = 0; a non-finite move or axis, or an angle not within +-kMaxDegrees,
/// is refused too (std::invalid_argument saying which).
[[nodiscard]] glm::dmat4 rigid_motion(const glm::dvec3& move, const glm::dvec3& axis, double deg);

/// Exactly `count` finite numbers separated by commas or spaces into out[0 .. count-1]; false
/// (out unspecified) otherwise.
[[nodiscard]] bool parse_numbers(const std::string& text, int count, double* out);

}  // namespace nurbs
