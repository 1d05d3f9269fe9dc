#include "gpgpu/array_texture.h"

#include <fmt/format.h>

#include <stdexcept>
#include <vector>

namespace gpgpu {

namespace {

ArrayTexture upload(std::span<const float> values, Format format, float pad, Layout2D (*layout)(int64_t, int),
                    int max_size) {
  const int ch = channels(format);
  if (is_integer(format) || format == Format::R8 || values.size() % size_t(ch) != 0)
    throw std::invalid_argument(
        fmt::format("upload_array: {} values do not make {} records", values.size(), format_name(format)));
  ArrayTexture a{layout(int64_t(values.size() / size_t(ch)), max_size), {}};
  a.texture = Texture(a.layout.width, a.layout.height, format);
  const size_t full = size_t(a.layout.width) * size_t(a.layout.height) * size_t(ch);
  if (values.size() == full) {
    a.texture.upload(values);
  } else {
    std::vector<float> padded(values.begin(), values.end());
    padded.resize(full, pad);
    a.texture.upload(padded);
  }
  return a;
}

}  // namespace

ArrayTexture upload_array(std::span<const float> values, Format format, int max_size, float pad) {
  return upload(values, format, pad, layout_for, max_size);
}

ArrayTexture upload_array_pow2(std::span<const float> values, Format format, int max_size, float pad) {
  return upload(values, format, pad, layout_pow2, max_size);
}

}  // namespace gpgpu
