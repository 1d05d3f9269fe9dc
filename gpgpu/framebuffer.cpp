#include "gpgpu/framebuffer.h"

#include <fmt/format.h>

#include <vector>

#include "gpgpu/gl_api.h"

namespace gpgpu {

Framebuffer::Framebuffer() { gl::CreateFramebuffers(1, &id_); }

Framebuffer::Framebuffer(std::span<const GLuint> color_textures) : Framebuffer() { attach(color_textures); }

Framebuffer::Framebuffer(std::span<Texture* const> color_textures) : Framebuffer() {
  std::vector<GLuint> ids;
  for (const Texture* t : color_textures) ids.push_back(t->id());
  attach(ids);
}

Framebuffer::~Framebuffer() {
  if (id_ != 0) gl::DeleteFramebuffers(1, &id_);
}

void Framebuffer::attach(std::span<const GLuint> color_textures) { attach(color_textures, 0); }

void Framebuffer::attach(std::span<const GLuint> color_textures, int level) {
  detach();
  std::vector<GLenum> buffers;
  for (size_t i = 0; i < color_textures.size(); ++i) {
    gl::NamedFramebufferTexture(id_, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), color_textures[i], level);
    buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  }
  attached_ = static_cast<int>(color_textures.size());
  if (!buffers.empty()) gl::NamedFramebufferDrawBuffers(id_, static_cast<GLsizei>(buffers.size()), buffers.data());
  gl::check_error("attaching framebuffer textures");
  const GLenum status = gl::CheckNamedFramebufferStatus(id_, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw FramebufferError(fmt::format("framebuffer incomplete: {} ({} colour attachment(s){})", gl::enum_name(status),
                                       color_textures.size(), level == 0 ? "" : fmt::format(", level {}", level)));
}

void Framebuffer::detach() {
  for (int i = 0; i < attached_; ++i)
    gl::NamedFramebufferTexture(id_, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), 0, 0);
  attached_ = 0;
}

}  // namespace gpgpu
