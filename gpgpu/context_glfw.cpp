// GLFW backend: a window (hidden unless asked) with a 4.5 core context, for the viewer and for
// running the GL tests under a real window system (xvfb-run in CI).
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <string>

#include "gpgpu/context.h"

namespace gpgpu::detail {
namespace {

std::string g_last_glfw_error;
void on_glfw_error(int code, const char* text) { g_last_glfw_error = fmt::format("{} (0x{:X})", text, code); }
void* glfw_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

class GlfwContext final : public Context {
 public:
  explicit GlfwContext(GLFWwindow* window) : window_(window) {
    int major = 0, minor = 0, rev = 0;
    glfwGetVersion(&major, &minor, &rev);
    info_.detail = fmt::format("GLFW {}.{}.{} window", major, minor, rev);
  }
  ~GlfwContext() override {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  void make_current() override { glfwMakeContextCurrent(window_); }
  [[nodiscard]] void* native_window() const override { return window_; }

 private:
  GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<Context> create_glfw(const ContextOptions& options, std::string& why) {
  glfwSetErrorCallback(&on_glfw_error);
  g_last_glfw_error.clear();
  if (!glfwInit()) {
    why = "glfwInit failed: " + (g_last_glfw_error.empty() ? std::string("no display") : g_last_glfw_error);
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    why = "no 4.5 core window: " + g_last_glfw_error;
    glfwTerminate();
    return nullptr;
  }
  return finish_context(std::make_unique<GlfwContext>(window), &glfw_proc, why);
}

}  // namespace gpgpu::detail
