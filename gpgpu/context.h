#pragma once
/// \file context.h
/// Headless (or windowed) OpenGL 4.5 core contexts: EGL surfaceless, EGL device platform, OSMesa,
/// GLFW. One context is current per process; creating it loads the gl:: table (gl_api.h).
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gpgpu {

enum class Backend {
  Auto,       ///< Egl, then OSMesa
  Egl,        ///< EGL: a hardware device if the device platform lists one, else surfaceless Mesa
  EglDevice,  ///< EGL_EXT_platform_device only (NURBSGL_EGL_DEVICE=i picks the device)
  OSMesa,     ///< Mesa's off-screen library (software), GL bound through OSMesaGetProcAddress
  Glfw,       ///< a GLFW window (the viewer); needs a display
};

/// "auto", "egl", "egl-device", "osmesa", "glfw".
std::string_view backend_name(Backend backend);
/// Parses a backend name; throws std::invalid_argument listing the valid names.
Backend parse_backend(std::string_view name);
/// The backend named by the NURBSGL_GL environment variable, or `fallback` when it is unset/empty.
Backend backend_from_env(Backend fallback = Backend::Auto);

struct ContextOptions {
  Backend backend = Backend::Auto;
  int width = 64;  ///< window size for Glfw; default framebuffer size elsewhere
  int height = 64;
  bool visible = false;  ///< Glfw only
  std::string title = "nurbsgl";
  /// Rasterizer threads of Mesa's software renderer llvmpipe (LP_NUM_THREADS, set for this process
  /// before the context starts); -1 leaves the environment alone (llvmpipe: one per core). 0 draws
  /// on the calling thread: no hand-off to the rasterizer threads and back on every pass, which
  /// costs llvmpipe 0.1-0.3 ms a pass whatever its size; large passes lose the other cores.
  /// Hardware drivers ignore it.
  int software_threads = -1;
};

/// What `nurbsgl gpu-info` prints.
struct ContextInfo {
  std::string backend;  ///< backend_name of the backend that started
  std::string detail;   ///< e.g. "EGL 1.5, surfaceless platform (Mesa)"
  std::string gl_version;
  std::string glsl_version;
  std::string renderer;
  std::string vendor;
  int max_texture_size = 0;
  int max_texture_units = 0;      ///< GL_MAX_TEXTURE_IMAGE_UNITS (fragment stage)
  /// The GPU's dedicated memory where the GL says it (GL_NVX_gpu_memory_info's total, or
  /// GL_ATI_meminfo's free texture memory), bytes; 0 where it does not (Mesa's software renderers).
  long long memory_bytes = 0;
  bool float_targets_ok = false;  ///< R32F/RG32F/RGBA32F attach, clear and read back unclamped
  bool timer_queries = false;     ///< GL_TIME_ELAPSED reports a non-zero counter width
  bool debug_output = false;      ///< KHR_debug messages go to stderr and check_error (gl_debug.h)
  std::string software_threads;   ///< LP_NUM_THREADS when the context started; empty = llvmpipe's default
  /// Set when the renderer rasterizes on the CPU (llvmpipe, softpipe, swrast) while the EGL device
  /// platform lists a hardware device: which, and how to use it; empty otherwise.
  std::string hardware_unused;
  /// Whether the renderer rasterizes on the CPU (Mesa's llvmpipe, softpipe or swrast, SwiftShader):
  /// its "GPU" passes run on the same cores as the host code.
  [[nodiscard]] bool software_renderer() const {
    for (const char* name : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
      if (renderer.find(name) != std::string::npos) return true;
    return false;
  }
};

/// Raised when no backend could start: one line naming each backend tried and why, and how to
/// choose another. The CLI maps it to exit code 3.
class NoGlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  /// `what` with `tried`: what each backend answered, for a caller with its own advice.
  NoGlError(const std::string& what, std::string tried) : std::runtime_error(what), tried_(std::move(tried)) {}
  [[nodiscard]] const std::string& tried() const { return tried_; }

 private:
  std::string tried_;
};

class Context;
namespace detail {
std::unique_ptr<Context> finish_context(std::unique_ptr<Context> ctx, void* (*get_proc)(const char*), std::string& why);
}

class Context {
 public:
  virtual ~Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  [[nodiscard]] const ContextInfo& info() const { return info_; }
  /// The GLFWwindow* of a Glfw context, nullptr otherwise.
  [[nodiscard]] virtual void* native_window() const { return nullptr; }
  virtual void make_current() = 0;

  /// Starts the requested backend (Auto: Egl, then OSMesa), makes it current, loads the gl:: table
  /// and probes float render targets. Throws NoGlError when nothing starts.
  static std::unique_ptr<Context> create(const ContextOptions& options = {});

 protected:
  Context() = default;
  ContextInfo info_;

 private:
  friend std::unique_ptr<Context> detail::finish_context(std::unique_ptr<Context>, void* (*)(const char*),
                                                         std::string&);
};

/// Whether `renderer` (GL_RENDERER) rasterizes on the CPU: Mesa's llvmpipe, softpipe or swrast.
[[nodiscard]] bool software_renderer(const std::string& renderer);

namespace detail {
/// The hardware devices of the EGL device platform, one line each ("device 1: EGL_NV_device_cuda
/// ..."); empty when there are none or no EGL device platform.
std::vector<std::string> egl_hardware_devices();
/// Each backend's factory: returns nullptr and sets `why` when it cannot start.
std::unique_ptr<Context> create_egl(const ContextOptions& options, bool device_only, std::string& why);
std::unique_ptr<Context> create_osmesa(const ContextOptions& options, std::string& why);
std::unique_ptr<Context> create_glfw(const ContextOptions& options, std::string& why);
/// Makes a new backend context current, loads the gl:: table through `get_proc` (the backend's
/// loader) and probes it into info(). Returns nullptr and sets `why` when that fails (a missing 4.5
/// entry point, a GL error while probing).
std::unique_ptr<Context> finish_context(std::unique_ptr<Context> ctx, void* (*get_proc)(const char*), std::string& why);
}  // namespace detail

}  // namespace gpgpu
