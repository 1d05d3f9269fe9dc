#include "gpgpu/context.h"

#include <fmt/format.h>

#include <array>
#include <algorithm>
#include <cstdlib>
#include <string>
#include <string_view>

#include "gpgpu/gl_api.h"
#include "gpgpu/gl_debug.h"

namespace gpgpu {

namespace {
constexpr std::array<std::pair<Backend, std::string_view>, 5> kNames{{
    {Backend::Auto, "auto"},
    {Backend::Egl, "egl"},
    {Backend::EglDevice, "egl-device"},
    {Backend::OSMesa, "osmesa"},
    {Backend::Glfw, "glfw"},
}};

std::string gl_string(GLenum name) {
  const GLubyte* s = gl::GetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

/// Float render targets: attach each float format, clear it to values outside [0, 1] and read them
/// back. A driver that clamps or lacks the formats fails here, before any query gives garbage.
bool probe_float_targets() {
  constexpr std::array<GLenum, 3> formats{GL_R32F, GL_RG32F, GL_RGBA32F};
  const std::array<float, 4> value{-2.5f, 3.25f, 1e20f, -1e-20f};
  bool ok = true;
  for (GLenum format : formats) {
    GLuint tex = 0, fbo = 0;
    gl::CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl::TextureStorage2D(tex, 1, format, 2, 2);
    gl::CreateFramebuffers(1, &fbo);
    gl::NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    if (gl::CheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      ok = false;
    } else {
      gl::ClearNamedFramebufferfv(fbo, GL_COLOR, 0, value.data());
      std::array<float, 16> back{};
      gl::GetTextureSubImage(tex, 0, 0, 0, 0, 2, 2, 1, GL_RGBA, GL_FLOAT, sizeof(back), back.data());
      const int channels = format == GL_R32F ? 1 : format == GL_RG32F ? 2 : 4;
      for (int c = 0; c < channels; ++c) ok = ok && back[c] == value[c];
    }
    gl::DeleteFramebuffers(1, &fbo);
    gl::DeleteTextures(1, &tex);
  }
  return ok && gl::GetError() == GL_NO_ERROR;
}
}  // namespace

std::string_view backend_name(Backend backend) {
  for (const auto& [b, name] : kNames)
    if (b == backend) return name;
  return "?";
}

Backend parse_backend(std::string_view name) {
  for (const auto& [b, n] : kNames)
    if (n == name) return b;
  throw std::invalid_argument(
      fmt::format("unknown GL backend '{}' (choose auto, egl, egl-device, osmesa or glfw)", name));
}

Backend backend_from_env(Backend fallback) {
  const char* env = std::getenv("NURBSGL_GL");
  if (env == nullptr || *env == '\0') return fallback;
  return parse_backend(env);
}

namespace {
void probe_gl(ContextInfo& info) {
  info.gl_version = gl_string(GL_VERSION);
  info.glsl_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
  info.renderer = gl_string(GL_RENDERER);
  info.vendor = gl_string(GL_VENDOR);
  gl::GetIntegerv(GL_MAX_TEXTURE_SIZE, &info.max_texture_size);
  gl::GetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &info.max_texture_units);
  GLint bits = 0;
  gl::GetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
  info.timer_queries = bits > 0;
  info.float_targets_ok = probe_float_targets();
  gl::check_error("probing the context");
  // The GPU's memory, where an extension says it (kB).
  GLint extensions = 0;
  gl::GetIntegerv(GL_NUM_EXTENSIONS, &extensions);
  for (GLint k = 0; k < extensions; ++k) {
    const auto* name = reinterpret_cast<const char*>(gl::GetStringi(GL_EXTENSIONS, GLuint(k)));
    if (name == nullptr) continue;
    GLint kb[4] = {0, 0, 0, 0};
    if (std::string_view(name) == "GL_NVX_gpu_memory_info")
      gl::GetIntegerv(0x9048, kb);  // GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
    else if (std::string_view(name) == "GL_ATI_meminfo")
      gl::GetIntegerv(0x87FC, kb);  // TEXTURE_FREE_MEMORY_ATI: free, largest block, ...
    else
      continue;
    if (gl::GetError() == GL_NO_ERROR && kb[0] > 0) info.memory_bytes = std::max(info.memory_bytes, 1024LL * kb[0]);
  }
}
}  // namespace

std::unique_ptr<Context> detail::finish_context(std::unique_ptr<Context> ctx, void* (*get_proc)(const char*),
                                                std::string& why) {
  try {
    ctx->make_current();
    gl::load(get_proc);
    ctx->info_.debug_output = gl::debug_output_requested();
    if (ctx->info_.debug_output) gl::enable_debug_output();
    probe_gl(ctx->info_);
    return ctx;
  } catch (const std::exception& e) {
    why = e.what();
    return nullptr;
  }
}

bool software_renderer(const std::string& renderer) {
  for (const char* name : {"llvmpipe", "softpipe", "swrast"})
    if (renderer.find(name) != std::string::npos) return true;
  return false;
}

std::unique_ptr<Context> Context::create(const ContextOptions& options) {
  // llvmpipe reads LP_NUM_THREADS when its screen starts, that is with the first context.
  if (options.software_threads >= 0) setenv("LP_NUM_THREADS", std::to_string(options.software_threads).c_str(), 1);
  const char* threads = std::getenv("LP_NUM_THREADS");
  std::vector<Backend> order;
  if (options.backend == Backend::Auto)
    order = {Backend::Egl, Backend::OSMesa};
  else
    order = {options.backend};

  std::string tried;
  for (Backend b : order) {
    std::string why;
    std::unique_ptr<Context> ctx;
    switch (b) {
      case Backend::Egl:
        ctx = detail::create_egl(options, false, why);
        break;
      case Backend::EglDevice:
        ctx = detail::create_egl(options, true, why);
        break;
      case Backend::OSMesa:
        ctx = detail::create_osmesa(options, why);
        break;
      case Backend::Glfw:
        ctx = detail::create_glfw(options, why);
        break;
      case Backend::Auto:
        break;
    }
    if (ctx) {
      ctx->info_.backend = std::string(backend_name(b));
      ctx->info_.software_threads = threads ? threads : "";
      if (software_renderer(ctx->info_.renderer)) {
        const std::vector<std::string> hardware = detail::egl_hardware_devices();
        if (!hardware.empty())
          ctx->info_.hardware_unused =
              fmt::format("the GL renderer ({}) rasterizes on the CPU while the EGL device platform lists {} hardware "
                          "device(s) ({}): --gl egl-device (NURBSGL_GL=egl-device, NURBSGL_EGL_DEVICE=i) runs on it{}",
                          ctx->info_.renderer, hardware.size(), fmt::join(hardware, "; "),
                          tried.empty() ? "" : fmt::format(" (not started here: {})", tried));
      }
      return ctx;
    }
    tried += fmt::format("{}{}: {}", tried.empty() ? "" : "; ", backend_name(b), why);
  }
  throw NoGlError(fmt::format("no usable OpenGL 4.5 core context ({}); choose another backend with --gl "
                              "egl|egl-device|osmesa|glfw or NURBSGL_GL",
                              tried),
                  tried);
}

}  // namespace gpgpu
