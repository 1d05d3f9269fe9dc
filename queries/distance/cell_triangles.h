#pragma once
/// \file cell_triangles.h
/// The split of a grid cell into two triangles: one rule for every path. Corner k of cell (i, j)
/// lies at (u_{i + (k & 1)}, v_{j + (k >> 1)}); triangle 0 is corners (0, 1, 3), triangle 1 is
/// corners (0, 3, 2): the (i, j)-(i+1, j+1) diagonal. Theorem 1 of Krishnamurthy et al. bounds the
/// distance from the surface over the cell to these triangles by K_e, so the GPU passes and their
/// CPU twins split alike (glsl/distance/point_batch.frag and glsl/distance/point_batch_trim.frag: s >= t on triangle
/// 0, t > s on triangle 1, (s, t) the unit-cell coordinates).
#include <array>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace queries {

/// The corners of each triangle of a cell.
inline constexpr int kCellTriangle[2][3] = {{0, 1, 3}, {0, 3, 2}};

/// A cell's two triangles in space and in (u, v).
struct CellTriangles {
  glm::dvec3 p[2][3];
  glm::dvec2 uv[2][3];
  /// The cell's corners in the order above.
  [[nodiscard]] std::array<glm::dvec3, 4> corners() const { return {p[0][0], p[0][1], p[1][2], p[0][2]}; }
  /// (u, v) of the point with barycentric weights w in triangle t.
  [[nodiscard]] glm::dvec2 uv_at(int t, const glm::dvec3& w) const {
    return w.x * uv[t][0] + w.y * uv[t][1] + w.z * uv[t][2];
  }
};

/// (u, v) of corner k of the cell [u0, u1] x [v0, v1].
[[nodiscard]] inline glm::dvec2 cell_corner_uv(int k, double u0, double u1, double v0, double v1) {
  return {k & 1 ? u1 : u0, k & 2 ? v1 : v0};
}

/// The triangles of the cell [u0, u1] x [v0, v1] whose corners (in the order above) are `corner`.
[[nodiscard]] inline CellTriangles cell_triangles(const glm::dvec3 corner[4], double u0, double u1, double v0,
                                                  double v1) {
  CellTriangles t;
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) {
      t.p[k][c] = corner[kCellTriangle[k][c]];
      t.uv[k][c] = cell_corner_uv(kCellTriangle[k][c], u0, u1, v0, v1);
    }
  return t;
}

}  // namespace queries
