#include "viewer/gl_extra.h"

#include <GLFW/glfw3.h>

#include <stdexcept>

namespace viewer::glx {

#define NURBSGL_VIEWER_DEFINE_GL(ret, name, params) name##_t name = nullptr;
NURBSGL_VIEWER_GL_FUNCTIONS(NURBSGL_VIEWER_DEFINE_GL)
#undef NURBSGL_VIEWER_DEFINE_GL

void load() {
#define NURBSGL_VIEWER_LOAD_GL(ret, name, params)                    \
  name = reinterpret_cast<name##_t>(glfwGetProcAddress("gl" #name)); \
  if (name == nullptr) throw std::runtime_error("GL entry point gl" #name " is not available");
  NURBSGL_VIEWER_GL_FUNCTIONS(NURBSGL_VIEWER_LOAD_GL)
#undef NURBSGL_VIEWER_LOAD_GL
}

}  // namespace viewer::glx
