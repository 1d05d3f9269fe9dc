#pragma once
/// \file shaders.h
/// The papers' kernels (glsl/distance/, glsl/raycast/), embedded into this library; gpgpu embeds its
/// own alone. Every queries pass gets its program here: the first call on a Gpu adds these files to
/// its shader library.
#include <span>
#include <string>
#include <string_view>

#include "gpgpu/gpu.h"
#include "gpgpu/shader_library.h"

namespace gpgpu {
std::span<const ShaderFile> distance_glsl();  ///< glsl/distance/, embedded by queries/CMakeLists.txt
std::span<const ShaderFile> raycast_glsl();   ///< glsl/raycast/, embedded by queries/CMakeLists.txt
}  // namespace gpgpu

namespace queries {

/// gpu.program(name, defines) with the papers' kernels added to the Gpu's shader library.
gpgpu::Program& program(gpgpu::Gpu& gpu, std::string_view name, const gpgpu::Defines& defines = {});

}  // namespace queries
