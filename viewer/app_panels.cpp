// The Dear ImGui panels: mode, model, picked face, and each mode's controls and readouts.
#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <filesystem>

#include "nurbs/io/model_summary.h"
#include "nurbs/raycast/thickness.h"
#include "nurbs/request_error.h"
#include "viewer/app.h"

namespace viewer {

namespace {

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

/// The thickness ramp (nurbs::ray::thickness_ramp), for the legend.
ImU32 ramp(float t) {
  const glm::dvec3 c = nurbs::ray::thickness_ramp(t);
  return ImGui::GetColorU32(ImVec4(float(c.x), float(c.y), float(c.z), 1.0f));
}

}  // namespace

void App::draw_panels() {
  if (!error_.empty()) panel_error();
  if (show_help_) panel_help();
  if (!a_) return;
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("nurbsgl");
  ImGui::Text("A: %s (%zu faces)", file_name(a_->path).c_str(), a_->faces.size());
  for (const std::string& line : a_->loaded.report.lines(3)) ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "A: %s", line.c_str());
  if (options_.models.size() > 1)
    ImGui::Text("B: %s (%zu faces)", file_name(b_->path).c_str(), b_->faces.size());
  else
    ImGui::TextUnformatted("B: a copy of A");
  int mode = static_cast<int>(mode_);
  bool changed = ImGui::RadioButton("view", &mode, 0);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("clearance", &mode, 1);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("tessellation", &mode, 2);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("thickness", &mode, 3);
  if (changed) set_mode(static_cast<Mode>(mode));
  if (mode_ == Mode::View || mode_ == Mode::Clearance) ImGui::Checkbox("face edges (E)", &show_edges_);
  ImGui::Separator();
  switch (mode_) {
    case Mode::View:
      ImGui::TextWrapped("Click a face to see its id, degree, control net and trim loops.");
      break;
    case Mode::Clearance:
      panel_clearance();
      break;
    case Mode::Tessellation:
      panel_tessellation();
      break;
    case Mode::Thickness:
      panel_thickness();
      break;
  }
  ImGui::Separator();
  ImGui::TextDisabled("F1 or H: keyboard and mouse help");
  panel_width_ = ImGui::GetWindowPos().x + ImGui::GetWindowWidth();
  ImGui::End();
  panel_face();
}

void App::panel_face() {
  const SceneModel* m = picked_model_ == 0 ? a_.get() : picked_model_ == 1 ? b_.get() : nullptr;
  if (m == nullptr || picked_face_ < 0) return;
  const nurbs::TrimmedSurface& face = m->faces[size_t(picked_face_)];
  const nurbs::io::FaceSummary f = nurbs::io::summarize_face(face);
  ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x - 310, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(300, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("face");
  ImGui::Text("model %s, face %d (file id %d)", picked_model_ == 0 ? "A" : "B", picked_face_, f.face_id);
  if (!f.name.empty()) ImGui::Text("name %s", f.name.c_str());
  ImGui::Text("degree %d x %d, %s", f.degree_u, f.degree_v, f.rational ? "rational" : "polynomial");
  ImGui::Text("control points %d x %d = %d", f.count_u, f.count_v, f.count_u * f.count_v);
  ImGui::Text("trim loops %d outer, %d inner, %d curves", f.outer_loops, f.inner_loops, f.trim_curves);
  if (face.reversed) ImGui::TextUnformatted("reversed (outward normal -Su x Sv)");
  ImGui::TextColored(ImVec4(0.95f, 0.85f, 0.2f, 1), "control net");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.1f, 0.9f, 0.95f, 1), "trim loops");
  if (ImGui::Button("clear (click empty space)")) {
    picked_model_ = picked_face_ = -1;
    rebuild_selection_overlay();
  }
  ImGui::End();
}

