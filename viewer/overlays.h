#pragma once
/// \file overlays.h
/// What the clearance search of Krishnamurthy et al. works on, drawn as boxes: the grid cells'
/// AABBs merged up a hierarchy level (§5.1-5.2), the voxel grid of the first stage (§5.4) and the
/// faces that stage keeps or culls for a placement. Built in each model's own frame.
#include <string>
#include <vector>

#include "queries/prepared_model.h"
#include "queries/voxel_stage.h"
#include "viewer/draw_buffers.h"

namespace viewer {

/// Per face, the boxes of blocks of 2^level x 2^level cells of its certified grid (samples
/// evaluated on the CPU, grown by the grid's K), blocks whose samples are all trimmed away left out
/// (the §5.3 empty cells, less the crossing test). The GPU merges cells of the whole atlas 2x2 per
/// level, so at level >= 1 its boxes may span faces; these stay within one face. Returns the number
/// of boxes, or -1 (nothing added) when there would be more than `max_boxes`.
long long add_cell_boxes(const queries::PreparedModel& m, int level, long long max_boxes, const glm::vec3& color,
                         LineBatch& batch);

/// The occupied voxels of `grid`, a box each.
void add_voxels(const queries::VoxelGrid& grid, const glm::vec3& color, LineBatch& batch);

/// Each face's control-point box: `kept` faces (flag 1) in `kept_color`, the others in `culled_color`.
void add_face_boxes(const std::vector<nurbs::TrimmedSurface>& faces, const std::vector<char>& kept,
                    const glm::vec3& kept_color, const glm::vec3& culled_color, LineBatch& batch);

}  // namespace viewer
