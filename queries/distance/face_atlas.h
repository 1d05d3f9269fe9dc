#pragma once
/// \file face_atlas.h
/// Many faces at once ("faces are batched"): the grids of a model's faces packed into one
/// atlas texture by skyline packing, evaluated in one pass (glsl/distance/surface_eval_atlas.frag, the batched
/// form of the tabulated method) and trimmed in one even-odd fill, so a model of hundreds of faces
/// costs a few passes per batch instead of a few per face. Faces whose grid exceeds the tile side
/// are left to the tiled single-face path (surface_grid.h).
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/trimmed_surface.h"

namespace queries {

/// Where one face's grid sits in an atlas: samples (i, j) at texel (x + i, y + j).
struct AtlasSlot {
  int face = 0;  ///< index into the caller's face list
  int x = 0, y = 0, width = 0, height = 0;
};

/// One atlas: its size and slots (the packing, no GPU work yet).
struct AtlasPlan {
  int width = 0, height = 0;
  std::vector<AtlasSlot> slots;
};

/// Packs grids of the given sizes (samples along u, v) into atlases of at most side x side texels
/// and at most max_samples texels each: skyline bottom-left packing, tallest grids first, into the
/// strip width (from the widest grid's to the side) that holds them in the fewest texels padded to
/// powers of two (the point pyramid's size), the side's when no width holds them all (the rest go
/// on to the next atlas). Grids larger than side in either direction are not packed (the caller
/// tiles them alone); `unpacked` lists them.
///
/// Every slot starts at a multiple of `align` texels, its grid padded to a multiple of it (up to the
/// side): the nodes of the box pyramids and hierarchies built over an atlas (2^l x 2^l texels at
/// level l) then hold one face's cells up to level log2(align), where nodes that straddle a slot
/// edge would merge the boxes of faces far apart in space, and a point would descend into them. The
/// price is texels: thin strips and tiny grids pad most, and a taller atlas may double the padded
/// pyramid (experiments/real_models.py prints the time and peak memory per model).
inline constexpr int kSlotAlign = 16;
std::vector<AtlasPlan> plan_atlases(const std::vector<std::pair<int, int>>& sizes, int side, long long max_samples,
                                    std::vector<int>& unpacked, int align = kSlotAlign);

/// An evaluated atlas: the points (x, y, z, w) of every slot, RGBA32F, zero outside the slots; and
/// the trim mask (R8, 1 = material) on the same texels. The boxes need the points alone (the
/// paper's four neighbours and K), so no normals are evaluated: a texture and the derivative sums
/// less.
struct FaceAtlas {
  AtlasPlan plan;
  gpgpu::Texture points, mask;
  gpgpu::Texture slot_of;  ///< R32F: the slot index of each texel, -1 outside the slots
};

/// Evaluates every slot's face (faces[slot.face]) on its grid (grids[slot.face]) in one pass and
/// renders all trim masks in one fill. `flatten_tolerance[f]` is in parameter units of face f.
/// Atlases of faces without trim loops upload their slots' rectangles as the mask (no fill pass).
FaceAtlas evaluate_atlas(gpgpu::Gpu& gpu, const AtlasPlan& plan, const std::vector<nurbs::TrimmedSurface>& faces,
                         const std::vector<nurbs::ParamGrid>& grids, const std::vector<double>& flatten_tolerance);

/// The evaluation program of evaluate_atlas (compiled on first use; callers may compile it ahead).
gpgpu::Program& atlas_program(gpgpu::Gpu& gpu);

}  // namespace queries
