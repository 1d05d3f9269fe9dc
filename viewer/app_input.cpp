// Input: the live mouse and keys as the GLFW callbacks leave them in Dear ImGui's IO, or the frames
// of an `--events` script written into the same IO before the frame starts. Either way
// handle_input() is the one place that turns them into camera moves, B's motion and picks.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "viewer/app.h"

namespace viewer {

void App::apply_scripted_input(int frame) {
  // After ImGui_ImplGlfw_NewFrame (which polls the real cursor and buttons), before ImGui::NewFrame
  // (which derives clicks, drags, deltas and key presses from this state, as for a real mouse).
  const std::vector<InputFrame>& script = options_.events;
  if (script.empty()) return;
  InputFrame f = script[std::min<size_t>(size_t(frame), script.size() - 1)];
  if (size_t(frame) >= script.size()) f.key = -1, f.wheel = 0.0f;  // the script is over: hold still
  ImGuiIO& io = ImGui::GetIO();
  io.MousePos = f.x < 0.0 ? ImVec2(-FLT_MAX, -FLT_MAX) : ImVec2(float(f.x), float(f.y));
  for (int b = 0; b < IM_ARRAYSIZE(io.MouseDown); ++b) io.MouseDown[b] = b < 3 && f.buttons[b];
  io.MouseWheel = f.wheel;
  if (scripted_key_ >= 0) io.KeysDown[scripted_key_] = false;
  scripted_key_ = f.key;
  if (f.key >= 0) io.KeysDown[f.key] = true;
  io.KeysDown[GLFW_KEY_LEFT_SHIFT] = io.KeyShift = f.shift;
  io.KeysDown[GLFW_KEY_LEFT_CONTROL] = io.KeyCtrl = f.ctrl;
}

void App::handle_input() {
  ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureKeyboard) {
    if (ImGui::IsKeyPressed(GLFW_KEY_F1) || ImGui::IsKeyPressed(GLFW_KEY_H)) show_help_ = !show_help_;
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(static_cast<GLFWwindow*>(window_), GLFW_TRUE);
    if (a_) {
      if (ImGui::IsKeyPressed(GLFW_KEY_1)) set_mode(Mode::View);
      if (ImGui::IsKeyPressed(GLFW_KEY_2)) set_mode(Mode::Clearance);
      if (ImGui::IsKeyPressed(GLFW_KEY_3)) set_mode(Mode::Tessellation);
      if (ImGui::IsKeyPressed(GLFW_KEY_4)) set_mode(Mode::Thickness);
      if (ImGui::IsKeyPressed(GLFW_KEY_F)) frame_camera();
      if (ImGui::IsKeyPressed(GLFW_KEY_E)) show_edges_ = !show_edges_;
      if (ImGui::IsKeyPressed(GLFW_KEY_W)) wireframe_ = !wireframe_;
      if (mode_ == Mode::Clearance) {
        const glm::dvec3 centre = 0.5 * (b_->mesh_min + b_->mesh_max);
        const double step = io.KeyShift ? 1.0 : 5.0;
        if (ImGui::IsKeyPressed(GLFW_KEY_Q)) placement_.rotate_about(centre, {0, 0, 1}, step), clearance_dirty_ = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_R)) placement_.rotate_about(centre, {0, 0, 1}, -step), clearance_dirty_ = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) continuous_ = !continuous_;
      }
    }
  }
  if (io.WantCaptureMouse || !a_) return;
  int ww = 0, wh = 0;
  glfwGetWindowSize(static_cast<GLFWwindow*>(window_), &ww, &wh);
  const bool move_b = mode_ == Mode::Clearance && (io.KeyShift || io.KeyCtrl);
  const ImVec2 d = io.MouseDelta;
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 1.0f) && (d.x != 0 || d.y != 0)) {
    if (move_b) {  // B in the view plane, following the cursor
      placement_.move += camera_.pixel_size(wh) * (double(d.x) * camera_.right() - double(d.y) * camera_.up());
      clearance_dirty_ = true;
    } else {
      camera_.orbit(d.x, d.y);
    }
  }
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 1.0f) && (d.x != 0 || d.y != 0)) {
    if (move_b) {  // B turned about its centre: horizontal drag about the view's up, vertical about its right
      const glm::dvec3 centre = 0.5 * (b_->mesh_min + b_->mesh_max);
      placement_.rotate_about(centre, camera_.up(), 0.5 * d.x);
      placement_.rotate_about(centre, camera_.right(), 0.5 * d.y);
      clearance_dirty_ = true;
    } else {
      camera_.pan(d.x, d.y, wh);
    }
  }
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 1.0f)) camera_.pan(d.x, d.y, wh);
  if (io.MouseWheel != 0.0f) camera_.zoom(io.MouseWheel);
  // A click (press and release without dragging) picks the face under the cursor.
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) && io.MouseDragMaxDistanceSqr[0] < 9.0f && !move_b)
    pick_at(io.MousePos.x, io.MousePos.y);
}

void App::pick_at(double x, double y) {
  int ww = 0, wh = 0;
  glfwGetWindowSize(static_cast<GLFWwindow*>(window_), &ww, &wh);
  const Ray ray = camera_.ray(x, y, ww, wh);
  std::optional<Pick> pa = pick(a_->tess.mesh, glm::dmat4(1.0), ray), pb;
  if (has_b() && mode_ == Mode::Clearance) pb = pick(b_->tess.mesh, motion_b(), ray);
  picked_model_ = -1;
  picked_face_ = -1;
  if (pa && (!pb || pa->t <= pb->t))
    picked_model_ = 0, picked_face_ = pa->face;
  else if (pb)
    picked_model_ = 1, picked_face_ = pb->face;
  rebuild_selection_overlay();
}

}  // namespace viewer
