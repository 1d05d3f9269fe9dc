// Clearance mode: both models prepared once as `nurbsgl clearance` prepares them (coarse-to-fine
// search, K_e <= tol x the larger model size, cli/cmd_clearance.cpp), one query per change of B's
// placement (the paper's Fig. 16 interaction: B's hierarchy refitted under the motion, A's kept in
// a ClearanceCache as the CLI's --motion keeps it).
#include <chrono>

#include "viewer/app.h"
#include "viewer/overlays.h"

namespace viewer {

void App::prepare_clearance() {
  // Each model at half the tolerance: the answer's bound (their sum) within it, as `nurbsgl clearance`.
  const double tolerance =
      queries::clearance_model_tolerance(options_.rel_tolerance * std::max(a_->size, b_->size));
  const auto t0 = std::chrono::steady_clock::now();
  prep_a_ = std::make_unique<queries::PreparedModel>(
      queries::prepare_model(*gpu_, a_->faces, tolerance, 1LL << 22, queries::Search::CoarseToFine));
  prep_b_ = std::make_unique<queries::PreparedModel>(
      queries::prepare_model(*gpu_, b_->faces, tolerance, 1LL << 22, queries::Search::CoarseToFine));
  cache_ = std::make_unique<queries::ClearanceCache>();  // A's hierarchy, reused by every query
  gpu_->finish();
  prepare_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void App::query_clearance() {
  clearance_dirty_ = false;
  try {
    if (!prep_a_) prepare_clearance();
    const auto t0 = std::chrono::steady_clock::now();
    queries::Clearance c =
        queries::clearance(*gpu_, *prep_a_, *prep_b_, motion_b(), nullptr, nullptr, {}, cache_.get());
    query_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!c.found) {
      clearance_.reset();
      clearance_error_ = "no pair of surface points found (every cell trimmed away?)";
      return;
    }
    clearance_ = std::move(c);
    clearance_error_.clear();
    if (show_culled_) overlay_dirty_ = true;  // the blocks pruned at this placement
    if (show_faces_) {                        // §5.4 for this placement: which faces the voxel pairs keep
      if (!voxels_a_) voxels_a_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(*prep_a_));
      if (!voxels_b_) voxels_b_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(*prep_b_));
      voxel_stage_ = queries::voxel_stage(*gpu_, *voxels_a_, *voxels_b_, motion_b());
      overlay_dirty_ = true;
    }
  } catch (const std::exception& e) {
    // A model the queries cannot prepare (a face beyond the sample budget): said in the panel.
    clearance_.reset();
    clearance_error_ = e.what();
  }
}

void App::update_blocks() {
  constexpr long long kMaxBlocks = 60000;  // per model: more boxes than that are no longer readable
  if (blocks_level_ == cell_level_) return;
  blocks_a_ = cell_blocks(*prep_a_, cell_level_, kMaxBlocks);
  blocks_b_ = cell_blocks(*prep_b_, cell_level_, kMaxBlocks);
  blocks_level_ = cell_level_;
}

void App::rebuild_overlays() {
  overlay_dirty_ = false;
  overlay_a_.clear();
  overlay_b_.clear();
  if (!prep_a_) return;
  if (show_cells_ || show_culled_) update_blocks();
  const bool blocks = blocks_a_ && blocks_b_;
  if (show_cells_) {
    cell_boxes_ = blocks ? static_cast<long long>(blocks_a_->kept.size() + blocks_b_->kept.size()) : -1;
    if (blocks) {
      add_boxes(blocks_a_->kept, nullptr, {0.3f, 0.8f, 1.0f}, {}, overlay_a_);
      add_boxes(blocks_b_->kept, nullptr, {1.0f, 0.6f, 0.2f}, {}, overlay_b_);
    }
  }
  if (show_voxels_) {
    if (!voxels_a_) voxels_a_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(*prep_a_));
    if (!voxels_b_) voxels_b_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(*prep_b_));
    add_voxels(*voxels_a_, {0.6f, 0.45f, 0.95f}, overlay_a_);
    add_voxels(*voxels_b_, {0.95f, 0.45f, 0.6f}, overlay_b_);
  }
  if (show_culled_ && blocks) {               // §5.3 and §5.1 at this level and placement (overlays.h)
    constexpr long long kMaxPairs = 4000000;  // about 40 ms of box pairs in double (347k pairs: 3.6 ms)
    const auto t0 = std::chrono::steady_clock::now();
    pruning_ = prune_blocks(*blocks_a_, *blocks_b_, motion_b(), kMaxPairs);
    pruning_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    add_boxes(blocks_a_->trimmed, nullptr, kTrimCulledColor, {}, overlay_a_);
    add_boxes(blocks_b_->trimmed, nullptr, kTrimCulledColor, {}, overlay_b_);
    if (!pruning_.too_many) {
      add_boxes(blocks_a_->kept, &pruning_.pruned_a, kKeptColor, kPrunedColor, overlay_a_);
      add_boxes(blocks_b_->kept, &pruning_.pruned_b, kKeptColor, kPrunedColor, overlay_b_);
    }
  }
  if (show_faces_ && voxel_stage_) {
    add_face_boxes(prep_a_->faces, voxel_stage_->faces_a, {0.2f, 0.95f, 0.3f}, {0.9f, 0.2f, 0.2f}, overlay_a_);
    add_face_boxes(prep_b_->faces, voxel_stage_->faces_b, {0.2f, 0.95f, 0.3f}, {0.9f, 0.2f, 0.2f}, overlay_b_);
  }
}

}  // namespace viewer
