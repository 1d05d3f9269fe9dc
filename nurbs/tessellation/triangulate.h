#pragma once
/// \file triangulate.h
/// §7 of Balázs, Guthe and Klein (WSCG 2004): triangulation of the material polygons of §6 in the
/// (u, v) plane. Convex polygons (cells with T-junction points) get the paper's linear-time
/// upper-left zipper; non-convex ones (with trim edges) the O(n log n) method of Garey, Johnson,
/// Preparata and Tarjan (1978): partition into y-monotone pieces, then triangulate each piece.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/tessellation/half_edge_trim.h"

namespace nurbs::tess {

struct TriangulationStats {
  int convex_polygons = 0;       ///< triangulated by the §7 zipper
  int nonconvex_polygons = 0;    ///< triangulated by monotone partition (marked and failing the convexity check)
  int monotone_pieces = 0;       ///< y-monotone pieces produced by the partition
  int degenerate_triangles = 0;  ///< zero-area triangles that could not be avoided (collinear vertices)
};

/// O(n) convexity check of §7: no right turn between consecutive edges. Collinear points are allowed
/// where the zero is exact (axis-parallel cell edges); a turn whose sign double arithmetic cannot
/// decide (orient_sign == 0, see triangulate_detail.h) counts as non-convex.
/// `polygon` indexes `vertices`, counter-clockwise.
[[nodiscard]] bool is_convex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon);

/// §7's linear-time triangulation of a convex polygon: start at the upper-left vertex (largest v,
/// then smallest u) with its two neighbours, then advance along both chains, each time taking the
/// upper-left of the two next vertices (the other one when that would give a zero-area triangle).
/// Appends n - 2 counter-clockwise triangles of vertex indices.
void triangulate_convex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon,
                        std::vector<glm::ivec3>& out, TriangulationStats* stats = nullptr);

/// [Gar78]: a simple counter-clockwise polygon (any shape, collinear points allowed) is split by
/// diagonals into y-monotone pieces with a plane sweep (vertex order: larger v first, then smaller u),
/// then each piece is triangulated with the stack algorithm. Appends n - 2 counter-clockwise triangles.
void triangulate_nonconvex(const std::vector<glm::dvec2>& vertices, const std::vector<int>& polygon,
                           std::vector<glm::ivec3>& out, TriangulationStats* stats = nullptr);

/// Triangles of every polygon of `polys` (indices into polys.vertices), counter-clockwise in (u, v).
/// A polygon without marked edge, or one passing is_convex, goes to triangulate_convex; the others
/// to triangulate_nonconvex.
[[nodiscard]] std::vector<glm::ivec3> triangulate_polygons(const TrimmedPolygons& polys,
                                                           TriangulationStats* stats = nullptr);

}  // namespace nurbs::tess
