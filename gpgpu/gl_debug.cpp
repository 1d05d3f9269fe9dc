#include "gpgpu/gl_debug.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <utility>

#include "gpgpu/gl_api.h"

namespace gpgpu::gl {
namespace {

std::string g_errors;  // one context per process (context.h); the callback is synchronous

std::string_view type_name(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR:
      return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
      return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
      return "undefined behaviour";
    case GL_DEBUG_TYPE_PERFORMANCE:
      return "performance";
    case GL_DEBUG_TYPE_PORTABILITY:
      return "portability";
    default:
      return "other";
  }
}

void APIENTRY on_message(GLenum source, GLenum type, GLuint /*id*/, GLenum severity, GLsizei length,
                         const GLchar* message, const void* /*user*/) {
  const std::string_view text(message, length < 0 ? std::char_traits<char>::length(message) : size_t(length));
  const bool high = severity == GL_DEBUG_SEVERITY_HIGH;
  fmt::print(stderr, "nurbsgl: GL debug [{}, {}]: {}\n", high ? "high" : "medium", type_name(type), text);
  // Compiler messages are not kept: a failed compile throws ShaderError with the whole log anyway.
  if (high && source != GL_DEBUG_SOURCE_SHADER_COMPILER)
    g_errors += fmt::format("{}{}", g_errors.empty() ? "" : "; ", text);
}

}  // namespace

bool debug_output_requested() {
  if (const char* env = std::getenv("NURBSGL_GL_DEBUG"); env != nullptr && *env != '\0')
    return std::string_view(env) != "0";
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

void enable_debug_output() {
  Enable(GL_DEBUG_OUTPUT);
  Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  DebugMessageCallback(on_message, nullptr);
  DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  for (GLenum quiet : {GL_DEBUG_SEVERITY_LOW, GL_DEBUG_SEVERITY_NOTIFICATION})
    DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, quiet, 0, nullptr, GL_FALSE);
  g_errors.clear();
}

std::string take_debug_errors() { return std::exchange(g_errors, {}); }

}  // namespace gpgpu::gl