void App::panel_clearance() {
  if (clearance_) {
    const queries::Clearance& c = *clearance_;
    ImGui::Text("clearance %.9g +- %.3g", c.distance, c.bound);
    ImGui::Text("proven in [%.9g, %.9g]%s", c.distance - c.bound, c.distance,
                c.meets_tolerance || !clearance_uncertified_.empty() ? "" : " (above T)");
    if (!clearance_uncertified_.empty()) {
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "not certified: %s", clearance_uncertified_.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::Text("faces %d (A) and %d (B)%s", c.face_a, c.face_b, c.on_trim_edge ? ", on a trim edge" : "");
    if (c.intersecting)
      ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "the models intersect at (%.6g, %.6g, %.6g)", c.intersection.x,
                         c.intersection.y, c.intersection.z);
    ImGui::Text("query %.1f ms, %d refinement rounds", query_ms_, c.rounds);
    ImGui::Text("models prepared in %.2f s (K_e <= %.3g)", prepare_s_, clearance_pair_->prepared_a().tolerance);
  } else if (!clearance_error_.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", clearance_error_.c_str());
    ImGui::PopTextWrapPos();
  }
  ImGui::TextDisabled("Shift + left drag: move B; Shift + right drag: turn B");
  bool moved = ImGui::DragScalarN("move B", ImGuiDataType_Double, &placement_.move[0], 3,
                                  static_cast<float>(0.002 * std::max(a_->size, b_->size)));
  moved |= ImGui::DragScalarN("axis", ImGuiDataType_Double, &placement_.axis[0], 3, 0.01f);
  moved |= ImGui::DragScalar("degrees", ImGuiDataType_Double, &placement_.deg, 0.2f);
  if (moved) clearance_dirty_ = true;
  ImGui::Checkbox("query every frame (Space)", &continuous_);
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextDisabled("same as: nurbsgl clearance A B %s", placement_.cli_arguments().c_str());
  ImGui::PopTextWrapPos();
  // Open at start when --overlay asked for some.
  if (ImGui::CollapsingHeader("overlays (search of 5.1-5.4)",
                              options_.overlays.empty() ? 0 : ImGuiTreeNodeFlags_DefaultOpen)) {
    bool again = ImGui::Checkbox("cell AABBs", &show_cells_);
    ImGui::SameLine();
    again |= ImGui::SliderInt("level", &cell_level_, 0, 10);
    if (show_cells_) {
      if (cell_boxes_ < 0)
        ImGui::TextDisabled("too many boxes at this level: raise it");
      else
        ImGui::TextDisabled("%lld boxes of 2^%d x 2^%d grid cells, grown by K", cell_boxes_, cell_level_, cell_level_);
    }
    again |= ImGui::Checkbox("culled boxes at this level", &show_culled_);
    if (show_culled_) panel_culled();
    again |= ImGui::Checkbox("voxel grid of the first stage (40^3)", &show_voxels_);
    if (ImGui::Checkbox("faces kept (green) / culled (red) by the voxel stage", &show_faces_)) {
      again = true;
      clearance_dirty_ = true;
    }
    if (again) overlay_dirty_ = true;
  }
  const float frame_max = std::max(20.0f, *std::max_element(frame_ms_.begin(), frame_ms_.end()));
  const std::string frame_label = fmt::format("frame {:.1f} ms", frame_ms_[(history_at_ + kHistory - 1) % kHistory]);
  ImGui::PlotLines("##frame", frame_ms_.data(), kHistory, history_at_, frame_label.c_str(), 0.0f, frame_max,
                   ImVec2(0, 60));
  const std::string query_label = fmt::format("query {:.1f} ms", query_ms_);
  ImGui::PlotLines("##query", query_ms_history_.data(), kHistory, history_at_, query_label.c_str(), 0.0f, frame_max,
                   ImVec2(0, 60));
}

void App::panel_culled() {
  if (!blocks_a_ || !blocks_b_) {
    ImGui::TextDisabled("too many boxes at this level: raise it");
    return;
  }
  ImGui::TextDisabled("trim culls (grey, 5.3): %zu blocks of A, %zu of B", blocks_a_->trimmed.size(),
                      blocks_b_->trimmed.size());
  if (pruning_.too_many) {
    ImGui::TextDisabled("%lld block pairs, over 4e6: not pruned here; raise the level", pruning_.pairs);
    return;
  }
  ImGui::TextDisabled("pruned (red, 5.1): A %lld of %zu, B %lld of %zu blocks",
                      static_cast<long long>(blocks_a_->kept.size()) - pruning_.kept_a, blocks_a_->kept.size(),
                      static_cast<long long>(blocks_b_->kept.size()) - pruning_.kept_b, blocks_b_->kept.size());
  ImGui::TextDisabled("kept (green): lower bound <= U = %.6g", pruning_.upper);
  ImGui::TextDisabled("%lld pairs in %.1f ms (CPU, double)", pruning_.pairs, pruning_ms_);
}

