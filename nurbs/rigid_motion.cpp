#include "nurbs/rigid_motion.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace nurbs {

glm::dmat4 rigid_motion(const glm::dvec3& move, const glm::dvec3& axis, double deg) {
  if (!(std::abs(deg) <= kMaxDegrees))
    throw std::invalid_argument(fmt::format("the angle {:g} is not a finite number of degrees within +-{:g}", deg, kMaxDegrees));
  if (!std::isfinite(move.x) || !std::isfinite(move.y) || !std::isfinite(move.z))
    throw std::invalid_argument("the move is not finite");
  glm::dmat4 m(1.0);
  if (deg != 0.0) {
    // Scaled by its largest component first: the length of a 1e200 or 1e-200 axis over- or underflows.
    const double largest = std::max({std::abs(axis.x), std::abs(axis.y), std::abs(axis.z)});
    if (!std::isfinite(largest)) throw std::invalid_argument("the rotation axis is not finite");
    if (largest == 0.0) throw std::invalid_argument("the rotation axis is zero");
    // The angle reduced modulo 360 exactly (fmod is exact) before it meets pi.
    m = glm::rotate(m, std::fmod(deg, 360.0) * M_PI / 180.0, glm::normalize(axis / largest));
  }
  return glm::translate(glm::dmat4(1.0), move) * m;
}

bool parse_numbers(const std::string& text, int count, double* out) {
  std::string spaced = text;
  for (char& c : spaced)
    if (c == ',') c = ' ';
  std::istringstream in(spaced);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  if (!in.eof() || static_cast<int>(v.size()) != count) return false;
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite(v[size_t(i)])) return false;
    out[i] = v[size_t(i)];
  }
  return true;
}

}  // namespace nurbs
