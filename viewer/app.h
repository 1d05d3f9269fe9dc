#pragma once
/// \file app.h
/// The desktop viewer: one GLFW window whose GL context is the gpgpu::Gpu's (the
/// queries run in it between frames), Dear ImGui panels, four modes (view, clearance,
/// tessellation, thickness) and scripted runs (a motion of B, or input replayed from --events) that
/// write a screenshot and print the readout and B's placement.
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "queries/distance/clearance.h"
#include "queries/distance/clearance_pair.h"
#include "queries/distance/prepared_model.h"
#include "queries/distance/voxel_stage.h"
#include "viewer/camera.h"
#include "viewer/draw_buffers.h"
#include "viewer/input_script.h"
#include "viewer/overlays.h"
#include "viewer/placement.h"
#include "viewer/scene_model.h"
#include "viewer/thickness_view.h"

namespace viewer {

struct ViewerOptions {
  std::vector<std::string> models;    ///< MODEL [MODEL2]; without MODEL2, B is a copy of A
  int frames = 0;                     ///< > 0: scripted run of that many frames, then exit
  std::string screenshot;             ///< PNG written from the last scripted frame
  std::string move_b, rotate_b;       ///< B's (final) placement, as `nurbsgl clearance`
  double rel_tolerance = 1e-5;        ///< as `nurbsgl clearance --tol`
  double eps = 1e-3;                  ///< display tessellation, relative to the model size
  std::string mode;                   ///< start mode: view, clearance, tessellation, thickness (empty: by models)
  int face = -1;                      ///< a face of A picked at start (its panel and overlays)
  std::vector<std::string> overlays;  ///< shown at start: cells, voxels, culled, faces
  int level = 3;                      ///< hierarchy level of the cell boxes
  std::string pick;                   ///< "X,Y": a click at that window pixel on the first frame
  std::vector<InputFrame> events;     ///< --events FILE: scripted input, one state per frame
  int width = 1280, height = 800;
};

enum class Mode { View, Clearance, Tessellation, Thickness };

/// Exit codes, as the nurbsgl CLI's.
enum ExitCode : int { kOk = 0, kFailed = 1, kBadInput = 2, kNoGl = 3 };

class App {
 public:
  explicit App(ViewerOptions options);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;
  /// Opens the window and runs until it closes (or the scripted frames end). Returns the exit code.
  int run();

 private:
  // app.cpp: set-up, loop
  void start_gl();
  void load_models();
  void frame_camera();
  void set_mode(Mode mode);
  void scripted_frame(int k);
  void print_scripted_results();
  // app_input.cpp: live or scripted input
  void apply_scripted_input(int frame);
  void handle_input();
  void pick_at(double x, double y);
  // app_clearance.cpp
  void prepare_clearance();
  void query_clearance();
  void rebuild_overlays();
  void update_blocks();
  // app_render.cpp
  void render_scene(int width, int height);
  void rebuild_selection_overlay();
  void draw_segment(const glm::dmat4& view_projection, int width, int height);
  // app_panels.cpp
  void draw_panels();
  void panel_face();
  void panel_clearance();
  void panel_culled();
  void panel_tessellation();
  void panel_thickness();
  void panel_help();
  void panel_error();

  [[nodiscard]] bool has_b() const { return b_ != nullptr; }
  [[nodiscard]] glm::dmat4 motion_b() const { return placement_.matrix(); }

  ViewerOptions options_;
  std::unique_ptr<gpgpu::Gpu> gpu_;
  void* window_ = nullptr;  // GLFWwindow*
  bool imgui_ready_ = false;
  int scripted_key_ = -1;  ///< the key an --events frame holds down in ImGui's IO
  gpgpu::Program* mesh_program_ = nullptr;
  gpgpu::Program* line_program_ = nullptr;

  std::unique_ptr<SceneModel> a_, b_;
  std::string error_;  ///< a model that failed to load: shown in the window, exit code 2
  Camera camera_;
  Mode mode_ = Mode::View;
  float panel_width_ = 390.0f;  ///< window pixels the left panel covers (the scene is centred right of it)
  bool show_help_ = false, show_edges_ = true, wireframe_ = false;

  // Picking: (model 0 = A, 1 = B, face index)
  int picked_model_ = -1, picked_face_ = -1;
  LineBatch selection_overlay_;
  LineBatch edges_a_, edges_b_;
  LineBatch segment_, segment_hidden_, segment_ends_;  ///< in front of the scene, behind it (dashed), its ends

  // Clearance (Krishnamurthy et al. §5, the paper's Fig. 16 interaction)
  Placement placement_;
  glm::dvec3 final_move_{0.0};  ///< scripted run: B's placement on the last frame
  std::vector<double> scripted_query_ms_, scripted_frame_ms_;
  /// Both models prepared for any placement of B (queries/distance/clearance_pair.h), A's hierarchy kept
  /// between queries; declared after gpu_: destroyed first.
  std::unique_ptr<queries::ClearancePair> clearance_pair_;
  std::optional<queries::Clearance> clearance_;
  std::string clearance_uncertified_;  ///< why the answer shown is not certified; empty when it may be
  double query_ms_ = 0.0, prepare_s_ = 0.0;
  bool clearance_dirty_ = true, continuous_ = false;
  std::string clearance_error_;

  // Overlays of the search (overlays.h)
  bool show_cells_ = false, show_voxels_ = false, show_culled_ = false, show_faces_ = false, overlay_dirty_ = true;
  int cell_level_ = 3;
  long long cell_boxes_ = 0;  ///< drawn per model A + B; -1: too many at this level
  // Blocks of cells at blocks_level_ (both models, their own frames) and their pruning for B's placement
  std::optional<CellBlocks> blocks_a_, blocks_b_;
  int blocks_level_ = -1;
  BlockPruning pruning_;
  double pruning_ms_ = 0.0;
  std::unique_ptr<queries::VoxelGrid> voxels_a_, voxels_b_;
  std::optional<queries::VoxelStage> voxel_stage_;
  LineBatch overlay_a_, overlay_b_;

  // Tessellation (Balázs et al.)
  float eps_rel_ = 1e-3f;
  bool approximate_ = false;

  // Thickness (Lemasson et al.)
  ThicknessView thickness_;
  std::string thickness_error_;
  float thick_threshold_ = 0.0f;  ///< model units; samples thinner are striped

  // Frame and query time graphs, milliseconds
  static constexpr int kHistory = 240;
  std::array<float, kHistory> frame_ms_{}, query_ms_history_{};
  int history_at_ = 0;
  std::chrono::steady_clock::time_point last_frame_;
};

}  // namespace viewer
