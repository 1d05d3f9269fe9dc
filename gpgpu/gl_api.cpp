#include "gpgpu/gl_api.h"

#include <fmt/format.h>

#include <stdexcept>

#include "gpgpu/gl_debug.h"

namespace gpgpu::gl {

#define NURBSGL_DEFINE_GL(ret, name, params) name##_t name = nullptr;
NURBSGL_GL_FUNCTIONS(NURBSGL_DEFINE_GL)
#undef NURBSGL_DEFINE_GL

void load(GetProcAddress get_proc) {
#define NURBSGL_LOAD_GL(ret, name, params)                 \
  name = reinterpret_cast<name##_t>(get_proc("gl" #name)); \
  if (name == nullptr) throw std::runtime_error("GL entry point gl" #name " is not available");
  NURBSGL_GL_FUNCTIONS(NURBSGL_LOAD_GL)
#undef NURBSGL_LOAD_GL
}

std::string enum_name(GLenum value) {
  switch (value) {
    case GL_NO_ERROR:
      return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_FRAMEBUFFER_COMPLETE:
      return "GL_FRAMEBUFFER_COMPLETE";
    case GL_FRAMEBUFFER_UNDEFINED:
      return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER:
      return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER:
      return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED:
      return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
      return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS:
      return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    default:
      return fmt::format("0x{:04X}", value);
  }
}

void check_error(const char* where) {
  GLenum first = GetError();
  const std::string debug = take_debug_errors();
  if (first == GL_NO_ERROR && debug.empty()) return;
  // Drain the queue (bounded: a lost context can report errors forever).
  for (int i = 0; i < 32 && GetError() != GL_NO_ERROR; ++i) {
  }
  const std::string driver = debug.empty() ? "" : fmt::format(" (driver: {})", debug);
  if (first == GL_NO_ERROR)
    throw std::runtime_error(fmt::format("GL debug message of high severity after {}{}", where, driver));
  throw std::runtime_error(fmt::format("GL error {} after {}{}", enum_name(first), where, driver));
}

}  // namespace gpgpu::gl
