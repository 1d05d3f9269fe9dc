#pragma once
/// \file point_batch.h
/// Batched point projection (beyond the paper): many query points at once against a
/// prepared model, one fragment per point (glsl/distance/point_batch.frag). Per atlas of the model:
///  1. once: the box of every cell's four float samples (glsl/distance/aabb_leaf.frag, ungrown) merged 2x2
///     up to one root (glsl/distance/aabb_merge.frag), the levels stored as mip levels of one texture
///     (Krishnamurthy et al. §5.1 hierarchies);
///  2. per batch: the points sorted along a Morton curve and laid out in 4 x 4 tiles (lanes that
///     run together descend alike), one pass in which every point descends the pyramid depth
///     first, nearest child first, with no stack array (siblings left per level in bit fields),
///     pruned by its best triangle distance so far, ending at the closest cell triangle; one
///     read-back of (distance, cell) for all points;
///     At a cell that a trim edge crosses the pass takes the distance to the cell's material part
///     (glsl/distance/point_batch_trim.frag: a triangle's closest point when a crossing count says it is
///     material, else the closest point of the trim pieces inside the cell), so the walk ends at
///     the closest material point (§5.3: "discard the point and continue the search");
///  3. per point on the CPU, in double: the winning cell's two triangles from its float samples,
///     the closest point and its (u, v) (barycentric on the cell's parameter triangle, as
///     point_distance.cpp), the face; trimmed faces (§5.3) check the point with is_material, and a
///     trimmed closest point is replaced by the cell's closest material point (material_cell; on
///     a trim piece, on_trim_edge). Only when that cell holds no material in double (the float
///     pass judged a point within rounding of a trim edge) is the point searched again on the CPU,
///     best first over the same pyramid. Cells with all four samples trimmed that no trim edge
///     crosses are culled; trim points are those of the flattened polygons (nurbs::flatten_trim,
///     within 1e-6 of the u domain).
/// Bound, per point (|distance - true distance| <= bound):
///   K_e (Theorem 1, max over the faces' grids) + the float budget of the samples (float_budget)
///   + 2 eps, eps = kFloatSlack (|p - centre| + radius): the float rounding of the pass's box and
///   triangle distances, which can make it pick a cell up to 2 eps farther than the closest one
///   (it prunes only boxes beyond best + eps). eps is a stated allowance (16 ulp; the distances
///   are taken to points, edge lines and planes, a few roundings each), not a proof; the tests
///   measure |pass - twin in double| <= 0.06 eps. point_bound = sqrt(4 K d + K^2) with K = bound.
/// With Search::Faithful grids (the cells the answers come from meet the tolerance).
///
/// Models prepared with Search::CoarseToFine (grids at a coarse tolerance, a few thousand cells a
/// face, whatever the degree and weights of the faces) are finished by refinement instead
/// (point_batch_finish.h): the winner of step 3 is a material point, so the surface there bounds
/// the distance from above (U); the pyramid's cells whose boxes, grown by their face's K_e, the
/// float budget and eps, lie within U are subdivided in double by refine_point (refine.h) until the
/// answer meets T. The bound is then the refinement's (U - L, in double, no float term): the float
/// pass only chooses the cells, and any T can be met.
///
/// Beyond that (PointBoxes::Oriented, the default): the pyramid's boxes are oriented, each in the
/// frame of its cells' mean tangent and normal (point_batch_obb.cpp). An axis-aligned box of a cell
/// tilted to the axes is as thick as the cell is wide, so a point 5 mm off the 100x105 surface finds
/// every cell within about one cell width of its distance below its best, and tests them all (90
/// cells per point on the wave band); an oriented box is as thick as the cell is curved, and the
/// same points test 5 (the prototype's count over 2000 points; 401 box tests -> 114).
#include <algorithm>
#include <array>
#include <functional>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "gpgpu/gpu.h"
#include "queries/distance/point_batch_finish.h"
#include "queries/distance/point_batch_geometry.h"
#include "queries/distance/point_batch_state.h"
#include "queries/distance/point_distance.h"
#include "queries/distance/prepared_model.h"

