#include "gpgpu/texture.h"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "gpgpu/gl_api.h"

namespace gpgpu {
namespace {

GLenum internal_format(Format f) {
  switch (f) {
    case Format::R8:
      return GL_R8;
    case Format::R32F:
      return GL_R32F;
    case Format::RG32F:
      return GL_RG32F;
    case Format::RGBA32F:
      return GL_RGBA32F;
    case Format::R32UI:
      return GL_R32UI;
  }
  return GL_NONE;
}

GLenum pixel_format(Format f) {
  switch (f) {
    case Format::R8:
    case Format::R32F:
      return GL_RED;
    case Format::RG32F:
      return GL_RG;
    case Format::RGBA32F:
      return GL_RGBA;
    case Format::R32UI:
      return GL_RED_INTEGER;
  }
  return GL_NONE;
}

}  // namespace

int channels(Format f) { return f == Format::RG32F ? 2 : f == Format::RGBA32F ? 4 : 1; }
bool is_integer(Format f) { return f == Format::R32UI; }
std::string_view format_name(Format f) {
  switch (f) {
    case Format::R8:
      return "R8";
    case Format::R32F:
      return "R32F";
    case Format::RG32F:
      return "RG32F";
    case Format::RGBA32F:
      return "RGBA32F";
    case Format::R32UI:
      return "R32UI";
  }
  return "?";
}

Texture::Texture(int width, int height, Format format) : Texture(width, height, format, 1) {}

Texture::Texture(int width, int height, Format format, int levels)
    : width_(width), height_(height), levels_(levels), format_(format) {
  GLint max_size = 0;
  gl::GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw std::invalid_argument(
        fmt::format("texture size {}x{} outside 1..GL_MAX_TEXTURE_SIZE ({})", width, height, max_size));
  int max_levels = 1;
  while ((std::max(width, height) >> max_levels) > 0) ++max_levels;
  if (levels < 1 || levels > max_levels)
    throw std::invalid_argument(
        fmt::format("{} mip levels for a {}x{} texture (it can have 1..{})", levels, width, height, max_levels));
  gl::CreateTextures(GL_TEXTURE_2D, 1, &id_);
  gl::TextureStorage2D(id_, levels, internal_format(format), width, height);
  // NEAREST everywhere: integer textures are incomplete with linear filters. With mip levels the
  // minification filter names them, so every level belongs to the texture's fetchable range.
  gl::TextureParameteri(id_, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
  gl::TextureParameteri(id_, GL_TEXTURE_MAX_LEVEL, levels - 1);
  gl::TextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl::TextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl::TextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl::check_error("creating a texture");
}

Texture::~Texture() {
  if (id_ != 0) gl::DeleteTextures(1, &id_);
}

Texture::Texture(Texture&& o) noexcept
    : id_(std::exchange(o.id_, 0)), width_(o.width_), height_(o.height_), levels_(o.levels_), format_(o.format_) {}

Texture& Texture::operator=(Texture&& o) noexcept {
  if (this != &o) {
    if (id_ != 0) gl::DeleteTextures(1, &id_);
    id_ = std::exchange(o.id_, 0);
    width_ = o.width_;
    height_ = o.height_;
    levels_ = o.levels_;
    format_ = o.format_;
  }
  return *this;
}

Region Texture::clip(Region r) const {
  if (r.width <= 0) r.width = width_ - r.x;
  if (r.height <= 0) r.height = height_ - r.y;
  if (r.x < 0 || r.y < 0 || r.width < 1 || r.height < 1 || r.x + r.width > width_ || r.y + r.height > height_)
    throw std::out_of_range(
        fmt::format("region {}x{} at ({}, {}) outside a {}x{} texture", r.width, r.height, r.x, r.y, width_, height_));
  return r;
}

void Texture::upload_raw(const void* data, size_t count, size_t elem, GLenum type, Region region) {
  const Region r = clip(region);
  const size_t need = size_t(r.width) * r.height * channels(format_);
  if (count != need)
    throw std::invalid_argument(fmt::format("upload of {} values into a {}x{} {} region needs {}", count, r.width,
                                            r.height, format_name(format_), need));
  (void)elem;
  gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl::TextureSubImage2D(id_, 0, r.x, r.y, r.width, r.height, pixel_format(format_), type, data);
  gl::check_error("uploading a texture");
}

void Texture::upload(std::span<const float> d, Region r) {
  if (is_integer(format_)) throw std::invalid_argument("float upload into an integer texture");
  upload_raw(d.data(), d.size(), sizeof(float), GL_FLOAT, r);
}
void Texture::upload(std::span<const uint8_t> d, Region r) {
  if (format_ != Format::R8) throw std::invalid_argument("uint8 upload needs an R8 texture");
  upload_raw(d.data(), d.size(), 1, GL_UNSIGNED_BYTE, r);
}
void Texture::upload(std::span<const uint32_t> d, Region r) {
  if (!is_integer(format_)) throw std::invalid_argument("uint32 upload needs an R32UI texture");
  upload_raw(d.data(), d.size(), 4, GL_UNSIGNED_INT, r);
}

void Texture::upload_level(int level, std::span<const float> d) {
  if (is_integer(format_)) throw std::invalid_argument("float upload into an integer texture");
  if (level < 0 || level >= levels_)
    throw std::out_of_range(fmt::format("mip level {} of a texture with {} level(s)", level, levels_));
  const int w = level_width(level), h = level_height(level);
  const size_t need = size_t(w) * size_t(h) * size_t(channels(format_));
  if (d.size() != need)
    throw std::invalid_argument(fmt::format("upload of {} values into level {} ({}x{} {}) needs {}", d.size(), level, w,
                                            h, format_name(format_), need));
  gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl::TextureSubImage2D(id_, level, 0, 0, w, h, pixel_format(format_), GL_FLOAT, d.data());
  gl::check_error("uploading a texture level");
}

std::vector<float> Texture::read(Region region) const {
  if (is_integer(format_)) throw std::invalid_argument("float read of an integer texture; use read_u32");
  const Region r = clip(region);
  std::vector<float> out(size_t(r.width) * r.height * channels(format_));
  gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl::GetTextureSubImage(id_, 0, r.x, r.y, 0, r.width, r.height, 1, pixel_format(format_), GL_FLOAT,
                         static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
  gl::check_error("reading a texture back");
  return out;
}

std::vector<float> Texture::read_level(int level) const {
  if (is_integer(format_)) throw std::invalid_argument("float read of an integer texture; use read_u32");
  if (level < 0 || level >= levels_)
    throw std::out_of_range(fmt::format("mip level {} of a texture with {} level(s)", level, levels_));
  const int w = level_width(level), h = level_height(level);
  std::vector<float> out(size_t(w) * size_t(h) * size_t(channels(format_)));
  gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl::GetTextureSubImage(id_, level, 0, 0, 0, w, h, 1, pixel_format(format_), GL_FLOAT,
                         static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
  gl::check_error("reading a texture level back");
  return out;
}

std::vector<uint32_t> Texture::read_u32(Region region) const {
  if (!is_integer(format_)) throw std::invalid_argument("read_u32 of a float texture; use read");
  const Region r = clip(region);
  std::vector<uint32_t> out(size_t(r.width) * r.height);
  gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl::GetTextureSubImage(id_, 0, r.x, r.y, 0, r.width, r.height, 1, GL_RED_INTEGER, GL_UNSIGNED_INT,
                         static_cast<GLsizei>(out.size() * sizeof(uint32_t)), out.data());
  gl::check_error("reading a texture back");
  return out;
}

}  // namespace gpgpu
