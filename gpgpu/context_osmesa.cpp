// OSMesa backend. libepoxy cannot be used here (it aborts without a GLX or EGL context), so the
// GL table is loaded through OSMesaGetProcAddress, which returns libOSMesa's own entry points.
#include <GL/osmesa.h>
#include <fmt/format.h>

#include <vector>

#include "gpgpu/context.h"

namespace gpgpu::detail {
namespace {

void* osmesa_proc(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

class OSMesaCtx final : public Context {
 public:
  OSMesaCtx(OSMesaContext ctx, int w, int h) : ctx_(ctx), width_(w), height_(h), buffer_(size_t(w) * h) {
    info_.detail = "OSMesa (Mesa off-screen, software)";
  }
  ~OSMesaCtx() override { OSMesaDestroyContext(ctx_); }
  void make_current() override {
    // OSMesa needs a client-memory colour buffer; every pass renders into our own FBOs instead.
    OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_);
  }

 private:
  OSMesaContext ctx_;
  int width_, height_;
  std::vector<unsigned> buffer_;
};

}  // namespace

std::unique_ptr<Context> create_osmesa(const ContextOptions& /*options*/, std::string& why) {
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         0,
                         OSMESA_STENCIL_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         4,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         5,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (ctx == nullptr) {
    why = "OSMesaCreateContextAttribs refused a 4.5 core context";
    return nullptr;
  }
  return finish_context(std::make_unique<OSMesaCtx>(ctx, 1, 1), &osmesa_proc, why);
}

}  // namespace gpgpu::detail
