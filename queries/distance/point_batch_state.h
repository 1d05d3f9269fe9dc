#pragma once
/// \file point_batch_state.h
/// The saved state of the batched point projection (point_batch.h): what a PointBatch builds from
/// a prepared model, kept between processes by the disk cache (batch_cache.h) and restored without
/// building it again.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "queries/distance/face_atlas.h"
#include "queries/distance/prepared_model.h"

namespace queries {

/// What a PointBatch builds from a prepared model (oriented boxes), to keep between processes
/// (batch_cache.h): per atlas its plan, the read-back samples, slot indices, masks and crossed
/// cells, the trimmed cells' data, and the oriented pyramid with its empty texels left out.
struct PointBatchState {
  struct Level {
    std::vector<uint32_t> texels;            ///< the non-empty texels, ascending
    std::array<std::vector<float>, 3> boxes;  ///< their 4 floats per texture
  };
  struct Atlas {
    AtlasPlan plan;
    int w0 = 1, h0 = 1, levels = 1;
    std::vector<float> samples, slot_of, mask, crossed, trim_cell, trim_head, trim_segs;
    std::vector<Level> obb;
  };
  std::vector<Atlas> atlases;
};

/// The same arrays as views (save_batch_state writes them): of a live PointBatch (state_view(),
/// valid while the batch lives; nothing is copied) or of a PointBatchState (view()).
struct PointBatchStateView {
  struct Level {
    std::span<const uint32_t> texels;
    std::array<std::span<const float>, 3> boxes;
  };
  struct Atlas {
    const AtlasPlan* plan = nullptr;
    int w0 = 1, h0 = 1, levels = 1;
    std::span<const float> samples, slot_of, mask, crossed, trim_cell, trim_head, trim_segs;
    std::vector<Level> obb;
  };
  std::vector<Atlas> atlases;
};
[[nodiscard]] PointBatchStateView view(const PointBatchState& state);
/// A state holding copies of the arrays `view` shows (PointBatch::export_state).
[[nodiscard]] PointBatchState copy_state(const PointBatchStateView& view);

/// A model from prepare_geometry with the atlases of `state` restored (plans and samples, uploaded;
/// their normals, masks and slot textures left empty): what PointBatch(gpu, m, state) needs.
void restore_atlases(PreparedModel& m, const PointBatchState& state);

}  // namespace queries
