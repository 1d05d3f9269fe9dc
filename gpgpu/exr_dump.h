#pragma once
/// \file exr_dump.h
/// OpenEXR dumps of textures for inspection (`--dump DIR`). Float textures become FLOAT channels
/// R, G, B, A (as many as the format has); R32UI becomes a UINT channel R; R8 a FLOAT channel R in
/// 0..1. EXR row y holds texel row y (no flip), so pixel (x, y) in a viewer is texel (x, y).
#include <filesystem>
#include <string>
#include <vector>

#include "gpgpu/texture.h"

namespace gpgpu {

/// Reads `texture` back and writes it to `path`. Throws std::runtime_error on I/O failure.
void write_exr(const std::filesystem::path& path, const Texture& texture);

/// An EXR image read back (for tests and tools): channel names in file order and interleaved values
/// (UINT channels converted to float).
struct ExrImage {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  std::vector<float> values;
};
ExrImage read_exr(const std::filesystem::path& path);

/// Writes an image of FLOAT channels (row y = image row y). Throws std::invalid_argument when the
/// values do not fill width x height x channels, std::runtime_error on I/O failure.
void write_exr(const std::filesystem::path& path, const ExrImage& image);

}  // namespace gpgpu
