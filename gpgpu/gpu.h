#pragma once
/// \file gpu.h
/// The GPU co-processor of Krishnamurthy et al. §1.1 (Fig. 3): a context, the embedded kernels, a
/// pass runner (full-screen triangle into target textures, every piece of state set explicitly and
/// reset afterwards), a texture pool for ping-pong and pyramid levels, the profiler and EXR dumps.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>

#include "gpgpu/context.h"
#include "gpgpu/framebuffer.h"
#include "gpgpu/profiler.h"
#include "gpgpu/program.h"
#include "gpgpu/texture.h"

namespace gpgpu {

/// A kernel input: the sampler uniform name (array elements as "u_levels[3]") and its texture.
/// `level` >= 0 shows the pass only that mip level (as its lod 0: base = max level), so a pass may
/// read one level of a texture while it renders into another (a box pyramid built level by level).
struct Input {
  std::string sampler;
  const Texture* texture = nullptr;
  int level = -1;
};

class Gpu;

/// A texture borrowed from the pool; goes back to it when destroyed.
class PooledTexture {
 public:
  PooledTexture() = default;
  PooledTexture(Gpu* owner, Texture texture) : owner_(owner), texture_(std::move(texture)) {}
  ~PooledTexture();
  PooledTexture(PooledTexture&& o) noexcept = default;
  PooledTexture& operator=(PooledTexture&& o) noexcept;
  Texture& operator*() { return texture_; }
  Texture* operator->() { return &texture_; }
  Texture* get() { return &texture_; }

 private:
  Gpu* owner_ = nullptr;
  Texture texture_;
};

class Gpu {
 public:
  /// Creates the context (see Context::create) and the pass machinery.
  explicit Gpu(const ContextOptions& options = {});
  explicit Gpu(std::unique_ptr<Context> context);
  ~Gpu();
  Gpu(const Gpu&) = delete;
  Gpu& operator=(const Gpu&) = delete;

  [[nodiscard]] const ContextInfo& info() const { return context_->info(); }
  [[nodiscard]] Context& context() { return *context_; }
  [[nodiscard]] Profiler& profiler() { return profiler_; }
  [[nodiscard]] ShaderLibrary& shaders() { return shaders_; }

  /// The program fullscreen.vert + `fragment` with `defines`, compiled once and cached.
  Program& program(const std::string& fragment, const Defines& defines = {});
  /// The same with another vertex stage (e.g. polygon.vert for rasterised geometry).
  Program& program(const std::string& vertex, const std::string& fragment, const Defines& defines);
  /// Programs compiled so far (each vertex + fragment + defines once).
  [[nodiscard]] size_t program_count() const { return programs_.size(); }
  /// Deletes every compiled program (they compile again on demand): tests of which programs a
  /// computation uses start from none. No program reference may be held across it.
  void forget_programs() { programs_.clear(); }

  /// Runs one pass: binds `outputs` (checked for completeness), the viewport (whole first output
  /// unless `viewport` is given), `inputs` on texture units 0..n-1, blend/depth/scissor/stencil off,
  /// draws the full-screen triangle, then unbinds everything. Timed under `name`. Throws
  /// std::invalid_argument, naming the pass, the program and the sampler, when an input's sampler is
  /// not an active uniform of `program` or an input texture is also an output (unless the input
  /// shows only another level than `output_level`). `output_level`: the mip level rendered into
  /// (the default viewport is that level's size).
  void run(std::string_view name, const Program& program, std::span<const Input> inputs,
           std::span<Texture* const> outputs, std::optional<Region> viewport = std::nullopt, int output_level = 0);

  /// Waits until every submitted pass has finished (glFinish): for wall-clock timing.
  void finish();

  /// A texture of this size and format from the pool (allocated when none is free).
  PooledTexture acquire(int width, int height, Format format);
  void release(Texture texture);

  /// Writes `texture` to DIR/NNN_name.exr when a dump folder is set (see set_dump_dir); no-op else.
  void dump(std::string_view name, const Texture& texture);
  void set_dump_dir(std::filesystem::path dir);
  [[nodiscard]] const std::optional<std::filesystem::path>& dump_dir() const { return dump_dir_; }

 private:
  void init();
  std::unique_ptr<Context> context_;
  ShaderLibrary shaders_;
  std::map<std::string, Program> programs_;
  Profiler profiler_;
  std::unique_ptr<Framebuffer> framebuffer_;
  GLuint vao_ = 0;
  std::multimap<std::tuple<int, int, int>, Texture> pool_;
  std::optional<std::filesystem::path> dump_dir_;
  int dump_counter_ = 0;
};

}  // namespace gpgpu
