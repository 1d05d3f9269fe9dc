#pragma once
/// \file point_batch_atlas.h
/// One atlas of the batched point projection (point_batch.h) as PointBatch holds it: the read-back
/// samples, slot indices, masks and crossed cells, the box pyramid the points descend (axis-aligned
/// on the GPU, or oriented, built on the CPU and uploaded), the CPU twin's copy of it, and the
/// trimmed cells' data.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "gpgpu/texture.h"
#include "queries/distance/face_atlas.h"

namespace queries {

struct BatchAtlas {
  /// The pyramid's shape: level 0 padded to powers of two (w0 x h0), so that every level halves.
  int w0 = 1, h0 = 1, levels = 1;
  [[nodiscard]] int level_width(int l) const { return std::max(1, w0 >> l); }
  [[nodiscard]] int level_height(int l) const { return std::max(1, h0 >> l); }
  gpgpu::Texture lo, hi;  ///< PointBoxes::Aabb: the axis-aligned pyramid, mip levels (empty otherwise)
  std::vector<float> samples;              ///< RGBA per atlas texel (model coordinates, float)
  std::vector<float> slot_of;              ///< slot index per texel, -1 outside
  std::vector<float> mask;                 ///< trim mask per texel, 1 = material
  std::vector<float> crossed;              ///< 1 where a trim edge crosses the texel's cell (PreparedModel)
  std::vector<std::vector<float>> cpu_lo;  ///< the twin's pyramid (built on first use), xyz
  std::vector<std::vector<float>> cpu_hi;
  std::array<gpgpu::Texture, 3> obb;                       ///< PointBoxes::Oriented: the pyramid, mip levels
  /// The cells a trim edge crosses (glsl/distance/point_batch_trim.frag): per texel 0 or 1 + header index;
  /// per header (first segment, crossing segments, pieces, reference side); per segment
  /// (s0, t0, s1, t1) in unit-cell coordinates, a cell's crossing segments then its pieces.
  std::vector<float> trim_cell, trim_head, trim_segs;
  gpgpu::Texture trim_cell_tex, trim_head_tex, trim_segs_tex;
  /// The oriented pyramid on the CPU, per level only its boxes (most texels of the padded levels
  /// are empty): the texels that hold one, ascending, the box index of every texel (-1: empty),
  /// and per box the uploaded texels' 3 x 4 floats.
  struct ObbLevel {
    std::vector<int32_t> index;
    std::vector<uint32_t> texels;
    std::array<std::vector<float>, 3> boxes;
  };
  std::vector<ObbLevel> cpu_obb;
  bool uploaded = false;  ///< the trim textures and the oriented pyramid are on the GPU (ensure_uploaded)

  /// Texture k of a sparse oriented level expanded to its n texels (empty boxes elsewhere).
  [[nodiscard]] static std::vector<float> expand_level(const ObbLevel& level, int k, size_t n);
  /// Uploads trim_cell, trim_head and trim_segs (padding the last two to whole rows).
  void upload_trim_textures(const AtlasPlan& plan);
  /// Uploads cpu_obb into obb, level by level expanded to every texel.
  void upload_oriented_pyramid();
};

}  // namespace queries
