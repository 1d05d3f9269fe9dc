#pragma once
/// \file point_batch_geometry.h
/// What the two halves of the batched point projection (point_batch.h) read after the build: the
/// prepared model, its atlases with their box pyramids and trimmed cells, the faces' trim edges and
/// the bounds' per-face terms. The descent (point_batch_descent.h, the pass's CPU twin) and the
/// finishing (point_batch_finish.h) take it by reference; PointBatch owns it.
#include <glm/vec3.hpp>
#include <vector>

#include "queries/distance/point_batch_atlas.h"
#include "queries/distance/point_batch_trim.h"
#include "queries/distance/prepared_model.h"

namespace queries {

/// Relative float slack of the descent (16 float ulp of |q| + the model's radius).
inline constexpr double kFloatSlack = 0x1.0p-20;
/// Width of the trimmed cells' header and segment textures (glsl/distance/point_batch_trim.frag u_trim_width).
inline constexpr int kTrimTextureWidth = 4096;

/// The boxes of the descent's pyramid: axis-aligned (Krishnamurthy et al. §5.1), or oriented.
enum class PointBoxes { Aabb, Oriented };

/// The best cell of one atlas for one point: triangle distance (+inf: none), the cell's texel,
/// the cells tested.
struct BatchCell {
  double distance = 0.0;
  int x = -1, y = -1;
  long long tested = 0;
  bool cut = false;  ///< the GPU walk was cut short (see glsl/distance/point_batch.frag): not the nearest cell
};

struct BatchGeometry {
  /// The model's terms (bound, trim edges, radius); atlases are added by the builder.
  BatchGeometry(const PreparedModel& model, PointBoxes boxes);

  const PreparedModel& m;  ///< must outlive this object
  PointBoxes boxes;
  std::vector<BatchAtlas> atlases;
  std::vector<TrimEdges> trim_edges;  ///< per face (empty for untrimmed faces)
  /// Per face: the float budget of its samples, and that plus its grid's K_e (how far its surface
  /// may lie from its cells' float triangles); grow_max the largest.
  std::vector<double> budget, grow;
  double grow_max = 0.0;
  double model_bound = 0.0;  ///< K_e + float budget, the largest over the faces
  double radius = 0.0;       ///< half the diagonal of the faces' control box

  /// The float slack eps of the descent for point p (model units).
  [[nodiscard]] double slack(const glm::dvec3& p) const;
  /// Whether texel (x, y) of atlas `at` (the a-th plan's; it need not be in `atlases` yet) is a
  /// cell of the pyramid's level 0 (four samples of one slot, a material sample or a trim edge
  /// crossing it: aabb_leaf.frag with TRIM_CROSSED).
  [[nodiscard]] bool pyramid_cell(const BatchAtlas& at, size_t a, int x, int y) const;
  /// The sample at texel (x, y) as the GPU pass has it: float sample - float origin.
  [[nodiscard]] glm::dvec3 float_sample(const BatchAtlas& at, size_t a, int x, int y) const;
  /// Distance from q (relative to the float origin) to node (level, x, y) of the pyramid, in
  /// double from the stored floats: the boxes the GPU pass reads; +inf for an empty node.
  [[nodiscard]] double node_distance(const BatchAtlas& at, const glm::dvec3& q, int level, int x, int y) const;
  /// The cell whose lower-left sample is texel (x, y) of atlas a: its face, (i, j) and four float samples.
  FaceCell cell_corners(size_t a, int x, int y, glm::dvec3 corners[4]) const;
  /// glsl/distance/point_batch_trim.frag trimmed_cell_dist2 in double on the uploaded floats (the
  /// twin): q and the corners relative to the float origin.
  [[nodiscard]] double trimmed_cell_distance(const BatchAtlas& at, const glm::dvec3& q, const glm::dvec3 c[4],
                                             int header) const;
  /// The points whose hull holds the material part of the cell at texel (x, y) (corners: its float
  /// samples relative to the origin): its material corners and its trim pieces' ends, mapped onto
  /// its triangles (each triangle's material part is a polygon with those vertices). All four
  /// corners for a cell without trim data; none for a cell without material.
  void material_points(const BatchAtlas& at, size_t a, int x, int y, const glm::dvec3 corners[4],
                       std::vector<glm::dvec3>& out) const;
};

}  // namespace queries
