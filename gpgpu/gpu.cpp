#include "gpgpu/gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "gpgpu/exr_dump.h"
#include "gpgpu/gl_api.h"

namespace gpgpu {
namespace {

/// The mip levels a sampler sees (texelFetch's lod counts from `base`).
void set_level_range(GLuint texture, int base, int max) {
  gl::TextureParameteri(texture, GL_TEXTURE_BASE_LEVEL, base);
  gl::TextureParameteri(texture, GL_TEXTURE_MAX_LEVEL, max);
}

}  // namespace

PooledTexture::~PooledTexture() {
  if (owner_ != nullptr && texture_.id() != 0) owner_->release(std::move(texture_));
}

PooledTexture& PooledTexture::operator=(PooledTexture&& o) noexcept {
  if (this != &o) {
    if (owner_ != nullptr && texture_.id() != 0) owner_->release(std::move(texture_));
    owner_ = o.owner_;
    texture_ = std::move(o.texture_);
  }
  return *this;
}

Gpu::Gpu(const ContextOptions& options) : context_(Context::create(options)) { init(); }

Gpu::Gpu(std::unique_ptr<Context> context) : context_(std::move(context)) { init(); }

void Gpu::init() {
  profiler_.set_timer_queries(context_->info().timer_queries);
  shaders_.add(embedded_glsl(), "glsl/gpgpu/");
  framebuffer_ = std::make_unique<Framebuffer>();
  gl::CreateVertexArrays(1, &vao_);
  gl::check_error("creating the pass machinery");
}

Gpu::~Gpu() {
  pool_.clear();
  programs_.clear();
  framebuffer_.reset();
  if (vao_ != 0) gl::DeleteVertexArrays(1, &vao_);
}

Program& Gpu::program(const std::string& fragment, const Defines& defines) {
  return program("fullscreen.vert", fragment, defines);
}

Program& Gpu::program(const std::string& vertex, const std::string& fragment, const Defines& defines) {
  std::string key = vertex + "+" + fragment;
  for (const auto& [k, v] : defines) key += fmt::format("|{}={}", k, v);
  auto it = programs_.find(key);
  if (it == programs_.end()) it = programs_.emplace(key, Program(shaders_, vertex, fragment, defines)).first;
  return it->second;
}

void Gpu::run(std::string_view name, const Program& program, std::span<const Input> inputs,
              std::span<Texture* const> outputs, std::optional<Region> viewport, int output_level) {
  std::vector<GLuint> ids;
  for (const Texture* t : outputs) ids.push_back(t->id());
  // Checked before any GL state changes: a bad pass throws and leaves nothing bound.
  std::vector<GLint> samplers;
  for (const Input& in : inputs) {
    try {
      samplers.push_back(program.active_location(in.sampler));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("pass '{}': {}", name, e.what()));
    }
    // Reading a texture while rendering into it is a feedback loop: undefined results (GL 4.5 §9.3),
    // unless the pass sees only other levels than the one rendered (§9.3.1).
    const bool other_level = in.level >= 0 && in.level != output_level;
    if (in.level >= in.texture->levels())
      throw std::invalid_argument(fmt::format("pass '{}': sampler '{}' reads level {} of a texture with {} level(s)",
                                              name, in.sampler, in.level, in.texture->levels()));
    if (!other_level && std::find(ids.begin(), ids.end(), in.texture->id()) != ids.end())
      throw std::invalid_argument(
          fmt::format("pass '{}' (program {}): sampler '{}' reads texture {}, which it also writes", name,
                      program.name(), in.sampler, in.texture->id()));
  }
  framebuffer_->attach(ids, output_level);  // throws FramebufferError when incomplete (no outputs, bad texture)
  const Region vp =
      viewport.value_or(Region{0, 0, outputs[0]->level_width(output_level), outputs[0]->level_height(output_level)});

  profiler_.begin(name);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_->id());
  gl::Viewport(vp.x, vp.y, vp.width, vp.height);
  for (GLenum cap : {GL_BLEND, GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_CULL_FACE, GL_DITHER})
    gl::Disable(cap);
  for (GLuint i = 0; i < ids.size(); ++i) gl::ColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl::UseProgram(program.id());
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i].level >= 0) set_level_range(inputs[i].texture->id(), inputs[i].level, inputs[i].level);
    gl::BindTextureUnit(static_cast<GLuint>(i), inputs[i].texture->id());
    gl::ProgramUniform1i(program.id(), samplers[i], static_cast<int>(i));
  }
  gl::BindVertexArray(vao_);
  gl::DrawArrays(GL_TRIANGLES, 0, 3);

  gl::BindVertexArray(0);
  for (size_t i = 0; i < inputs.size(); ++i) {
    gl::BindTextureUnit(static_cast<GLuint>(i), 0);
    if (inputs[i].level >= 0) set_level_range(inputs[i].texture->id(), 0, inputs[i].texture->levels() - 1);
  }
  gl::UseProgram(0);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  profiler_.end();
  framebuffer_->detach();
  gl::check_error(std::string(name).c_str());
}

void Gpu::finish() { gl::Finish(); }

PooledTexture Gpu::acquire(int width, int height, Format format) {
  auto it = pool_.find({width, height, static_cast<int>(format)});
  if (it != pool_.end()) {
    Texture t = std::move(it->second);
    pool_.erase(it);
    return PooledTexture(this, std::move(t));
  }
  return PooledTexture(this, Texture(width, height, format));
}

void Gpu::release(Texture texture) {
  const std::tuple<int, int, int> key{texture.width(), texture.height(), static_cast<int>(texture.format())};
  pool_.emplace(key, std::move(texture));
}

void Gpu::set_dump_dir(std::filesystem::path dir) {
  std::filesystem::create_directories(dir);
  dump_dir_ = std::move(dir);
}

void Gpu::dump(std::string_view name, const Texture& texture) {
  if (!dump_dir_) return;
  write_exr(*dump_dir_ / fmt::format("{:03d}_{}.exr", dump_counter_++, name), texture);
}

}  // namespace gpgpu
