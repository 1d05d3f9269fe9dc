#pragma once
/// \file framebuffer.h
/// A framebuffer object over colour textures (RAII). Completeness is checked when it is created:
/// an incomplete one throws FramebufferError naming the GL status.
#include <GL/glcorearb.h>

#include <span>
#include <stdexcept>

#include "gpgpu/texture.h"

namespace gpgpu {

class FramebufferError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Framebuffer {
 public:
  Framebuffer();  ///< no attachments yet
  /// Attaches the textures as colour attachments 0..n-1 and checks completeness.
  explicit Framebuffer(std::span<const GLuint> color_textures);
  explicit Framebuffer(std::span<Texture* const> color_textures);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  [[nodiscard]] GLuint id() const { return id_; }
  /// Replaces the colour attachments (detaching the previous ones) and checks completeness.
  void attach(std::span<const GLuint> color_textures);
  /// The same with mip level `level` of every texture attached.
  void attach(std::span<const GLuint> color_textures, int level);
  /// Detaches every colour attachment, so no texture stays referenced by this object.
  void detach();

 private:
  GLuint id_ = 0;
  int attached_ = 0;
};

}  // namespace gpgpu
