#include "gpgpu/polygon_fill.h"

#include "gpgpu/gl_api.h"

namespace gpgpu {
namespace {

/// GL objects of one fill, released on every path (RAII).
struct FillObjects {
  GLuint fbo = 0, stencil = 0, vao = 0, vbo = 0, empty_vao = 0;
  ~FillObjects() {
    if (fbo) gl::DeleteFramebuffers(1, &fbo);
    if (stencil) gl::DeleteRenderbuffers(1, &stencil);
    if (vao) gl::DeleteVertexArrays(1, &vao);
    if (empty_vao) gl::DeleteVertexArrays(1, &empty_vao);
    if (vbo) gl::DeleteBuffers(1, &vbo);
  }
};

}  // namespace

namespace {
Program& fan_program(Gpu& gpu) { return gpu.program("polygon.vert", "fill_constant.frag", {}); }
Program& cover_program(Gpu& gpu) { return gpu.program("fill_constant.frag"); }
}  // namespace

void compile_polygon_fill(Gpu& gpu) {
  fan_program(gpu);
  cover_program(gpu);
}

void fill_polygons_even_odd(Gpu& gpu, const std::vector<std::vector<glm::vec2>>& polygons, Texture& target) {
  FillObjects o;
  gl::CreateRenderbuffers(1, &o.stencil);
  gl::NamedRenderbufferStorage(o.stencil, GL_STENCIL_INDEX8, target.width(), target.height());
  gl::CreateFramebuffers(1, &o.fbo);
  gl::NamedFramebufferTexture(o.fbo, GL_COLOR_ATTACHMENT0, target.id(), 0);
  gl::NamedFramebufferRenderbuffer(o.fbo, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER, o.stencil);
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0};
  gl::NamedFramebufferDrawBuffers(o.fbo, 1, buffers);
  const GLenum status = gl::CheckNamedFramebufferStatus(o.fbo, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw FramebufferError("polygon fill framebuffer incomplete: " + gl::enum_name(status));

  std::vector<glm::vec2> vertices;
  std::vector<std::pair<GLint, GLsizei>> fans;
  for (const auto& poly : polygons) {
    if (poly.size() < 3) continue;
    fans.emplace_back(static_cast<GLint>(vertices.size()), static_cast<GLsizei>(poly.size()));
    vertices.insert(vertices.end(), poly.begin(), poly.end());
  }
  gl::CreateVertexArrays(1, &o.vao);
  gl::CreateVertexArrays(1, &o.empty_vao);
  gl::CreateBuffers(1, &o.vbo);
  if (vertices.empty()) vertices.emplace_back(0.0f, 0.0f);  // a zero-size buffer store is not portable
  gl::NamedBufferData(o.vbo, static_cast<GLsizeiptr>(vertices.size() * sizeof(glm::vec2)), vertices.data(),
                      GL_STATIC_DRAW);
  gl::VertexArrayVertexBuffer(o.vao, 0, o.vbo, 0, sizeof(glm::vec2));
  gl::VertexArrayAttribFormat(o.vao, 0, 2, GL_FLOAT, GL_FALSE, 0);
  gl::VertexArrayAttribBinding(o.vao, 0, 0);
  gl::EnableVertexArrayAttrib(o.vao, 0);

  Program& fan = fan_program(gpu);
  Program& cover = cover_program(gpu);
  fan.set("u_target_size", float(target.width()), float(target.height()));
  fan.set("u_value", 0.0f, 0.0f, 0.0f, 0.0f);
  cover.set("u_value", 1.0f, 1.0f, 1.0f, 1.0f);

  gpu.profiler().begin("polygon_fill_even_odd");
  const GLfloat zero[] = {0, 0, 0, 0};
  const GLint stencil_zero = 0;
  gl::ClearNamedFramebufferfv(o.fbo, GL_COLOR, 0, zero);
  gl::ClearNamedFramebufferiv(o.fbo, GL_STENCIL, 0, &stencil_zero);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, o.fbo);
  gl::Viewport(0, 0, target.width(), target.height());
  for (GLenum cap : {GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST, GL_CULL_FACE, GL_DITHER}) gl::Disable(cap);
  gl::Enable(GL_STENCIL_TEST);
  // Pass 1: fans invert stencil bit 0, colour untouched.
  gl::ColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  gl::StencilMask(0x01);
  gl::StencilFunc(GL_ALWAYS, 0, 0x01);
  gl::StencilOp(GL_KEEP, GL_KEEP, GL_INVERT);
  gl::UseProgram(fan.id());
  gl::BindVertexArray(o.vao);
  for (const auto& [first, count] : fans) gl::DrawArrays(GL_TRIANGLE_FAN, first, count);
  // Pass 2: write 1 where the bit is set.
  gl::ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl::StencilFunc(GL_EQUAL, 1, 0x01);
  gl::StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  gl::UseProgram(cover.id());
  gl::BindVertexArray(o.empty_vao);
  gl::DrawArrays(GL_TRIANGLES, 0, 3);
  // Leave nothing behind.
  gl::Disable(GL_STENCIL_TEST);
  gl::StencilMask(0xFF);
  gl::StencilFunc(GL_ALWAYS, 0, 0xFF);
  gl::BindVertexArray(0);
  gl::UseProgram(0);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  gpu.profiler().end();
  gl::check_error("polygon fill");
}

std::vector<uint8_t> fill_polygons_even_odd_cpu(const std::vector<std::vector<glm::vec2>>& polygons, int width,
                                                int height) {
  std::vector<uint8_t> mask(size_t(width) * size_t(height), 0);
  for (int j = 0; j < height; ++j) {
    const double y = j + 0.5;
    for (int i = 0; i < width; ++i) {
      const double x = i + 0.5;
      bool inside = false;
      for (const auto& poly : polygons) {
        if (poly.size() < 3) continue;  // as the GPU path: no area
        for (size_t a = 0, b = poly.size() - 1; a < poly.size(); b = a++) {
          const double ya = poly[a].y, yb = poly[b].y;
          if ((ya > y) != (yb > y)) {
            const double xc = poly[a].x + (y - ya) / (yb - ya) * (poly[b].x - poly[a].x);
            if (x < xc) inside = !inside;
          }
        }
      }
      mask[size_t(j) * size_t(width) + size_t(i)] = inside ? 1 : 0;
    }
  }
  return mask;
}

}  // namespace gpgpu