namespace queries {

/// Figures of the last batch.
struct PointBatchStats {
  long long points = 0;
  long long cells_tested = 0;  ///< triangle pairs evaluated by the descent (summed over points)
  long long fallbacks = 0;     ///< points searched again on the CPU: the winning cell holds no material in double
  long long trimmed = 0;       ///< points whose winning cell a trim edge crosses (its material part, on the GPU)
  long long cut = 0;           ///< points whose GPU walk was cut short, descended again by the CPU twin
  long long refined_cells = 0;  ///< Search::CoarseToFine models: cells the refinement evaluated (summed)
  double gpu_seconds = 0.0;    ///< upload, descent passes and read-back (0 with BatchEngine::Cpu)
  double cpu_seconds = 0.0;    ///< the double-precision finishing and fallbacks, on every hardware thread
};

/// Where step 2 runs: the GPU pass (glsl/distance/point_batch.frag), or its twin in double (descend_cpu) on
/// every hardware thread, each point's best distance over the atlases so far pruning the next
/// atlas's descent. The same pyramid, cells and finishing, the same bound: the CPU engine is for
/// a GL whose renderer is the CPU itself (llvmpipe), where the float pass is not faster.
enum class BatchEngine { Gpu, Cpu };

/// The grid tolerance for a batched model whose answers must carry bounds within `tolerance` (T):
/// T less the float terms of the bound (the largest float budget of the samples and 2 eps for a
/// point within the model's control box grown by its size), at least T / 2.
[[nodiscard]] double batch_grid_tolerance(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance);

/// The geometry of a batched query at tolerance T (model units) on atlases of `atlas_side`: faithful
/// grids (at batch_grid_tolerance) when every face meets it within `max_samples` and fits an atlas
/// and the whole takes at most `max_bytes` (estimate_batch_bytes), else the coarse grids of
/// Search::CoarseToFine, whose answers PointBatch refines to T in double (high-degree rational
/// faces whose Filip bound needs millions of samples a face at T). The choice depends on the model
/// and T only, never on the points.
[[nodiscard]] PreparedModel prepare_batch_geometry(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance,
                                                   long long max_samples, int atlas_side, PointBoxes boxes,
                                                   long long max_bytes);

/// The float terms of a batched answer's bound at a point p: the largest float budget of the faces'
/// samples plus 2 eps, eps = kFloatSlack (|p - centre| + radius) (the centre and half diagonal of
/// the faces' control box, as PointBatch). No tolerance at or below it can be met at p, whatever
/// the grids: the float arithmetic of the pass, not the sampling, limits the answer there.
struct BatchFloatFloor {
  double budget = 0.0, radius = 0.0;
  glm::dvec3 centre{0.0};
  explicit BatchFloatFloor(const std::vector<nurbs::TrimmedSurface>& faces);
  [[nodiscard]] double at(const glm::dvec3& p) const;
};

/// Bytes a batched query over `m` (prepared by prepare_geometry, no atlases yet) will hold at its
/// peak, from the atlas plan that prepare_atlases will make with atlases of `atlas_side`: per atlas
/// texel its samples, masks and indices (GPU and CPU copies), per texel of the pyramid's
/// levels (padded to powers of two) its boxes (GPU and CPU), plus the GL driver's own. An estimate
/// for refusing a request that cannot fit before the work, not a measurement.
[[nodiscard]] long long estimate_batch_bytes(const PreparedModel& m, int atlas_side, PointBoxes boxes);

class PointBatch {
 public:
  /// From a state exported by an earlier PointBatch over the same model (same faces, grids and
  /// atlas plans; PointBoxes::Oriented): the same pyramid and trimmed cells, uploaded, none built.
  /// `m` has its atlases from restore_atlases.
  PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBatchState state);
  /// This batch's state (PointBoxes::Oriented only, else std::logic_error): a copy, and views of
  /// the batch's own arrays (what the disk cache writes while the batch answers points).
  [[nodiscard]] PointBatchState export_state() const;
  [[nodiscard]] PointBatchStateView state_view() const;

  /// Builds the pyramids on the GPU (oriented boxes: on the CPU, uploaded) and reads the atlases'
  /// samples, masks and slot indices back once. `m` (Search::Faithful, or Search::CoarseToFine:
  /// answers finished by refinement) must outlive this object.
  PointBatch(gpgpu::Gpu& gpu, const PreparedModel& m, PointBoxes boxes = PointBoxes::Oriented);

