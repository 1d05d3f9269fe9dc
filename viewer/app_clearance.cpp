// Clearance mode: both models prepared once by the library's front door queries::ClearancePair, as
// `nurbsgl clearance` prepares them for a placement it does not know in advance (every face kept,
// the GPU descent), one query per change of B's placement (the paper's Fig. 16 interaction: B's
// hierarchy refitted under the motion, A's kept between queries).
#include <chrono>

#include "viewer/app.h"
#include "viewer/overlays.h"

namespace viewer {

void App::prepare_clearance() {
  queries::ClearanceOptions o;
  o.tolerance = options_.rel_tolerance;
  const auto t0 = std::chrono::steady_clock::now();
  clearance_pair_ = std::make_unique<queries::ClearancePair>(
      a_->loaded, options_.models.size() > 1 ? &b_->loaded : nullptr, o, gpu_.get());
  clearance_pair_->prepare({});
  prepare_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void App::query_clearance() {
  clearance_dirty_ = false;
  try {
    if (!clearance_pair_) prepare_clearance();
    const queries::PreparedModel &a = clearance_pair_->prepared_a(), &b = clearance_pair_->prepared_b();
    const auto t0 = std::chrono::steady_clock::now();
    queries::ClearanceAnswer answer = clearance_pair_->query(motion_b());
    query_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!answer.clearance.found) {
      clearance_.reset();
      clearance_error_ = answer.failure();
      return;
    }
    clearance_ = std::move(answer.clearance);
    clearance_uncertified_ = answer.reason;
    clearance_error_.clear();
    if (show_culled_) overlay_dirty_ = true;  // the blocks pruned at this placement
    if (show_faces_) {                        // §5.4 for this placement: which faces the voxel pairs keep
      if (!voxels_a_) voxels_a_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(a));
      if (!voxels_b_) voxels_b_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(b));
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
  blocks_a_ = cell_blocks(clearance_pair_->prepared_a(), cell_level_, kMaxBlocks);
  blocks_b_ = cell_blocks(clearance_pair_->prepared_b(), cell_level_, kMaxBlocks);
  blocks_level_ = cell_level_;
}

void App::rebuild_overlays() {
  overlay_dirty_ = false;
  overlay_a_.clear();
  overlay_b_.clear();
  if (!clearance_pair_) return;
  const queries::PreparedModel &prep_a = clearance_pair_->prepared_a(), &prep_b = clearance_pair_->prepared_b();
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
    if (!voxels_a_) voxels_a_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(prep_a));
    if (!voxels_b_) voxels_b_ = std::make_unique<queries::VoxelGrid>(queries::voxelize(prep_b));
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
    add_face_boxes(prep_a.faces, voxel_stage_->faces_a, {0.2f, 0.95f, 0.3f}, {0.9f, 0.2f, 0.2f}, overlay_a_);
    add_face_boxes(prep_b.faces, voxel_stage_->faces_b, {0.2f, 0.95f, 0.3f}, {0.9f, 0.2f, 0.2f}, overlay_b_);
  }
}

}  // namespace viewer
