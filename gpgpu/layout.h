#pragma once
/// \file layout.h
/// Long 1D arrays laid out row-major in a 2D texture within GL_MAX_TEXTURE_SIZE: element i sits at
/// texel (i % width, i / width). Kernels use the same rule (glsl/gpgpu/lib_layout.glsl).
#include <cstdint>

namespace gpgpu {

struct Layout2D {
  int64_t count = 0;  ///< elements stored
  int width = 1;
  int height = 1;
  [[nodiscard]] int64_t capacity() const { return int64_t(width) * height; }
};

/// A near-square layout for `count` elements (fewer reduction passes than 1 x N), at least 1x1.
/// Throws std::length_error when count > max_size^2.
Layout2D layout_for(int64_t count, int max_size);

/// A layout whose width is a power of two (at most max_size, and no wider than needed), so kernels
/// find element i at (i & (width - 1), i >> log2(width)) with no integer division, which llvmpipe
/// has no vector instruction for (glsl/gpgpu/lib_layout.glsl, pow2_texel). Used for arrays read many
/// times per fragment (control points, basis tables, knots).
Layout2D layout_pow2(int64_t count, int max_size);

}  // namespace gpgpu
