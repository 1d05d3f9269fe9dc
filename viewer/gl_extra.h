#pragma once
/// \file gl_extra.h
/// The GL entry points the viewer draws with beyond gpgpu's table (gpgpu/gl_api.h), which holds only
/// what the GPGPU passes need. Loaded the same way, through the GLFW context's own loader
/// (glfwGetProcAddress), never through libepoxy: see README "GL binding".
#include <GL/glcorearb.h>

namespace viewer::glx {

// clang-format off
// X(return type, name without the "gl" prefix, parameter list)
#define NURBSGL_VIEWER_GL_FUNCTIONS(X)                                                   \
  X(void, DrawElements, (GLenum, GLsizei, GLenum, const void*))                         \
  X(void, PolygonMode, (GLenum, GLenum))                                                \
  X(void, PolygonOffset, (GLfloat, GLfloat))                                            \
  X(void, DepthFunc, (GLenum))                                                          \
  X(void, DepthMask, (GLboolean))                                                       \
  X(void, ReadBuffer, (GLenum))                                                         \
  X(void, ReadPixels, (GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*))          \
  X(void, VertexArrayElementBuffer, (GLuint, GLuint))
// clang-format on

#define NURBSGL_VIEWER_DECLARE_GL(ret, name, params) \
  using name##_t = ret(APIENTRYP) params;            \
  extern name##_t name;
NURBSGL_VIEWER_GL_FUNCTIONS(NURBSGL_VIEWER_DECLARE_GL)
#undef NURBSGL_VIEWER_DECLARE_GL

/// Loads the table from the current GLFW context. Throws std::runtime_error naming a missing entry
/// point. Call after the gpgpu::Context is created (it made the window's context current).
void load();

}  // namespace viewer::glx
