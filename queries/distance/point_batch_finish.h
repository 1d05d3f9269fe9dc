#pragma once
/// \file point_batch_finish.h
/// Step 3 of the batched point projection (point_batch.h), per point on the CPU in double: from the
/// best cell of each atlas (the GPU pass's or its twin's) to the answer. The winning cell's two
/// triangles and their closest point, its (u, v) and face, the trim test (§5.3) with the cell's
/// closest material point, the best-first search again where the cell holds no material in double,
/// and the refinement of Search::CoarseToFine models (and of answers beyond a refine tolerance).
#include <glm/vec3.hpp>
#include <vector>

#include "queries/distance/point_batch_geometry.h"
#include "queries/distance/point_distance.h"

namespace queries {

class BatchFinish {
 public:
  /// `trim_on_gpu`: whether the cells of `best` carry the material part of trimmed cells (PointBatch's
  /// set_trim_on_gpu); `refine_to` > 0: answers whose bound exceeds it are refined (set_refine_tolerance).
  BatchFinish(const BatchGeometry& g, bool trim_on_gpu, double refine_to)
      : g_(g), trim_on_gpu_(trim_on_gpu), refine_to_(refine_to) {}

  /// The answer for p from the best cell of each atlas; counts the points searched again
  /// (fallbacks) and those whose winner is trimmed. Thread-safe once the CPU pyramids exist when
  /// a face is trimmed. `within` > 0: only a point nearer than it is wanted.
  PointDistance finish(const glm::dvec3& p, const std::vector<BatchCell>& best, long long& fallbacks,
                       long long& trimmed, double within = 0.0) const;
  /// Best first over every atlas's pyramid in double, a triangle point in a trimmed region discarded.
  [[nodiscard]] PointDistance search_material(const glm::dvec3& p, double within = 0.0) const;
  /// The closest material point to p of the cell at texel (x, y) of atlas a, in double: a triangle's
  /// closest point when material, else the closest point of the cell's trim pieces; found = false
  /// when the cell holds no material.
  [[nodiscard]] PointDistance material_cell(const glm::dvec3& p, size_t a, int x, int y) const;
  /// The closest point to p of the cell at texel (x, y) of atlas a: of its closer triangle, or of
  /// `triangle` 0 (corners 0, 1, 3) or 1 (0, 3, 2) alone; `trim_edge`: classify its corners.
  [[nodiscard]] PointDistance cell_result(const glm::dvec3& p, size_t a, int x, int y, bool trim_edge = true,
                                          int triangle = -1) const;
  /// Search::CoarseToFine: the answer for p refined from `start` (finish's material point) to
  /// `tolerance`; `within` as in finish.
  [[nodiscard]] PointDistance refine(const glm::dvec3& p, const PointDistance& start, double within,
                                     double tolerance) const;

 private:
  [[nodiscard]] bool material(const PointDistance& r) const;  ///< is_material of r.uv on r.face
  /// The cells (of every atlas) whose grown boxes lie within `upper` of p, best first; `upper` is
  /// lowered on the way by the material corners met.
  void refine_candidates(const glm::dvec3& p, double& upper, std::vector<FaceCell>& out) const;

  const BatchGeometry& g_;
  bool trim_on_gpu_;
  double refine_to_;
};

}  // namespace queries
