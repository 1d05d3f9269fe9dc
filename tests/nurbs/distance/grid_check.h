#pragma once
/// \file grid_check.h
/// Independent check of a certified grid: dense samples of the surface, in double, inside
/// a cell, against the grid's two triangles (split along the (i, j)-(i+1, j+1) diagonal) and the
/// bilinear interpolant of its four corners. Filip's argument bounds both by the cell's K (per
/// coordinate) and K_e (Euclidean norm).
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/distance/certified_grid.h"
#include "nurbs/surface_eval.h"

namespace grid_check {

/// Largest deviation found in one cell: per coordinate and as a vector length.
struct Deviation {
  double coord = 0.0, norm = 0.0;
};

/// `samples` + 1 points per cell edge (corners included) of cell (i, j) of `g` on surface `s`.
inline Deviation cell_deviation(const nurbs::Surface& s, const nurbs::ParamGrid& g, int i, int j, int samples) {
  const double u0 = g.u[size_t(i)], u1 = g.u[size_t(i) + 1], v0 = g.v[size_t(j)], v1 = g.v[size_t(j) + 1];
  const glm::dvec3 p00 = nurbs::surface_point(s, u0, v0), p10 = nurbs::surface_point(s, u1, v0);
  const glm::dvec3 p01 = nurbs::surface_point(s, u0, v1), p11 = nurbs::surface_point(s, u1, v1);
  Deviation d;
  for (int b = 0; b <= samples; ++b) {
    for (int a = 0; a <= samples; ++a) {
      const double x = double(a) / samples, y = double(b) / samples;
      const glm::dvec3 p = nurbs::surface_point(s, u0 + x * (u1 - u0), v0 + y * (v1 - v0));
      const glm::dvec3 tri = x >= y ? p00 + x * (p10 - p00) + y * (p11 - p10) : p00 + y * (p01 - p00) + x * (p11 - p01);
      const glm::dvec3 bil = (1 - y) * ((1 - x) * p00 + x * p10) + y * ((1 - x) * p01 + x * p11);
      for (const glm::dvec3& e : {p - tri, p - bil}) {
        d.coord = std::max({d.coord, std::abs(e.x), std::abs(e.y), std::abs(e.z)});
        d.norm = std::max(d.norm, glm::length(e));
      }
    }
  }
  return d;
}

}  // namespace grid_check
