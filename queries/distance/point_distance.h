#pragma once
/// \file point_distance.h
/// Minimum distance and closest point from a point to a trimmed NURBS model, Krishnamurthy et al.
/// §3.1-3.2 (Fig. 6) with the bounds of §4, over every face at once:
///  1. every face evaluated once on its certified grid (K_e <= tolerance on every cell), all faces
///     packed in atlases (face_atlas.h), trim masks beside them;
///  2. per query, one pass renders the min and max point-AABB distance of every cell into R and G
///     (glsl/distance/point_aabb_minmax.frag, Eqs. 5-12; boxes of four samples grown by K_e and the float
///     budget), a log-n min reduction of G gives the least upper bound U (one read-back), a pass
///     marks the cells with R <= U and stream reduction returns them (one read-back of the count,
///     one of the cells);
///  3. on the CPU, in double, two triangles per surviving cell from the surface evaluated at the
///     cell's corners; the closest one wins.
/// Bounds: |d - d*| < K (Theorem 1) and |P' - Q| <= sqrt(4 K d + K^2) (Theorem 2), with K the
/// Euclidean K_e (the paper's per-coordinate K does not bound the distance, README "Error bounds"),
/// maxed over the surviving cells (the true closest point's cell is one of them).
/// Trimmed faces (§5.3): cells with all four samples trimmed are culled, cells with some give no
/// upper bound; a closest point in a trimmed region is discarded and the next candidate taken; when
/// the winner's cell is partly trimmed the result says so (on_trim_edge: the point lies within one
/// cell of a trim curve, where the sample-level trim classification is the limit).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/trimmed_surface.h"
#include "queries/distance/face_atlas.h"
#include "queries/distance/prepared_model.h"

namespace queries {

struct PointDistance {
  bool found = false;
  double distance = 0.0;
  glm::dvec3 point{0.0};     ///< closest point found (on a grid triangle)
  glm::dvec2 uv{0.0};        ///< its parameters on the face (barycentric in the cell's parameter triangle)
  int face = -1;             ///< index into the query's face list
  double bound = 0.0;        ///< |distance - true distance| < bound (Theorem 1, K_e)
  double point_bound = 0.0;  ///< |point - true closest point| <= sqrt(4 K d + K^2) (Theorem 2)
  bool on_trim_edge = false;
  long long cells = 0;       ///< cells tested on the GPU
  long long candidates = 0;  ///< cells whose lower bound is within U (read back)
  double upper = 0.0;        ///< U, the least upper bound over the cells
  // Search::CoarseToFine (refine.h): the point is an exact surface point, bound = U - L.
  bool meets_tolerance = true;  ///< bound <= T (false when the refinement hit its budget)
  int rounds = 0;               ///< subdivision rounds
  long long refined_cells = 0;  ///< cells evaluated on the CPU
};

struct Refined;
/// The answer of refine_point (refine.h) written into r: found, the exact surface point, its (u, v)
/// and face, bound U - L, point bound sqrt(4 K d + K^2) with K = that bound, and the refinement's
/// figures (r's cells, candidates and U stay).
void set_refined(PointDistance& r, const Refined& f);

/// A model prepared for many point queries (grids, atlases and masks stay on the GPU).
class PointDistanceQuery {
 public:
  /// `tolerance`: the K_e of every face's grid, model units. Throws when a face cannot meet it
  /// within `max_samples`, or when a face's grid does not fit an atlas of the GPU's size.
  PointDistanceQuery(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                     long long max_samples = kDefaultMaxSamples, Search search = Search::Faithful);
  PointDistance query(const glm::dvec3& p);
  /// An atlas of at most this many cells is pruned on the CPU from one read-back of its min/max
  /// pass: U and the cells within it computed there with the GPU passes' float arithmetic (the same
  /// cells), without the reduction, threshold and stream-reduction passes (beyond the paper, as
  /// ClearanceLimits::host_pairs). 0: always on the GPU; -1 (the default): 65536 with the
  /// coarse-to-fine search, 0 with the faithful path.
  void set_host_cells(long long cells) { host_cells_ = cells; }
  /// The host-cell limit in force: set_host_cells' value, -1 resolved for the search.
  [[nodiscard]] long long host_cells_used() const {
    return host_cells_ >= 0 ? host_cells_ : m_.search == Search::CoarseToFine ? 65536 : 0;
  }

  [[nodiscard]] const std::vector<nurbs::CertifiedGrid>& grids() const { return m_.grids; }
  [[nodiscard]] size_t atlases() const { return m_.atlases.size(); }
  [[nodiscard]] const PreparedModel& model() const { return m_; }

 private:
  gpgpu::Gpu& gpu_;
  PreparedModel m_;
  long long host_cells_ = -1;
};

/// CPU twin in double: the same cells, boxes, cut-off and triangles for one face on its grid
/// (no trimming, no float budget). The test oracle of the GPU path.
PointDistance point_distance_cpu(const nurbs::Surface& s, const nurbs::FilipBound& b, const nurbs::ParamGrid& g,
                                 const glm::dvec3& p);

/// Closest point to p on triangle abc (Ericson, "Real-Time Collision Detection", §5.1.5) and its
/// barycentric weights (wa, wb, wc).
glm::dvec3 closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                               glm::dvec3& weights);

}  // namespace queries
