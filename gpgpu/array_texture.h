#pragma once
/// \file array_texture.h
/// Upload of a long 1D array of records into a 2D texture (gpgpu/layout.h), padding the last row
/// with a caller-chosen value (the neutral element of the reduction that will read it).
#include <span>

#include "gpgpu/layout.h"
#include "gpgpu/texture.h"

namespace gpgpu {

struct ArrayTexture {
  Layout2D layout;
  Texture texture;
};

/// `values` holds count * channels(format) floats (float formats only). Texels past `count` get
/// `pad` in every channel. `max_size` is GL_MAX_TEXTURE_SIZE (Gpu::info().max_texture_size).
ArrayTexture upload_array(std::span<const float> values, Format format, int max_size, float pad);

/// The same with a power-of-two width (layout_pow2): kernels index it with pow2_texel.
ArrayTexture upload_array_pow2(std::span<const float> values, Format format, int max_size, float pad);

}  // namespace gpgpu
