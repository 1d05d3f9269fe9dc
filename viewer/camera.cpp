#include "viewer/camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace viewer {

void Camera::frame(const glm::dvec3& lo, const glm::dvec3& hi, double aspect) {
  target_ = 0.5 * (lo + hi);
  radius_ = std::max(0.5 * glm::length(hi - lo), 1e-9);
  const double half_fov = std::min(0.5 * kFovY, std::atan(std::tan(0.5 * kFovY) * std::max(aspect, 0.1)));
  distance_ = 1.05 * radius_ / std::sin(half_fov);
}

void Camera::orbit(double dx, double dy) {
  yaw_ -= 0.01 * dx;
  pitch_ = std::clamp(pitch_ + 0.01 * dy, -1.55, 1.55);
}

void Camera::pan(double dx, double dy, double height) {
  const double s = pixel_size(height);
  target_ += s * (-dx * right() + dy * up());
}

void Camera::zoom(double wheel_steps) {
  distance_ = std::clamp(distance_ * std::pow(0.88, wheel_steps), 1e-6 * radius_, 1e3 * radius_);
}

glm::dvec3 Camera::eye() const {
  const glm::dvec3 d(std::cos(pitch_) * std::cos(yaw_), std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_));
  return target_ + distance_ * d;
}

glm::dmat4 Camera::view() const { return glm::lookAt(eye(), target_, glm::dvec3(0.0, 0.0, 1.0)); }

glm::dmat4 Camera::projection(double aspect) const {
  // Clip planes around the framed model wherever the eye is: near at most the model's front.
  const double near = std::max(distance_ - 4.0 * radius_, 1e-3 * distance_);
  const double far = distance_ + 4.0 * radius_;
  return glm::translate(glm::dmat4(1.0), glm::dvec3(offset_x_, 0.0, 0.0)) * glm::perspective(kFovY, aspect, near, far);
}

glm::dvec3 Camera::right() const { return glm::normalize(glm::cross(target_ - eye(), glm::dvec3(0.0, 0.0, 1.0))); }

glm::dvec3 Camera::up() const { return glm::normalize(glm::cross(right(), target_ - eye())); }

double Camera::pixel_size(double height) const {
  return 2.0 * distance_ * std::tan(0.5 * kFovY) / std::max(height, 1.0);
}

Ray Camera::ray(double x, double y, double width, double height) const {
  const glm::dmat4 inv = glm::inverse(projection(width / std::max(height, 1.0)) * view());
  const glm::dvec2 ndc(2.0 * x / width - 1.0, 1.0 - 2.0 * y / height);
  glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
  a /= a.w;
  b /= b.w;
  return {glm::dvec3(a), glm::normalize(glm::dvec3(b - a))};
}

}  // namespace viewer