void App::panel_tessellation() {
  const auto& st = a_->tess.stats;
  ImGui::Text("%lld triangles, %lld vertices in %.2f s", st.triangles, st.vertices, a_->tess_seconds);
  if (st.failed_faces > 0) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%d faces failed", st.failed_faces);
  ImGui::Text("eps %.4g model units", a_->tess_eps);
  if (!a_->tess_failure.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "not certified: %s", a_->tess_failure.c_str());
    ImGui::PopTextWrapPos();
  }
  ImGui::SliderFloat("eps / size", &eps_rel_, 1e-5f, 1e-1f, "%.2e", ImGuiSliderFlags_Logarithmic);
  bool again = ImGui::IsItemDeactivatedAfterEdit();
  int mode = approximate_ ? 1 : 0;
  again |= ImGui::RadioButton("guaranteed", &mode, 0);
  ImGui::SameLine();
  again |= ImGui::RadioButton("approximate (no bound)", &mode, 1);
  approximate_ = mode == 1;
  ImGui::Checkbox("wireframe only (W)", &wireframe_);
  if (again) {
    const auto tm = approximate_ ? nurbs::tess::TessMode::Approximate : nurbs::tess::TessMode::Guaranteed;
    try {
      for (SceneModel* m : {a_.get(), b_.get()}) tessellate_scene_model(*m, double(eps_rel_), tm);
    } catch (const nurbs::RequestError& e) {  // an eps the model cannot be meshed at: the mesh stays
      a_->tess_failure = e.what();
    }
    picked_model_ = picked_face_ = -1;
    rebuild_selection_overlay();
  }
  ImGui::TextDisabled(approximate_ ? "Balazs et al.'s estimate: eps for loops and surface"
                                   : "proven: eps/2 for the trim loops, eps/2 for the cells");
}

void App::panel_thickness() {
  if (!thickness_error_.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", thickness_error_.c_str());
    ImGui::PopTextWrapPos();
  }
  if (!thickness_.ready()) return;
  ImGui::Text("%lld rays, %lld hits in %.2f s (CPU ray caster)", thickness_.rays, thickness_.hits, thickness_.seconds);
  ImGui::Text("thickness %.5g to %.5g", thickness_.lo, thickness_.hi);
  if (!thickness_.uncertified.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "not certified: %s", thickness_.uncertified.c_str());
    ImGui::PopTextWrapPos();
  }
  if (thick_threshold_ <= 0.0f) thick_threshold_ = static_cast<float>(thickness_.quantile(0.05));
  ImGui::SliderFloat("threshold", &thick_threshold_, float(thickness_.lo), float(thickness_.hi), "%.4g");
  ImGui::Text("%lld of %lld samples below (striped white)", thickness_.below(thick_threshold_), thickness_.hits);
  // Legend: the colour ramp from the thinnest to the thickest hit.
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float w = ImGui::GetContentRegionAvail().x, h = 16.0f;
  ImDrawList* dl = ImGui::GetWindowDrawList();
  constexpr int kSteps = 24;
  for (int i = 0; i < kSteps; ++i) {
    const float x0 = p.x + w * i / kSteps, x1 = p.x + w * (i + 1) / kSteps;
    dl->AddRectFilledMultiColor(ImVec2(x0, p.y), ImVec2(x1, p.y + h), ramp(float(i) / kSteps),
                                ramp(float(i + 1) / kSteps), ramp(float(i + 1) / kSteps), ramp(float(i) / kSteps));
  }
  ImGui::Dummy(ImVec2(w, h));
  ImGui::Text("%.4g (thin)", thickness_.lo);
  ImGui::SameLine(w - 80);
  ImGui::Text("%.4g", thickness_.hi);
  ImGui::TextDisabled("grey: no hit (open shell or ray escaped)");
}

void App::panel_help() {
  ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f),
                          ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  ImGui::Begin("help", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  const char* lines[][2] = {{"left drag", "orbit"},
                            {"right or middle drag", "pan"},
                            {"wheel", "zoom"},
                            {"click", "pick a face (id, degree, control net, trim loops)"},
                            {"1 2 3 4", "view, clearance, tessellation, thickness"},
                            {"Shift + left drag", "clearance: move B in the view plane"},
                            {"Shift + right drag", "clearance: turn B about its centre"},
                            {"Q / R", "clearance: turn B 5 degrees about z (Shift: 1)"},
                            {"Space", "clearance: query every frame"},
                            {"E", "face edges"},
                            {"W", "tessellation: wireframe only"},
                            {"F", "frame the models"},
                            {"F1 or H", "this help"},
                            {"Esc", "quit"}};
  if (ImGui::BeginTable("keys", 2)) {
    for (const auto& l : lines) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(l[0]);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(l[1]);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

void App::panel_error() {
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(size.x * 0.5f, size.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(size.x - 40.0f, 700.0f), 0), ImGuiCond_Always);
  ImGui::Begin("cannot load the model", nullptr, ImGuiWindowFlags_NoCollapse);
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.45f, 1.0f), "%s", error_.c_str());
  ImGui::PopTextWrapPos();
  ImGui::TextDisabled("Esc closes the window (exit code 2).");
  ImGui::End();
}

}  // namespace viewer
