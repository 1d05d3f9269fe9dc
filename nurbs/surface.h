#pragma once
/// \file surface.h
/// A tensor-product (rational) B-spline surface: plain data, the flat table every other module
/// (CPU evaluation, Filip bound, GPU upload) reads.
#include <glm/vec3.hpp>
#include <vector>

namespace nurbs {

struct Surface {
  int degree_u = 0;
  int degree_v = 0;
  int count_u = 0;              ///< control points along u
  int count_v = 0;              ///< control points along v
  std::vector<double> knots_u;  ///< size count_u + degree_u + 1
  std::vector<double> knots_v;  ///< size count_v + degree_v + 1
  /// Euclidean control points, row-major with u fastest: point(i, j) = points[j * count_u + i].
  std::vector<glm::dvec3> points;
  /// Empty = polynomial; else same layout as points, every weight > 0.
  std::vector<double> weights;

  [[nodiscard]] bool rational() const { return !weights.empty(); }
  [[nodiscard]] const glm::dvec3& point(int i, int j) const { return points[static_cast<size_t>(j) * count_u + i]; }
  [[nodiscard]] double weight(int i, int j) const {
    return weights.empty() ? 1.0 : weights[static_cast<size_t>(j) * count_u + i];
  }
};

}  // namespace nurbs
