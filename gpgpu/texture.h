#pragma once
/// \file texture.h
/// 2D textures with immutable storage and NEAREST sampling (every kernel reads with texelFetch).
/// Float formats for data, R8 for masks, R32UI for exact counts (stream compaction).
/// A texture may hold mip levels (box hierarchies stored mip-style, Krishnamurthy et al. §5.1):
/// level l is max(1, width >> l) x max(1, height >> l), a pass renders into one level
/// (Gpu::run's output_level) and a kernel reads any with texelFetch(sampler, p, l).
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace gpgpu {

enum class Format { R8, R32F, RG32F, RGBA32F, R32UI };

[[nodiscard]] int channels(Format f);
[[nodiscard]] bool is_integer(Format f);
[[nodiscard]] std::string_view format_name(Format f);

/// A texel rectangle; width/height <= 0 mean "to the texture's edge".
struct Region {
  int x = 0, y = 0, width = 0, height = 0;
};

class Texture {
 public:
  Texture() = default;
  /// Allocates width x height texels (1 <= size <= GL_MAX_TEXTURE_SIZE); contents undefined.
  Texture(int width, int height, Format format);
  /// The same with `levels` mip levels (1 <= levels <= 1 + log2(max(width, height))).
  Texture(int width, int height, Format format, int levels);
  ~Texture();
  Texture(Texture&& other) noexcept;
  Texture& operator=(Texture&& other) noexcept;
  Texture(const Texture&) = delete;
  Texture& operator=(const Texture&) = delete;

  [[nodiscard]] GLuint id() const { return id_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] Format format() const { return format_; }
  [[nodiscard]] int64_t texels() const { return int64_t(width_) * height_; }
  [[nodiscard]] int levels() const { return levels_; }
  [[nodiscard]] int level_width(int level) const { return std::max(1, width_ >> level); }
  [[nodiscard]] int level_height(int level) const { return std::max(1, height_ >> level); }

  /// Uploads channels(format) values per texel, row-major from row 0 (texel (0,0) first).
  /// Float data for float formats and R8 (0..1), uint8 for R8, uint32 for R32UI.
  void upload(std::span<const float> data, Region region = {});
  void upload(std::span<const uint8_t> data, Region region = {});
  void upload(std::span<const uint32_t> data, Region region = {});

  /// Uploads the whole mip level `level` (float formats): channels(format) values per texel of
  /// level_width(level) x level_height(level), row-major.
  void upload_level(int level, std::span<const float> data);

  /// Reads back a region as floats (R8 as 0..1), channels(format) per texel, row-major.
  [[nodiscard]] std::vector<float> read(Region region = {}) const;
  [[nodiscard]] std::vector<uint32_t> read_u32(Region region = {}) const;
  /// Reads back mip level `level` (whole level) as floats, channels(format) per texel, row-major.
  [[nodiscard]] std::vector<float> read_level(int level) const;

 private:
  Region clip(Region r) const;
  void upload_raw(const void* data, size_t bytes, size_t elem, GLenum type, Region region);
  GLuint id_ = 0;
  int width_ = 0, height_ = 0, levels_ = 1;
  Format format_ = Format::RGBA32F;
};

}  // namespace gpgpu
