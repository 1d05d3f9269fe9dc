#pragma once
/// \file material_distance.h
/// Distances on the material part of a grid cell's triangles (Krishnamurthy et al. §5.3: "if the
/// point lies inside the trimmed region, we discard the point and continue the search"). The
/// faithful leaf passes (point_distance.cpp, clearance.cpp) take a triangle's closest point when it
/// is material; when it is trimmed, the search goes on over the material part of the triangle.
///
/// Why the trim pieces suffice: the distance is convex on a triangle (on a pair of triangles). If
/// the closest material point lay inside the material away from every trim edge, it would be a
/// local, hence the global, minimum over the whole triangle, which is trimmed. So it lies on a
/// trim edge piece inside the triangle (for a pair: on a piece of one side, the other side's point
/// either inside its material or on one of its pieces). Where several points tie, the set of
/// minima is convex and meets a trim edge, so the value is the same. The pieces are straight on
/// the triangles (TrimEdges::pieces), so the answer is exact for the piecewise-linear interpolant
/// and Theorem 1's bound K holds for it as for an untrimmed face, not only the bounding box's
/// size that the paper states for answers on a trim edge.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <vector>

#include "queries/distance/point_batch_trim.h"
#include "queries/distance/prepared_model.h"

namespace queries {

/// The trim edges of a model's faces, each face's indexed when first asked for (the faithful leaf
/// passes need few faces' of a large model).
class FaceTrimEdges {
 public:
  explicit FaceTrimEdges(const PreparedModel& m) : m_(m) {}
  /// Null for an untrimmed face.
  const TrimEdges* operator()(int face);

 private:
  const PreparedModel& m_;
  std::map<int, TrimEdges> index_;
};

/// One triangle of a grid cell: its corners, their parameters and, for a trimmed face, the trim
/// edges of its face and their pieces inside the cell (null for an untrimmed face); only the
/// pieces on this triangle (TrimPiece::triangle) count.
struct MaterialTriangle {
  const glm::dvec3* p = nullptr;   ///< 3 corners
  const glm::dvec2* uv = nullptr;  ///< their (u, v)
  int triangle = 0;                ///< 0: the cell's corners (0, 1, 3); 1: (0, 3, 2)
  const TrimEdges* trim = nullptr;
  const std::vector<TrimPiece>* pieces = nullptr;
  /// Whether (u, v) of a point inside the triangle is material.
  [[nodiscard]] bool material(glm::dvec2 at) const { return trim == nullptr || trim->is_material(at); }
};

/// Closest points of the material parts of two triangles.
struct MaterialPair {
  bool found = false;  ///< false when neither triangle has a material point (the distance is then +inf)
  double distance = 0.0;
  glm::dvec3 point_a{0.0}, point_b{0.0};
  glm::dvec2 uv_a{0.0}, uv_b{0.0};
};

/// The least distance between material points of a and b below `below` (found = false when none
/// is below it). Trim-edge points count where material lies beside their edge (TrimEdges::pieces).
[[nodiscard]] MaterialPair material_pair_distance(const MaterialTriangle& a, const MaterialTriangle& b, double below);

}  // namespace queries
