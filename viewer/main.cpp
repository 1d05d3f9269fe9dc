// `nurbsgl-viewer MODEL [MODEL2]`: the desktop viewer (viewer/app.h). With
// `--frames N --screenshot FILE.png` it runs a scripted motion of B for N frames, writes the last
// frame as PNG, prints that frame's readout "clearance D +- B" (as `nurbsgl clearance`) and exits.
// `--events FILE` replays scripted mouse and key input instead (viewer/input_script.h) and prints B's
// final placement as `nurbsgl clearance` options.
// Exit codes as nurbsgl's: 0 ok, 1 a query failed, 2 bad command line or model, 3 no OpenGL.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>

#include "viewer/app.h"
#include "viewer/input_script.h"
#include "viewer/placement.h"

namespace {

int run(int argc, char** argv) {
  viewer::ViewerOptions o;
  CLI::App app("nurbsgl-viewer: trimmed NURBS models, clearance, tessellation and thickness on the GPU.\n"
               "One model, or two for clearance (B defaults to a copy of A).",
               "nurbsgl-viewer");
  std::string model_a, model_b;
  app.add_option("A", model_a, "Model file")->required();
  app.add_option("B", model_b, "Second model file, for clearance (default: a copy of A)");
  app.add_option("--frames", o.frames, "Scripted run: N frames of B sliding past A to its placement, then exit")
      ->check(CLI::Range(1, 100000));
  app.add_option("--screenshot", o.screenshot, "With --frames: write the last frame as PNG");
  app.add_option("--move-b", o.move_b, "B's (final) placement: translate by DX,DY,DZ after the rotation");
  app.add_option("--rotate-b", o.rotate_b, "Rotate B by DEG degrees about AX,AY,AZ through the origin");
  app.add_option("--tol", o.rel_tolerance, "Clearance: the bound of the answer, relative to the larger model size (each model at half of it)")
      ->check(CLI::Range(1e-9, 0.1))
      ->capture_default_str();
  app.add_option("--eps", o.eps, "Displayed tessellation's eps, relative to the model size")
      ->check(CLI::Range(1e-6, 0.5))
      ->capture_default_str();
  app.add_option("--mode", o.mode, "Start mode (default: clearance with two models, else view)")
      ->check(CLI::IsMember({"view", "clearance", "tessellation", "thickness"}));
  app.add_option("--face", o.face, "Pick face I of A at start: its panel, control net and trim loops")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--overlay", o.overlays,
                 "Clearance overlays shown at start: cells, voxels, culled (blocks the trim culls and those pruned "
                 "at --level), faces (kept by the voxel stage)")
      ->check(CLI::IsMember({"cells", "voxels", "culled", "faces"}))
      ->delimiter(',');
  app.add_option("--level", o.level, "Hierarchy level of the cell boxes (2^level cells a side)")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  std::string events;
  app.add_option("--events", events,
                 "Replay the input events of FILE, one per frame (drag, click, key, wheel, move, frame; "
                 "viewer/input_script.h), then exit; prints B's placement as nurbsgl clearance options");
  app.add_option("--pick", o.pick, "Scripted run: click at window pixel X,Y on the first frame (picks a face)");
  app.add_option("--width", o.width, "Window width")->check(CLI::Range(64, 8192))->capture_default_str();
  app.add_option("--height", o.height, "Window height")->check(CLI::Range(64, 8192))->capture_default_str();
  try {
    app.parse(argc, argv);
    o.models = {model_a};
    if (!model_b.empty()) o.models.push_back(model_b);
    double v[4];
    if (!o.move_b.empty() && !viewer::parse_numbers(o.move_b, 3, v))
      throw CLI::ValidationError("--move-b", "'" + o.move_b + "' is not 3 finite numbers");
    if (!o.rotate_b.empty() && (!viewer::parse_numbers(o.rotate_b, 4, v) || (v[0] == 0 && v[1] == 0 && v[2] == 0)))
      throw CLI::ValidationError("--rotate-b", "'" + o.rotate_b + "' is not AX,AY,AZ,DEG with a non-zero axis");
    if (!events.empty()) {
      try {
        o.events = viewer::read_input_script(events);
      } catch (const std::runtime_error& e) {
        throw CLI::ValidationError("--events", e.what());
      }
      if (o.events.empty()) throw CLI::ValidationError("--events", events + ": no events");
      // The run lasts the script and one frame more, at least --frames.
      o.frames = std::max<int>(o.frames, static_cast<int>(o.events.size()) + 1);
    }
    if (!o.screenshot.empty() && o.frames == 0)
      throw CLI::ValidationError("--screenshot", "needs --frames N or --events");
    if (!o.pick.empty() && (o.frames == 0 || !viewer::parse_numbers(o.pick, 2, v)))
      throw CLI::ValidationError("--pick", "needs --frames N and X,Y");
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : viewer::kBadInput;
  }
  try {
    viewer::App viewer_app(o);
    return viewer_app.run();
  } catch (const std::exception& e) {
    fmt::print(stderr, "nurbsgl-viewer: {}\n", e.what());
    return viewer::kFailed;
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (...) {  // run() reports what it knows; this only keeps an exception from escaping main
    return viewer::kFailed;
  }
}
