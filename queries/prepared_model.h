#pragma once
/// \file prepared_model.h
/// A model prepared for distance queries (Krishnamurthy et al. §3-5): every face on its certified
/// grid (K_e <= tolerance on every cell), all faces evaluated in atlases with their trim masks
/// (face_atlas.h), and per atlas slot the growth of its cell boxes: K_e plus the float budget of
/// the GPU samples. Evaluated once; queries reuse it.
#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/certified_grid.h"
#include "nurbs/trim_classify.h"
#include "nurbs/trimmed_surface.h"
#include "queries/face_atlas.h"

namespace queries {

/// A grid cell of one face: cell (i, j) of faces[face].
struct FaceCell {
  int face = -1, i = 0, j = 0;
};

struct PreparedModel {
  std::vector<nurbs::TrimmedSurface> faces;
  std::vector<nurbs::FilipBound> bounds;
  std::vector<nurbs::CertifiedGrid> grids;
  std::vector<FaceAtlas> atlases;
  std::vector<gpgpu::Texture> grow;  ///< per atlas: R32F, one texel per slot
  /// Per face: its trim loops flattened within 1e-6 of its u domain width, for classifying the
  /// closest points the queries find (empty for untrimmed faces).
  std::vector<nurbs::TrimPolygons> trims;
  glm::dvec3 centre{0.0};  ///< centre of the control-point box of all faces

  /// The cell whose lower-left sample is texel (x, y) of atlas `a`, if that texel starts a cell.
  [[nodiscard]] std::optional<FaceCell> cell_at(size_t a, int x, int y) const;
};

/// Prepares `faces` for queries at K_e <= `tolerance` (model units). Throws std::runtime_error
/// naming a face that cannot meet it within `max_samples`, and std::length_error when a face's grid
/// is larger than an atlas of the GPU's size.
PreparedModel prepare_model(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                            long long max_samples = 1LL << 22);

/// Float budget of one face's GPU samples: the tabulated evaluation's measured error (1.0e-7 of the
/// control box, surface_grid.h) with a factor 10, plus 4 ulp of the largest coordinate (the atlas
/// adds each face's origin back in float).
[[nodiscard]] double float_budget(const nurbs::Surface& s);

}  // namespace queries
