#pragma once
/// \file voxel_stage.h
/// The object first stage of Krishnamurthy et al. §5.4: a voxel grid per object whose voxels list
/// the faces that may pass through them; occupied voxels of A as rows and of B as columns of a 2D
/// texture, the min and max box-box distance of every voxel pair (Eqs. 13-20), the least upper
/// bound U by a min reduction, the pairs with lower bound <= U by stream reduction, read back and
/// de-duplicated into the face pairs the surface-surface search (clearance.h) has to examine.
///
/// Conservative occupancy. Every face is put on a coarse certified grid (K_e <= a quarter of the
/// voxel size, nurbs/distance/certified_grid.h) evaluated in double; the surface over a cell lies within K_e
/// of the cell's two triangles, so within the box of its 4 corners grown by that cell's K_e, and
/// every voxel that box overlaps gets the face. Hence every surface point lies in a voxel listing
/// its face.
///  - Trimmed faces (§5.3): with VoxelizeOptions::skip_trimmed_cells (default) a cell is skipped
///    when its 4 corners are outside material and no edge of the face's trim polygons passes
///    through it (its parameter box, grown by twice the flattening tolerance). That is a proof: a
///    material point in the cell and a non-material corner would have the trim boundary between
///    them, inside the (convex) cell. The corner test alone, as the GPU leaf pass aabb_leaf.frag
///    uses it, is the paper's §5.3 limitation (material between the corners of a cell is lost); it
///    is not used here. Off: every cell of every face is kept.
///
/// Honest upper bounds. The max distance of a voxel pair bounds the clearance only when both voxels
/// hold surface material; a voxel is a "witness" when it holds a material grid sample (an exact
/// surface point). Only witness-witness pairs give upper bounds; every occupied voxel pair gives a
/// lower bound. So the face pair holding the true closest points is always kept.
///
/// Rigid motion: B's voxel boxes are refitted as the box of their 8 moved corners.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <utility>
#include <vector>

#include "gpgpu/gpu.h"
#include "queries/distance/prepared_model.h"

namespace queries {

struct VoxelizeOptions {
  int n = 40;                      ///< voxels per axis (the paper's 40^3)
  double cell_fraction = 0.25;     ///< K_e of the coarse grids, as a fraction of the voxel size
  bool skip_trimmed_cells = true;  ///< skip cells proven trimmed away (see the file comment)
};

/// A voxel grid of one object in its own (unmoved) frame. Voxel (i, j, k) has index
/// i + n (j + n k) and box lo + h * [(i, j, k), (i, j, k) + 1].
struct VoxelGrid {
  int n = 0;
  glm::dvec3 lo{0.0}, h{0.0};              ///< grid origin and voxel size per axis
  std::vector<int> voxels;                 ///< occupied voxel indices, increasing
  std::vector<char> witness;               ///< per occupied voxel: holds a material sample
  std::vector<int> face_begin;             ///< per occupied voxel, CSR into `faces` (size voxels + 1)
  std::vector<int> faces;                  ///< face references, increasing within a voxel
  int face_count = 0;                      ///< faces of the model
  long long cells = 0, skipped_cells = 0;  ///< coarse grid cells examined / skipped as trimmed away
  double seconds = 0.0;                    ///< time to build

  /// Box of voxel index `v` (not a position in `voxels`).
  [[nodiscard]] std::pair<glm::dvec3, glm::dvec3> box(int v) const;
};

/// Builds the voxel grid of `m` (its faces, Filip bounds and trim polygons; nothing on the GPU).
/// Box of the grid: the box of all grown cell boxes, clipped to the faces' control boxes (which hold
/// the surfaces), each side at least 1/n of the largest so flat objects keep cubic-ish voxels.
/// Prepare once per model and keep it across motions.
VoxelGrid voxelize(const PreparedModel& m, const VoxelizeOptions& options = {});
/// The same from the faces themselves (Filip bounds computed here; trim loops flattened within
/// `trim_tolerance` of each u domain width).
VoxelGrid voxelize(const std::vector<nurbs::TrimmedSurface>& faces, const VoxelizeOptions& options = {});

struct VoxelOptions {
  double slack = 1e-5;  ///< pairs with lower bound <= U (1 + slack) survive (float rounding of both)
  int max_tile = 4096;  ///< tile side for the pair texture (further capped by GL_MAX_TEXTURE_SIZE)
  /// Beyond the paper: skip a tile whose rows' and columns' hulls are farther apart than the cut so
  /// far (its pairs could neither lower U nor survive). Same result; voxels are in z-major order,
  /// so a tile's rows and columns are slabs of the objects.
  bool cull_tiles = false;
};

/// Wall-clock seconds of the GPU path, each stage ended by a glFinish: upload = B's refit, Morton
/// order, seed bound and box textures; minmax / reduce / compact = the passes of all tiles
/// (compact includes the threshold pass); readback = candidates read back, filtered, face pairs.
struct VoxelTimings {
  double upload = 0, minmax = 0, reduce = 0, compact = 0, readback = 0, total = 0;
};

struct VoxelStage {
  std::vector<std::pair<int, int>> face_pairs;  ///< kept (face of A, face of B), sorted, unique
  std::vector<char> faces_a, faces_b;           ///< per face: in some kept pair
  double upper = 0.0;                           ///< U: least witness-pair max distance (+inf if none)
  long long voxels_a = 0, voxels_b = 0;         ///< occupied voxels
  long long voxel_pairs = 0, surviving_pairs = 0;
  int tiles = 0, culled_tiles = 0;  ///< pair texture tiles, tiles skipped (GPU path)
  /// CPU twin: pairs whose lower bound is within 1e-6 (relative) of the cut, which the float GPU
  /// pass may put on either side.
  long long borderline_pairs = 0;
  VoxelTimings timings;
};

/// The §5.4 stage on the GPU: A fixed, B moved by `motion_b` (rigid). Per tile of the pair texture
/// one pass (glsl/distance/voxel_pairs_minmax.frag), reduce_min of G, threshold_le at the best U so far
/// (seeded with one witness pair found on the CPU) and compact; the candidates and their lower
/// bounds are read back, kept when within the final U and turned into face pairs on the CPU.
VoxelStage voxel_stage(gpgpu::Gpu& gpu, const VoxelGrid& a, const VoxelGrid& b,
                       const glm::dmat4& motion_b = glm::dmat4(1.0), const VoxelOptions& options = {});

/// CPU twin in double: every voxel pair, same cut U (1 + slack). The test oracle.
VoxelStage voxel_stage_cpu(const VoxelGrid& a, const VoxelGrid& b, const glm::dmat4& motion_b = glm::dmat4(1.0),
                           const VoxelOptions& options = {});

/// Min and max distance between boxes [lo1, hi1] and [lo2, hi2] (Eqs. 13-20), in double.
std::pair<double, double> box_box_minmax(const glm::dvec3& lo1, const glm::dvec3& hi1, const glm::dvec3& lo2,
                                         const glm::dvec3& hi2);

}  // namespace queries
