#include "nurbs/rigid_motion.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace nurbs {

glm::dmat4 rigid_motion(const glm::dvec3& move, const glm::dvec3& axis, double deg) {
  glm::dmat4 m(1.0);
  if (deg != 0.0) {
    if (glm::length(axis) == 0.0) throw std::invalid_argument("the rotation axis is zero");
    m = glm::rotate(m, deg * M_PI / 180.0, glm::normalize(axis));
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
