#pragma once
/// \file polygon_fill.h
/// Even-odd fill of closed polygons into an R8 mask by the stencil-invert method: every polygon is
/// drawn as a triangle fan that inverts one stencil bit, so a texel ends with the bit set iff its
/// centre is inside an odd number of polygons; a second pass writes 1 there, 0 elsewhere. This is
/// how trim textures are made (Krishnamurthy et al. §5.3, their ref. [27]). Texels whose centre
/// lies on an edge follow GL's rasterisation rule.
#include <glm/vec2.hpp>
#include <vector>

#include "gpgpu/gpu.h"

namespace gpgpu {

/// `polygons` in window coordinates of `target` (texel (i, j) has centre (i + 0.5, j + 0.5));
/// each is closed implicitly. `target` must be R8 (or any colour format: 1.0 inside, 0.0 outside).
void fill_polygons_even_odd(Gpu& gpu, const std::vector<std::vector<glm::vec2>>& polygons, Texture& target);

/// Compiles fill_polygons_even_odd's programs ahead of its first call (otherwise on first use).
void compile_polygon_fill(Gpu& gpu);

/// CPU twin: the same even-odd rule on texel centres (edges exactly through a centre may differ).
std::vector<uint8_t> fill_polygons_even_odd_cpu(const std::vector<std::vector<glm::vec2>>& polygons, int width,
                                                int height);

}  // namespace gpgpu
