// EGL backends: surfaceless Mesa and the device platform (EGL_EXT_platform_device), which serves
// llvmpipe ("EGL_MESA_device_software") and headless NVIDIA alike. EGL extension entry points come
// from libepoxy; GL entry points from eglGetProcAddress (Mesa and NVIDIA return core functions too,
// EGL_KHR_get_all_proc_addresses).
#include <dlfcn.h>
#include <epoxy/egl.h>
#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "gpgpu/context.h"

namespace gpgpu::detail {
namespace {

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

void* egl_proc(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

class EglContext final : public Context {
 public:
  EglContext(EGLDisplay display, EGLContext context, std::string detail) : display_(display), context_(context) {
    info_.detail = std::move(detail);
  }
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  void make_current() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_); }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

std::string egl_error() { return fmt::format("EGL error 0x{:04X}", eglGetError()); }

/// Initialises `display` and creates a 4.5 core context without a surface.
std::unique_ptr<Context> start_on(EGLDisplay display, const std::string& what, std::string& why) {
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
    why = fmt::format("{}: eglInitialize failed ({})", what, egl_error());
    return nullptr;
  }
  const char* exts = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(exts, "EGL_KHR_surfaceless_context")) {
    eglTerminate(display);
    why = fmt::format("{}: no EGL_KHR_surfaceless_context", what);
    return nullptr;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    why = fmt::format("{}: desktop OpenGL API not supported ({})", what, egl_error());
    return nullptr;
  }
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint n = 0;
  const bool no_config = has_extension(exts, "EGL_KHR_no_config_context");
  if (!no_config && (!eglChooseConfig(display, config_attribs, &config, 1, &n) || n < 1)) {
    eglTerminate(display);
    why = fmt::format("{}: no OpenGL-renderable EGL config", what);
    return nullptr;
  }
  const EGLint ctx_attribs[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(display, no_config ? EGL_NO_CONFIG_KHR : config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT) {
    why = fmt::format("{}: no OpenGL 4.5 core context ({})", what, egl_error());
    eglTerminate(display);
    return nullptr;
  }
  std::unique_ptr<Context> result = finish_context(
      std::make_unique<EglContext>(display, ctx, fmt::format("EGL {}.{}, {}", major, minor, what)), &egl_proc, why);
  if (!result) why = fmt::format("{}: {}", what, why);
  return result;
}

struct DeviceChoice {
  EGLDeviceEXT device = nullptr;
  std::string what;
};

/// Enumerates EGL devices; picks NURBSGL_EGL_DEVICE if set, else the first hardware device, else
/// (when `allow_software`) the first software one.
DeviceChoice choose_device(bool allow_software, std::string& why) {
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!eglQueryDevicesEXT(16, devices, &count) || count == 0) {
    why = "device platform: no EGL devices";
    return {};
  }
  int pick = -1;
  if (const char* env = std::getenv("NURBSGL_EGL_DEVICE"); env && *env) {
    pick = std::atoi(env);
    if (pick < 0 || pick >= count) {
      why = fmt::format("device platform: NURBSGL_EGL_DEVICE={} but only {} device(s)", env, count);
      return {};
    }
  } else {
    for (int i = 0; i < count && pick < 0; ++i)
      if (!has_extension(eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS), "EGL_MESA_device_software")) pick = i;
    if (pick < 0 && allow_software) pick = 0;
  }
  if (pick < 0) {
    why = fmt::format("device platform: {} device(s), none hardware", count);
    return {};
  }
  const char* dev_exts = eglQueryDeviceStringEXT(devices[pick], EGL_EXTENSIONS);
  return {devices[pick], fmt::format("device {} of {} ({})", pick, count, dev_exts ? dev_exts : "")};
}

}  // namespace

std::vector<std::string> egl_hardware_devices() {
  if (dlopen("libEGL.so.1", RTLD_LAZY | RTLD_GLOBAL) == nullptr) return {};
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr || !has_extension(client, "EGL_EXT_device_enumeration")) return {};
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!eglQueryDevicesEXT(16, devices, &count)) return {};
  std::vector<std::string> out;
  for (EGLint i = 0; i < count; ++i) {
    const char* exts = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
    if (!has_extension(exts, "EGL_MESA_device_software"))
      out.push_back(fmt::format("device {}: {}", i, exts ? exts : "no extensions listed"));
  }
  return out;
}

std::unique_ptr<Context> create_egl(const ContextOptions& /*options*/, bool device_only, std::string& why) {
  // libepoxy loads libEGL on the first EGL call and aborts the process when it cannot: look first.
  if (dlopen("libEGL.so.1", RTLD_LAZY | RTLD_GLOBAL) == nullptr) {
    const char* err = dlerror();
    why = std::string("libEGL.so.1 cannot be loaded (") + (err ? err : "?") + ")";
    return nullptr;
  }
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr) {
    why = "no EGL client extensions (libEGL without EGL 1.5 / EXT_client_extensions)";
    return nullptr;
  }
  std::string reasons;
  auto note = [&](const std::string& r) { reasons += (reasons.empty() ? "" : ", ") + r; };
  const bool device_platform =
      has_extension(client, "EGL_EXT_platform_device") && has_extension(client, "EGL_EXT_device_enumeration");
  auto try_device = [&](bool allow_software) -> std::unique_ptr<Context> {
    std::string w;
    DeviceChoice d = choose_device(allow_software, w);
    if (d.device != nullptr) {
      auto ctx = start_on(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, d.device, nullptr), d.what, w);
      if (ctx) return ctx;
    }
    note(w);
    return nullptr;
  };
  // 1. A hardware device (headless NVIDIA), or any device when the device platform was asked for.
  if (device_platform) {
    if (auto ctx = try_device(device_only)) return ctx;
  } else {
    note("no EGL_EXT_platform_device");
  }
  if (!device_only) {
    // 2. Mesa's surfaceless platform (llvmpipe or a Mesa hardware driver).
    if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
      std::string w;
      auto ctx = start_on(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                          "surfaceless platform (Mesa)", w);
      if (ctx) return ctx;
      note(w);
    } else {
      note("no EGL_MESA_platform_surfaceless");
    }
    // 3. The software device of the device platform.
    if (device_platform) {
      if (auto ctx = try_device(true)) return ctx;
    }
  }
  why = reasons;
  return nullptr;
}

}  // namespace gpgpu::detail
