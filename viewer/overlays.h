#pragma once
/// \file overlays.h
/// What the clearance search of Krishnamurthy et al. works on, drawn as boxes: the grid cells'
/// AABBs merged up a hierarchy level (§5.1-5.2), the blocks the trim culls (§5.3) and those the
/// box pruning drops for a placement (§5.1), the voxel grid of the first stage (§5.4) and the faces
/// that stage keeps or culls. Built in each model's own frame.
#include <optional>
#include <string>
#include <vector>

#include "nurbs/model_ops.h"
#include "queries/distance/prepared_model.h"
#include "queries/distance/voxel_stage.h"
#include "viewer/draw_buffers.h"

namespace viewer {

/// The culled-boxes overlay's colours, exact in 8 bits (51, 102, 255), so that the screenshot test
/// can count their pixels (the lines are drawn unlit, viewer_lines.frag).
inline constexpr glm::vec3 kKeptColor{0.2f, 1.0f, 0.4f};        ///< blocks the pruning keeps
inline constexpr glm::vec3 kPrunedColor{1.0f, 0.2f, 0.2f};      ///< blocks pruned for this placement
inline constexpr glm::vec3 kTrimCulledColor{0.4f, 0.4f, 0.4f};  ///< blocks the trim culls (dim)

/// One model's cells merged into blocks of 2^level x 2^level cells per face (samples evaluated on
/// the CPU in double, boxes grown by the grid's K). The GPU merges cells of the whole atlas 2x2 per
/// level, so at level >= 1 its boxes may span faces; these stay within one face.
struct CellBlocks {
  std::vector<nurbs::Box> kept;  ///< blocks with a material sample or a cell a trim edge crosses
  std::vector<char> witness;     ///< per kept block: 1 when a sample is material (surface inside)
  /// Blocks the trim culls (§5.3 with the crossing test of PreparedModel::crossed): every sample
  /// trimmed away and no trim edge through any of their cells.
  std::vector<nurbs::Box> trimmed;
};

/// The blocks of `m` at `level`; nullopt when there are more than `max_boxes` blocks.
std::optional<CellBlocks> cell_blocks(const queries::PreparedModel& m, int level, long long max_boxes);

/// The box pruning of §5.1 at one level, on the CPU in double: U = the least max distance
/// (Eqs. 13-16) over pairs of witness blocks of A and of B moved by `motion_b` (B's boxes: the
/// boxes of their moved corners); a block whose min distance (Eqs. 17-20) to every block of the
/// other model exceeds U is pruned.
struct BlockPruning {
  std::vector<char> pruned_a, pruned_b;  ///< per kept block of A and of B: 1 = pruned
  long long pairs = 0;                   ///< block pairs compared
  long long kept_a = 0, kept_b = 0;      ///< blocks not pruned
  double upper = 0.0;                    ///< U
  bool too_many = false;                 ///< more than `max_pairs` pairs: nothing computed
};
BlockPruning prune_blocks(const CellBlocks& a, const CellBlocks& b, const glm::dmat4& motion_b, long long max_pairs);

/// The boxes `boxes` as lines: those flagged 1 in `flags` (if given) in `flagged_color`, the others in `color`.
void add_boxes(const std::vector<nurbs::Box>& boxes, const std::vector<char>* flags, const glm::vec3& color,
               const glm::vec3& flagged_color, LineBatch& batch);

/// The kept blocks of `cell_blocks(m, level, max_boxes)` in `color`. Returns the number of boxes,
/// or -1 (nothing added) when there would be more than `max_boxes`.
long long add_cell_boxes(const queries::PreparedModel& m, int level, long long max_boxes, const glm::vec3& color,
                         LineBatch& batch);

/// The occupied voxels of `grid`, a box each.
void add_voxels(const queries::VoxelGrid& grid, const glm::vec3& color, LineBatch& batch);

/// Each face's control-point box: `kept` faces (flag 1) in `kept_color`, the others in `culled_color`.
void add_face_boxes(const std::vector<nurbs::TrimmedSurface>& faces, const std::vector<char>& kept,
                    const glm::vec3& kept_color, const glm::vec3& culled_color, LineBatch& batch);

}  // namespace viewer
