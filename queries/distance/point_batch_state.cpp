#include "queries/distance/point_batch_state.h"

namespace queries {

PointBatchStateView view(const PointBatchState& state) {
  PointBatchStateView s;
  for (const PointBatchState::Atlas& at : state.atlases) {
    PointBatchStateView::Atlas& sa = s.atlases.emplace_back();
    sa.plan = &at.plan;
    sa.w0 = at.w0, sa.h0 = at.h0, sa.levels = at.levels;
    sa.samples = at.samples, sa.slot_of = at.slot_of, sa.mask = at.mask, sa.crossed = at.crossed;
    sa.trim_cell = at.trim_cell, sa.trim_head = at.trim_head, sa.trim_segs = at.trim_segs;
    for (const PointBatchState::Level& level : at.obb)
      sa.obb.push_back({level.texels, {level.boxes[0], level.boxes[1], level.boxes[2]}});
  }
  return s;
}

PointBatchState copy_state(const PointBatchStateView& v) {
  const auto own = [](std::span<const float> x) { return std::vector<float>(x.begin(), x.end()); };
  PointBatchState s;
  for (const PointBatchStateView::Atlas& va : v.atlases) {
    PointBatchState::Atlas& sa = s.atlases.emplace_back();
    sa.plan = *va.plan;
    sa.w0 = va.w0, sa.h0 = va.h0, sa.levels = va.levels;
    sa.samples = own(va.samples), sa.slot_of = own(va.slot_of), sa.mask = own(va.mask);
    sa.crossed = own(va.crossed), sa.trim_cell = own(va.trim_cell), sa.trim_head = own(va.trim_head);
    sa.trim_segs = own(va.trim_segs);
    for (const PointBatchStateView::Level& level : va.obb)
      sa.obb.push_back({std::vector<uint32_t>(level.texels.begin(), level.texels.end()),
                        {own(level.boxes[0]), own(level.boxes[1]), own(level.boxes[2])}});
  }
  return s;
}

void restore_atlases(PreparedModel& m, const PointBatchState& state) {
  m.atlases.clear();
  for (const PointBatchState::Atlas& sa : state.atlases) {
    FaceAtlas fa;
    fa.plan = sa.plan;
    fa.points = gpgpu::Texture(sa.plan.width, sa.plan.height, gpgpu::Format::RGBA32F);
    fa.points.upload(sa.samples);
    m.atlases.push_back(std::move(fa));
  }
}

}  // namespace queries
