#include "viewer/app.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "gpgpu/gl_api.h"
#include "viewer/gl_extra.h"
#include "viewer/screenshot.h"

namespace gpgpu {
std::span<const ShaderFile> viewer_glsl();  // viewer/shaders/, embedded by viewer/CMakeLists.txt
}

namespace viewer {

App::App(ViewerOptions options) : options_(std::move(options)) {}

App::~App() {
  // ImGui's GL objects belong to the window's context: gone before the Gpu closes the window.
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  // The scene's GL objects go next (members after gpu_), the context last.
}

void App::start_gl() {
  gpgpu::ContextOptions ctx;
  ctx.backend = gpgpu::Backend::Glfw;
  ctx.width = options_.width;
  ctx.height = options_.height;
  ctx.visible = true;
  ctx.title = "nurbsgl-viewer";
  gpu_ = std::make_unique<gpgpu::Gpu>(ctx);
  window_ = gpu_->context().native_window();
  glx::load();
  gpu_->shaders().add(gpgpu::viewer_glsl(), "viewer/shaders/");
  mesh_program_ = &gpu_->program("viewer_mesh.vert", "viewer_mesh.frag", {});
  line_program_ = &gpu_->program("viewer_lines.vert", "viewer_lines.frag", {});
  auto* window = static_cast<GLFWwindow*>(window_);
  glfwSwapInterval(options_.frames > 0 ? 0 : 1);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // nothing written into the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 450");
  imgui_ready_ = true;
}

void App::load_models() {
  try {
    a_ = std::make_unique<SceneModel>();
    load_scene_model(*a_, options_.models.at(0));
    b_ = std::make_unique<SceneModel>();
    load_scene_model(*b_, options_.models.size() > 1 ? options_.models[1] : options_.models[0]);
    eps_rel_ = static_cast<float>(options_.eps);
    for (SceneModel* m : {a_.get(), b_.get()})
      tessellate_scene_model(*m, options_.eps, nurbs::tess::TessMode::Guaranteed);
  } catch (const std::exception& e) {
    error_ = e.what();
    a_.reset();
    b_.reset();
    return;
  }
  for (const auto& f : a_->faces) add_trim_loops(f, {0.08f, 0.08f, 0.1f}, edges_a_);
  for (const auto& f : b_->faces) add_trim_loops(f, {0.08f, 0.08f, 0.1f}, edges_b_);

  // B's placement: the options, else beside A along x with a gap of a tenth of their sizes.
  double v[4];
  // The options were checked in main.cpp.
  if (!options_.move_b.empty() && parse_numbers(options_.move_b, 3, v)) {
    placement_.move = {v[0], v[1], v[2]};
  } else {
    const glm::dvec3 ca = 0.5 * (a_->mesh_min + a_->mesh_max), cb = 0.5 * (b_->mesh_min + b_->mesh_max);
    const double half = 0.5 * ((a_->mesh_max.x - a_->mesh_min.x) + (b_->mesh_max.x - b_->mesh_min.x));
    placement_.move = ca - cb + glm::dvec3(half + 0.1 * std::max(a_->size, b_->size), 0.0, 0.0);
  }
  if (!options_.rotate_b.empty() && parse_numbers(options_.rotate_b, 4, v)) {
    placement_.axis = {v[0], v[1], v[2]};
    placement_.deg = v[3];
  }
}

void App::frame_camera() {
  if (!a_) return;
  glm::dvec3 lo = a_->mesh_min, hi = a_->mesh_max;
  if (has_b() && mode_ == Mode::Clearance) {
    const glm::dmat4 m = motion_b();
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 c(k & 1 ? b_->mesh_max.x : b_->mesh_min.x, k & 2 ? b_->mesh_max.y : b_->mesh_min.y,
                         k & 4 ? b_->mesh_max.z : b_->mesh_min.z);
      const glm::dvec3 p = glm::dvec3(m * glm::dvec4(c, 1.0));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  }
  int w = options_.width, h = options_.height;
  if (window_ != nullptr) glfwGetWindowSize(static_cast<GLFWwindow*>(window_), &w, &h);
  camera_.frame(lo, hi, (double(w) - panel_width_) / std::max(h, 1));
}

void App::set_mode(Mode mode) {
  if (mode == mode_) return;
  mode_ = mode;
  if (mode == Mode::Clearance) clearance_dirty_ = true;
  if (mode == Mode::Thickness && a_ && !thickness_.ready() && thickness_error_.empty()) {
    try {
      thickness_.compute(a_->loaded, 20000);
    } catch (const std::exception& e) {  // said in the panel; the other modes go on
      thickness_error_ = e.what();
    }
  }
  frame_camera();
}

void App::scripted_frame(int k) {
  // B slides along x past A and ends exactly at the given placement on the last frame, so that
  // frame's readout is `nurbsgl clearance A B --move-b ...` at that placement.
  if (k == 0) final_move_ = placement_.move;
  const int n = options_.frames;
  const double sweep = 1.5 * std::max(a_->size, b_->size);
  const double s = n > 1 ? double(k - (n - 1)) / double(n - 1) : 0.0;
  placement_.move = final_move_;
  if (k != n - 1) placement_.move.x += s * sweep;
  clearance_dirty_ = true;
}

void App::print_scripted_results() {
  if (clearance_)
    fmt::print("clearance {:.9g} +- {:.3g}{}\n", clearance_->distance, clearance_->bound,
               clearance_->intersecting ? " (intersecting)" : "");
  // The mesh and the thickness map as `nurbsgl tessellate` and `nurbsgl thickness` report them on
  // the same model (the same front doors): the test compares them.
  if (mode_ == Mode::Tessellation && a_)
    fmt::print("mesh {} triangles, {} vertices, eps {:.9g}\n", a_->tess.stats.triangles, a_->tess.stats.vertices,
               a_->tess_eps);
  if (mode_ == Mode::Thickness && thickness_.ready())
    fmt::print("thickness {} rays, {} hits, min {}, max {}\n", thickness_.rays, thickness_.hits, thickness_.lo,
               thickness_.hi);
  // B's placement as `nurbsgl clearance` options, every digit of the doubles: the CLI rerun at it
  // builds the same motion bit for bit.
  if (mode_ == Mode::Clearance && has_b()) fmt::print("placement {}\n", placement_.cli_arguments(17));
  if (mode_ == Mode::Clearance && show_culled_ && pruning_.too_many)
    fmt::print(stderr, "culled boxes at level {}: {} block pairs, not pruned (over 4e6)\n", cell_level_,
               pruning_.pairs);
  else if (mode_ == Mode::Clearance && show_culled_ && blocks_a_ && blocks_b_)
    fmt::print(stderr,
               "culled boxes at level {}: A {} kept, {} pruned, {} trim-culled; B {} kept, {} pruned, {} trim-culled "
               "(U = {:.6g}, {} pairs in {:.1f} ms)\n",
               cell_level_, pruning_.kept_a, blocks_a_->kept.size() - size_t(pruning_.kept_a),
               blocks_a_->trimmed.size(), pruning_.kept_b, blocks_b_->kept.size() - size_t(pruning_.kept_b),
               blocks_b_->trimmed.size(), pruning_.upper, pruning_.pairs, pruning_ms_);
  const auto summary = [](std::vector<double> ms) {  // "median M ms (min A, max B)"
    std::sort(ms.begin(), ms.end());
    return fmt::format("median {:.1f} ms (min {:.1f}, max {:.1f})", ms[ms.size() / 2], ms.front(), ms.back());
  };
  if (mode_ == Mode::Clearance && !scripted_query_ms_.empty())
    fmt::print(stderr, "{} frames: clearance query {}, models prepared in {:.3f} s\n", scripted_query_ms_.size(),
               summary(scripted_query_ms_), prepare_s_);
  if (!scripted_frame_ms_.empty())
    fmt::print(stderr, "frame time {} over frames 2-{}\n", summary(scripted_frame_ms_), scripted_frame_ms_.size() + 1);
}

int App::run() {
  try {
    start_gl();
  } catch (const gpgpu::NoGlError& e) {  // the viewer has one backend, a window: no --gl to suggest
    fmt::print(stderr,
               "nurbsgl-viewer: no OpenGL 4.5 window ({}); the viewer needs a display (X11 or Wayland; without "
               "one, xvfb-run -a nurbsgl-viewer ...); the nurbsgl commands run headless\n",
               e.tried().empty() ? e.what() : e.tried());
    return kNoGl;
  }
  load_models();
  if (!error_.empty()) fmt::print(stderr, "nurbsgl-viewer: {}\n", error_);
  if (a_) {
    const std::string& m = options_.mode;
    // Two models, or a scripted run (B then a copy of A): clearance; else view.
    Mode start = options_.models.size() > 1 || options_.frames > 0 ? Mode::Clearance : Mode::View;
    if (!m.empty())
      start = m == "view"           ? Mode::View
              : m == "clearance"    ? Mode::Clearance
              : m == "tessellation" ? Mode::Tessellation
                                    : Mode::Thickness;
    set_mode(start);
    const auto& ov = options_.overlays;
    show_cells_ = std::find(ov.begin(), ov.end(), "cells") != ov.end();
    show_voxels_ = std::find(ov.begin(), ov.end(), "voxels") != ov.end();
    show_culled_ = std::find(ov.begin(), ov.end(), "culled") != ov.end();
    show_faces_ = std::find(ov.begin(), ov.end(), "faces") != ov.end();
    cell_level_ = options_.level;
    clearance_dirty_ = true;
    if (options_.face >= 0 && options_.face < static_cast<int>(a_->faces.size())) {
      picked_model_ = 0;
      picked_face_ = options_.face;
      rebuild_selection_overlay();
    }
  }
  frame_camera();
  auto* window = static_cast<GLFWwindow*>(window_);
  last_frame_ = std::chrono::steady_clock::now();
  int exit_code = error_.empty() ? kOk : kBadInput;
  for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
    glfwPollEvents();
    int window_width = 0, window_height = 0;
    glfwGetWindowSize(window, &window_width, &window_height);
    camera_.set_center_offset(double(panel_width_) / std::max(window_width, 1));
    const bool scripted = options_.frames > 0, events = !options_.events.empty();
    if (scripted && !events && a_ && mode_ == Mode::Clearance) scripted_frame(frame);
    if (scripted && a_ && frame == 0 && !options_.pick.empty()) {
      double xy[2] = {0.0, 0.0};
      (void)parse_numbers(options_.pick, 2, xy);  // checked in main.cpp
      pick_at(xy[0], xy[1]);
      if (picked_face_ < 0)
        fmt::print(stderr, "picked nothing at ({}, {})\n", xy[0], xy[1]);
      else
        fmt::print(stderr, "picked {} face {} at ({}, {})\n", picked_model_ == 0 ? "A" : "B", picked_face_, xy[0],
                   xy[1]);
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    apply_scripted_input(frame);
    ImGui::NewFrame();
    if (!scripted || events) handle_input();
    if (mode_ == Mode::Clearance && a_ && (clearance_dirty_ || continuous_)) {
      query_clearance();
      if (scripted) scripted_query_ms_.push_back(query_ms_);
    }
    if (overlay_dirty_ && mode_ == Mode::Clearance && a_) rebuild_overlays();  // the panel shows their counts
    draw_panels();
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    render_scene(fw, fh);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    gpgpu::gl::check_error("viewer frame");

    const auto now = std::chrono::steady_clock::now();
    const double frame_ms = std::chrono::duration<double, std::milli>(now - last_frame_).count();
    if (scripted && frame > 0) scripted_frame_ms_.push_back(frame_ms);  // the first frame prepares the models
    frame_ms_[history_at_] = static_cast<float>(frame_ms);
    query_ms_history_[history_at_] = static_cast<float>(query_ms_);
    history_at_ = (history_at_ + 1) % kHistory;
    last_frame_ = now;

    if (scripted && frame + 1 >= options_.frames) {
      if (!options_.screenshot.empty()) write_screenshot(options_.screenshot, fw, fh);
      print_scripted_results();
      if (!clearance_error_.empty()) {
        fmt::print(stderr, "nurbsgl-viewer: clearance: {}\n", clearance_error_);
        exit_code = std::max(exit_code, int(kFailed));
      }
      break;
    }
    glfwSwapBuffers(window);
  }
  return exit_code;
}

}  // namespace viewer
