#pragma once
/// \file camera.h
/// An orbit camera around a target point, z up: left drag orbits, right or middle drag pans, the
/// wheel zooms. Double precision; the matrices go to the shaders as float.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace viewer {

/// A ray in world space (direction unit length).
struct Ray {
  glm::dvec3 origin{0.0}, direction{0.0, 0.0, -1.0};
};

class Camera {
 public:
  /// Looks at the box [lo, hi] from the current direction, the whole box in view in a region of
  /// the window `aspect` = width / height wide.
  void frame(const glm::dvec3& lo, const glm::dvec3& hi, double aspect = 1.0);
  /// Moves the image's centre right by `ndc_x` (normalised device units): the scene then sits in
  /// the part of the window the panel leaves free.
  void set_center_offset(double ndc_x) { offset_x_ = ndc_x; }
  /// Mouse deltas in window pixels; `height` is the window height (pan moves the point under the
  /// cursor with it).
  void orbit(double dx, double dy);
  void pan(double dx, double dy, double height);
  void zoom(double wheel_steps);

  [[nodiscard]] glm::dvec3 eye() const;
  [[nodiscard]] glm::dmat4 view() const;
  [[nodiscard]] glm::dmat4 projection(double aspect) const;
  /// Camera axes in world space (right, up), for moving things in the view plane.
  [[nodiscard]] glm::dvec3 right() const;
  [[nodiscard]] glm::dvec3 up() const;
  /// World units per window pixel at the target's depth.
  [[nodiscard]] double pixel_size(double height) const;
  /// The ray through window pixel (x, y) (origin top left) of a width x height window.
  [[nodiscard]] Ray ray(double x, double y, double width, double height) const;

 private:
  glm::dvec3 target_{0.0};
  double distance_ = 10.0;
  double yaw_ = -1.0;    ///< radians, about z
  double pitch_ = 0.45;  ///< radians, above the xy plane
  double radius_ = 1.0;  ///< of the framed box, for the clip planes
  double offset_x_ = 0.0;
  static constexpr double kFovY = 0.6;  ///< radians
};

}  // namespace viewer