  /// All points at once (input order kept): distance, closest point, (u, v), face, bound, and
  /// on_trim_edge as PointDistance has them; `candidates` = cells tested by the descent. More
  /// points than points_per_pass() go in several passes.
  ///
  /// `within` (optional, one per point; <= 0: none): only a point nearer than within[i] is wanted.
  /// The descent starts with that as its best distance, so it prunes every box beyond it; found
  /// is false when no cell is nearer. Fast where many cells are nearly equidistant from the point
  /// (the centre of a sphere, the axis of a cylinder), which the plain query must all visit.
  std::vector<PointDistance> query(std::span<const glm::dvec3> points, std::span<const double> within = {});
  /// Whether the pass takes the material part of the cells a trim edge crosses (the default), or
  /// their whole triangles as the paper's corner test does, the CPU then searching again every
  /// point whose winner lies in a trimmed region (best first, search_material).
  void set_trim_on_gpu(bool on) { trim_on_gpu_ = on; }
  void set_engine(BatchEngine e) { engine_ = e; }
  /// T > 0: an answer whose bound exceeds T (the float terms grow with the point's distance from
  /// the model) is refined in double until it meets T, as the answers of Search::CoarseToFine
  /// models are (point_batch_finish.h). 0 (the default): answers keep the pass's bound.
  void set_refine_tolerance(double t) { refine_to_ = t; }
  [[nodiscard]] BatchEngine engine() const { return engine_; }
  [[nodiscard]] bool trim_on_gpu() const { return trim_on_gpu_; }
  [[nodiscard]] size_t points_per_pass() const { return points_per_pass_; }
  void set_points_per_pass(size_t n) { points_per_pass_ = std::max<size_t>(n, 1); }
  /// Called with (points done, points) after each pass of a query of several passes.
  void set_progress(std::function<void(size_t, size_t)> f) { progress_ = std::move(f); }

  /// CPU twin in double: the same pyramid built on the CPU from the read-back samples, the same
  /// descent, the same finishing. The test oracle of query().
  PointDistance query_cpu(const glm::dvec3& p, double within = 0.0);

  /// Step 2 alone, per atlas then per point: the GPU pass and its twin (tests compare them).
  std::vector<std::vector<BatchCell>> descend_gpu(std::span<const glm::dvec3> points,
                                                  std::span<const double> within = {});
  BatchCell descend_cpu(size_t atlas, const glm::dvec3& p, double within = 0.0);

  /// Level `level` of atlas `a`'s axis-aligned pyramid (PointBoxes::Aabb; with oriented boxes the GPU
  /// one is not filled), lo (or hi) corners, 4 floats per texel: from the GPU, and the CPU twin's
  /// (3 floats per texel).
  [[nodiscard]] std::vector<float> gpu_level(size_t a, int level, bool hi) const;
  [[nodiscard]] const std::vector<float>& cpu_level(size_t a, int level, bool hi);
  [[nodiscard]] int levels(size_t a) const { return g_.atlases[a].levels; }
  [[nodiscard]] int level_width(size_t a, int level) const { return g_.atlases[a].level_width(level); }
  [[nodiscard]] int level_height(size_t a, int level) const { return g_.atlases[a].level_height(level); }

  /// The part of every bound that does not depend on the point: K_e + float budget (model units;
  /// with Search::CoarseToFine each answer carries the refinement's bound instead).
  [[nodiscard]] double model_bound() const { return g_.model_bound; }
  /// The float slack eps of the descent for point p (model units).
  [[nodiscard]] double slack(const glm::dvec3& p) const { return g_.slack(p); }
  [[nodiscard]] const PointBatchStats& stats() const { return stats_; }
  [[nodiscard]] PointBoxes boxes() const { return g_.boxes; }
  /// Level `level` of atlas `a`'s oriented pyramid as uploaded: texture k = 0, 1, 2 holds per texel
  /// (centre, e0), (axis a0, e1), (axis a2 = normal, e2); a1 = a2 x a0; e0 < 0: empty.
  [[nodiscard]] std::vector<float> oriented_level(size_t a, int level, int k) const;

 private:
  using Atlas = BatchAtlas;
  /// Uploads what the GPU pass of atlas `at` reads and only it does (the trim textures, the oriented
  /// pyramid), on the first pass: the CPU engine never does.
  void ensure_uploaded(Atlas& at, size_t a);
  /// PointBoxes::Aabb: the pyramid's boxes on the GPU (aabb_leaf.frag, aabb_merge.frag) into at.lo, at.hi.
  void build_aabb_pyramid(Atlas& at, const FaceAtlas& fa, size_t index);
  /// PointBoxes::Oriented: builds at.cpu_obb and uploads it into at.obb (point_batch_obb.cpp).
  void build_oriented_pyramid(Atlas& at, size_t a);
  /// Fills at.trim_* for the trimmed faces of atlas a and uploads them.
  void upload_trim_cells(Atlas& at, size_t a);
  /// Step 3 with this batch's settings.
  [[nodiscard]] BatchFinish finishing() const { return BatchFinish(g_, trim_on_gpu_, refine_to_); }

  gpgpu::Gpu& gpu_;
  BatchGeometry g_;
  double refine_to_ = 0.0;  ///< set_refine_tolerance
  PointBatchStats stats_;
  size_t points_per_pass_ = size_t(1) << 22;  ///< a 4096 x 1024 texture of points
  std::function<void(size_t, size_t)> progress_;
  bool trim_on_gpu_ = true;
  BatchEngine engine_ = BatchEngine::Gpu;
};

}  // namespace queries
