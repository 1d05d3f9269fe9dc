// Drawing the scene into the window's default framebuffer. Every piece of state a draw needs is
// set here each frame: the GPU queries run passes into their own framebuffers between frames.
#include <fmt/format.h>

#include <algorithm>
#include <glm/gtc/type_ptr.hpp>

#include "gpgpu/gl_api.h"
#include "nurbs/raycast/thickness.h"
#include "viewer/app.h"
#include "viewer/gl_extra.h"

namespace viewer {

namespace gl = gpgpu::gl;

namespace {

/// The distance segment's colour: pure magenta, used by nothing else, so that the screenshot test
/// can find the segment by counting exact pixels (viewer/check_screenshot.cpp).
constexpr glm::vec3 kSegmentColor{1.0f, 0.0f, 1.0f};
/// The part of the segment hidden by the models: dashed, dimmer.
constexpr glm::vec3 kHiddenSegmentColor{0.6f, 0.15f, 0.6f};

void set_mvp(const gpgpu::Program& p, const glm::dmat4& view_projection, const glm::dmat4& model) {
  const glm::mat4 mvp(view_projection * model);
  p.set_mat4("u_mvp", glm::value_ptr(mvp));
}

}  // namespace

void App::rebuild_selection_overlay() {
  selection_overlay_.clear();
  const SceneModel* m = picked_model_ == 0 ? a_.get() : picked_model_ == 1 ? b_.get() : nullptr;
  if (m == nullptr || picked_face_ < 0 || picked_face_ >= static_cast<int>(m->faces.size())) return;
  add_control_net(m->faces[picked_face_], {0.95f, 0.85f, 0.2f}, selection_overlay_);
  add_trim_loops(m->faces[picked_face_], {0.1f, 0.9f, 0.95f}, selection_overlay_);
}

void App::render_scene(int width, int height) {
  gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::Viewport(0, 0, width, height);
  for (GLenum cap : {GL_BLEND, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_CULL_FACE}) gl::Disable(cap);
  gl::ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glx::DepthMask(GL_TRUE);
  const float background[4] = {0.16f, 0.17f, 0.2f, 1.0f}, depth = 1.0f;
  gl::ClearNamedFramebufferfv(0, GL_COLOR, 0, background);
  gl::ClearNamedFramebufferfv(0, GL_DEPTH, 0, &depth);
  if (!a_ || width <= 0 || height <= 0) return;

  gl::Enable(GL_DEPTH_TEST);
  glx::DepthFunc(GL_LEQUAL);
  const glm::dmat4 view = camera_.view();
  const glm::dmat4 vp = camera_.projection(double(width) / height) * view;
  const bool show_b = mode_ == Mode::Clearance && has_b();
  const gpgpu::Program& mp = *mesh_program_;

  struct Item {
    MeshBuffers* buffers;
    glm::dmat4 model;
    glm::vec3 color;
    int index;  // 0 = A, 1 = B
  };
  std::vector<Item> items;
  if (mode_ == Mode::Thickness && thickness_.ready()) {
    items.push_back({&thickness_.buffers, glm::dmat4(1.0), {0.7f, 0.7f, 0.7f}, 0});
  } else {
    items.push_back({&a_->buffers, glm::dmat4(1.0), {0.62f, 0.68f, 0.78f}, 0});
    if (show_b) items.push_back({&b_->buffers, motion_b(), {0.78f, 0.66f, 0.52f}, 1});
  }
  const bool wire_only = mode_ == Mode::Tessellation && wireframe_;
  for (const Item& it : items) {
    set_mvp(mp, vp, it.model);
    const glm::mat4 mv(view * it.model);
    mp.set_mat4("u_model_view", glm::value_ptr(mv));
    mp.set("u_picked_face", picked_model_ == it.index ? float(picked_face_) : -1.0f);
    const bool thick = mode_ == Mode::Thickness && thickness_.ready();
    mp.set("u_style", thick ? 1 : 0);
    mp.set("u_range", float(thickness_.lo), float(thickness_.hi));
    for (int k = 0; k < 4; ++k)
      mp.set(fmt::format("u_ramp[{}]", k), float(nurbs::ray::kThicknessRamp[k][0]),
             float(nurbs::ray::kThicknessRamp[k][1]), float(nurbs::ray::kThicknessRamp[k][2]));
    mp.set("u_threshold", thick_threshold_);
    mp.set("u_color", it.color.x, it.color.y, it.color.z);
    if (!wire_only) {
      // Pushed back so that edges and trim loops drawn on the surface win the depth test.
      gl::Enable(GL_POLYGON_OFFSET_FILL);
      glx::PolygonOffset(1.0f, 1.0f);
      it.buffers->draw(mp);
      gl::Disable(GL_POLYGON_OFFSET_FILL);
    }
    if (mode_ == Mode::Tessellation) {  // the triangles' edges
      mp.set("u_style", 2);
      const glm::vec3 edge = wire_only ? glm::vec3(0.85f, 0.9f, 0.95f) : 0.4f * it.color;
      mp.set("u_color", edge.x, edge.y, edge.z);
      glx::PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      it.buffers->draw(mp);
      glx::PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
  }

  const gpgpu::Program& lp = *line_program_;
  if (show_edges_ && mode_ != Mode::Tessellation && mode_ != Mode::Thickness) {
    set_mvp(lp, vp, glm::dmat4(1.0));
    edges_a_.draw(lp);
    if (show_b) {
      set_mvp(lp, vp, motion_b());
      edges_b_.draw(lp);
    }
  }
  if (show_b) {  // the search's boxes (overlays.h), B's in its own moved frame
    if (overlay_dirty_) rebuild_overlays();
    set_mvp(lp, vp, glm::dmat4(1.0));
    overlay_a_.draw(lp);
    set_mvp(lp, vp, motion_b());
    overlay_b_.draw(lp);
  }
  if (!selection_overlay_.empty() && (picked_model_ == 0 || show_b)) {
    gl::Disable(GL_DEPTH_TEST);  // the control net lies off the surface: always in view
    set_mvp(lp, vp, picked_model_ == 1 ? motion_b() : glm::dmat4(1.0));
    selection_overlay_.draw(lp);
    gl::Enable(GL_DEPTH_TEST);
  }
  if (mode_ == Mode::Clearance && clearance_) draw_segment(vp, width, height);
  gl::Disable(GL_DEPTH_TEST);
  gl::check_error("viewer scene");
}

void App::draw_segment(const glm::dmat4& view_projection, int width, int height) {
  // Quads 3 pixels wide in normalised device coordinates (core profile lines are one pixel wide),
  // at the segment's own depth: the part in front of the scene pure magenta, the part behind it
  // dashed in a dim magenta (a second draw with GL_GREATER), a 7-pixel square at each end on top.
  segment_.clear();
  segment_hidden_.clear();
  segment_ends_.clear();
  const glm::dvec4 ca = view_projection * glm::dvec4(clearance_->point_a, 1.0);
  const glm::dvec4 cb = view_projection * glm::dvec4(clearance_->point_b, 1.0);
  if (ca.w <= 0.0 || cb.w <= 0.0) return;  // an end behind the eye
  // z / w is linear across the window, so quads placed in NDC interpolate the depth exactly.
  const glm::dvec3 pa = glm::dvec3(ca) / ca.w, pb = glm::dvec3(cb) / cb.w;
  const glm::dvec2 px(2.0 / width, 2.0 / height);  // one pixel in NDC
  glm::dvec2 dir = (glm::dvec2(pb) - glm::dvec2(pa)) / px;
  const double len = glm::length(dir);  // pixels
  dir = len > 0.0 ? dir / len : glm::dvec2(1.0, 0.0);
  const glm::dvec3 n(glm::dvec2(-dir.y, dir.x) * 1.5 * px, 0.0);
  const auto piece = [&](LineBatch& batch, double t0, double t1, const glm::vec3& color) {
    const glm::dvec3 p0 = glm::mix(pa, pb, t0), p1 = glm::mix(pa, pb, t1);
    batch.triangle(p0 - n, p1 - n, p1 + n, color);
    batch.triangle(p0 - n, p1 + n, p0 + n, color);
  };
  piece(segment_, 0.0, 1.0, kSegmentColor);
  constexpr double kDash = 6.0, kGap = 4.0;  // pixels
  for (double s = 0.0; s < len; s += kDash + kGap)
    piece(segment_hidden_, s / len, std::min(s + kDash, len) / len, kHiddenSegmentColor);
  for (const glm::dvec3& p : {pa, pb}) {
    const glm::dvec3 h(3.5 * px, 0.0), k(h.x, -h.y, 0.0);
    segment_ends_.triangle(p - h, p + k, p + h, kSegmentColor);
    segment_ends_.triangle(p - h, p + h, p - k, kSegmentColor);
  }
  const glm::mat4 identity(1.0f);
  line_program_->set_mat4("u_mvp", glm::value_ptr(identity));
  // Both passes compare against the scene's depth only (no writes), so each pixel of the segment
  // falls in exactly one; pulled a few depth units forward, as the mesh is pushed back, so that
  // the ends on the surfaces count as in front.
  gl::Enable(GL_DEPTH_TEST);
  glx::DepthMask(GL_FALSE);
  gl::Enable(GL_POLYGON_OFFSET_FILL);
  glx::PolygonOffset(0.0f, -4.0f);
  glx::DepthFunc(GL_LEQUAL);
  segment_.draw(*line_program_);
  glx::DepthFunc(GL_GREATER);
  segment_hidden_.draw(*line_program_);
  gl::Disable(GL_POLYGON_OFFSET_FILL);
  glx::DepthFunc(GL_LEQUAL);
  glx::DepthMask(GL_TRUE);
  gl::Disable(GL_DEPTH_TEST);
  segment_ends_.draw(*line_program_);
}

}  // namespace viewer
