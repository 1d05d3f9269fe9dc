#pragma once
/// \file trim_texture.h
/// Trim textures (Krishnamurthy et al. §5.3, their ref. [27]): an R8 mask of the same samples as the
/// evaluated surface (surface_grid.h); texel (i, j) is 1 where (u_i, v_j) is material. The trim
/// loops are flattened (nurbs/trim_classify.h) and filled even-odd with the stencil
/// (gpgpu/polygon_fill.h), which equals the CPU classification for properly nested loops (outer
/// loops containing their holes, as in a valid B-rep face) except at samples within about one grid
/// cell of a trim curve (flattening and rasterisation of edges through sample points).
///
/// Knot-aligned grids (nurbs/distance/certified_grid.h) have one step per segment: parameters map to window
/// coordinates piecewise linearly. Polygon edges are split where they cross a segment end, so each
/// piece maps to a straight window segment and the fill classifies the samples as in (u, v).
#include <glm/vec2.hpp>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/trimmed_surface.h"

namespace queries {

/// The face's trim loops (split at the grid's segment ends), or the domain rectangle when it has no
/// outer loop, in window coordinates of the grid: sample (i, j) at (i + 0.5, j + 0.5). Filled
/// even-odd they give the trim mask; the atlas (face_atlas.h) offsets them into its slots.
std::vector<std::vector<glm::vec2>> trim_window_polygons(const nurbs::TrimmedSurface& face,
                                                         const nurbs::ParamGrid& params, double flatten_tolerance);

/// The flattening tolerance the trim masks of a grid use: a tenth of its smallest step (parameter
/// units), fine enough that flattening moves only samples within it of a trim curve.
[[nodiscard]] inline double trim_flatten_tolerance(const nurbs::ParamGrid& g) { return 0.1 * g.min_step(); }

/// One R8 mask per tile of the grid `params` cut in tiles of `tile_side` samples (the tiling of
/// evaluate_surface: tiles share boundary samples), row-major. Faces without loops are all material;
/// faces with holes but no outer loop get the domain rectangle as outer boundary. `flatten_tolerance`
/// is in parameter units (a fraction of a grid step is enough).
std::vector<gpgpu::Texture> trim_masks(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face,
                                       const nurbs::ParamGrid& params, int tile_side, double flatten_tolerance);

/// The mask of a grid that fits one texture, and of the uniform n x m grid.
gpgpu::Texture trim_texture(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, const nurbs::ParamGrid& params,
                            double flatten_tolerance);
gpgpu::Texture trim_texture(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, int n, int m, double flatten_tolerance);

/// Reference classification of the same samples by nurbs::is_material (winding numbers), row-major
/// with i fastest: 1 = material.
std::vector<uint8_t> trim_mask_cpu(const nurbs::TrimmedSurface& face, const nurbs::ParamGrid& params,
                                   double flatten_tolerance);
std::vector<uint8_t> trim_mask_cpu(const nurbs::TrimmedSurface& face, int n, int m, double flatten_tolerance);

}  // namespace queries
