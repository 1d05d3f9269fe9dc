// Benchmark of the object first stage of Krishnamurthy et al. §5.4 (queries/distance/voxel_stage.h): the
// teapot moved near the wall of the vase. Prints voxels per object, voxel pairs, surviving pairs,
// face pairs kept of all, time per stage (GPU and the CPU twin), then the clearance three ways:
// the hierarchy over all faces (queries::clearance as it is), and a driver that runs the voxel
// stage and then queries::clearance on models prepared from the kept faces only. Not a test: it
// prints figures and asserts nothing about speed.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <glm/gtc/matrix_transform.hpp>

#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "queries/distance/clearance.h"
#include "queries/distance/voxel_stage.h"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::vector<nurbs::TrimmedSurface> subset(const std::vector<nurbs::TrimmedSurface>& faces,
                                          const std::vector<char>& keep) {
  std::vector<nurbs::TrimmedSurface> out;
  for (size_t f = 0; f < faces.size(); ++f)
    if (keep[f]) out.push_back(faces[f]);
  return out;
}

void print_grid(const char* name, const queries::VoxelGrid& g) {
  fmt::print(
      "{}: {} faces, {}^3 voxels of {:.4g} x {:.4g} x {:.4g}: {} occupied ({} witnesses), {} cells "
      "({} skipped as trimmed away), {:.1f} ms\n",
      name, g.face_count, g.n, g.h.x, g.h.y, g.h.z, g.voxels.size(), std::count(g.witness.begin(), g.witness.end(), 1),
      g.cells, g.skipped_cells, 1e3 * g.seconds);
}

void print_clearance(const char* name, const queries::Clearance& c, double ms) {
  fmt::print("{}: distance {:.9g} +- {:.3g} (faces {}, {}), {} levels, {} leaf pairs, {:.1f} ms\n", name, c.distance,
             c.bound, c.face_a, c.face_b, c.pairs_per_level.size(), c.leaf_pairs, ms);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Voxel first stage (Krishnamurthy et al. §5.4): teapot near the vase wall"};
  std::string backend = "auto", shared = NURBSGL_SHARED_DIR;
  // Default: the teapot (its base at z = 0, about 6.4 x 4 x 3.2) halfway up the vase, its spout
  // side 1-2 units from the outer wall (found by trying: the clearance is printed below).
  std::vector<double> move{33.75, 0.0, 48.65};
  double rel_tol = 1e-4;
  int n = 40, reps = 3, tile = 1024;
  app.add_option("--gl", backend, "GL backend: auto, egl, egl-device, osmesa, glfw")->capture_default_str();
  app.add_option("--shared", shared, "Folder holding models/generated")->capture_default_str();
  app.add_option("--n", n, "Voxels per axis")->capture_default_str();
  app.add_option("--move-b", move, "Move of the teapot (DX DY DZ)")->expected(3)->capture_default_str();
  app.add_option("--tol", rel_tol, "Clearance tolerance relative to the larger model size")->capture_default_str();
  app.add_option("--tile", tile, "Tile side of the culled run")->capture_default_str();
  app.add_option("--reps", reps, "Repetitions of each query (median)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::string dir = shared + "/models/generated/";
  const nurbs::Model vase = nurbs::io::read_model(dir + "vase_shell_t2.igs");
  const nurbs::Model teapot = nurbs::io::read_model(dir + "teapot_bezier32.igs");
  const std::vector<nurbs::TrimmedSurface> fa = nurbs::world_faces(vase), fb = nurbs::world_faces(teapot);
  const nurbs::Box va = nurbs::model_box(vase), tb = nurbs::model_box(teapot);
  fmt::print(
      "vase box ({:.4g} {:.4g} {:.4g})-({:.4g} {:.4g} {:.4g}), teapot box ({:.4g} {:.4g} {:.4g})-({:.4g} {:.4g} "
      "{:.4g})\n",
      va.min.x, va.min.y, va.min.z, va.max.x, va.max.y, va.max.z, tb.min.x, tb.min.y, tb.min.z, tb.max.x, tb.max.y,
      tb.max.z);
  const glm::dmat4 motion = glm::translate(glm::dmat4(1.0), glm::dvec3(move[0], move[1], move[2]));
  fmt::print("teapot moved by ({:.6g}, {:.6g}, {:.6g})\n", move[0], move[1], move[2]);

  gpgpu::Gpu gpu(gpgpu::ContextOptions{gpgpu::parse_backend(backend)});
  fmt::print("backend {} on {}, GL_MAX_TEXTURE_SIZE {}\n", gpu.info().backend, gpu.info().renderer,
             gpu.info().max_texture_size);

  const queries::VoxelGrid ga = queries::voxelize(fa, {.n = n}), gb = queries::voxelize(fb, {.n = n});
  print_grid("vase", ga);
  print_grid("teapot", gb);
  const auto stage = [&](const queries::VoxelOptions& o) {
    std::vector<queries::VoxelStage> runs;
    for (int r = 0; r < std::max(1, reps); ++r) runs.push_back(queries::voxel_stage(gpu, ga, gb, motion, o));
    std::sort(runs.begin(), runs.end(), [](const auto& x, const auto& y) { return x.timings.total < y.timings.total; });
    return runs[runs.size() / 2];
  };
  const auto tc = Clock::now();
  const queries::VoxelStage cpu = queries::voxel_stage_cpu(ga, gb, motion);
  const double cpu_ms = ms_since(tc);
  const queries::VoxelStage faithful = stage({}), culled = stage({.max_tile = tile, .cull_tiles = true});
  for (const queries::VoxelStage* x : {&faithful, &culled}) {
    const queries::VoxelTimings& t = x->timings;
    fmt::print(
        "{}: voxel pairs {} ({} tiles, {} culled), surviving {}, U {:.6g}; face pairs kept {} of {} (vase faces "
        "{}, teapot faces {}); same face pairs as the CPU twin: {}\n",
        x == &faithful ? "voxel stage (paper)" : "voxel stage, tiles culled", x->voxel_pairs, x->tiles, x->culled_tiles,
        x->surviving_pairs, x->upper, x->face_pairs.size(), fa.size() * fb.size(),
        std::count(x->faces_a.begin(), x->faces_a.end(), 1), std::count(x->faces_b.begin(), x->faces_b.end(), 1),
        cpu.face_pairs == x->face_pairs ? "yes" : "NO");
    fmt::print(
        "  GPU median of {}: upload {:.1f} ms, min/max passes {:.1f} ms, reduce {:.1f} ms, threshold + "
        "compact {:.1f} ms, read-back + face pairs {:.1f} ms, total {:.1f} ms\n",
        std::max(1, reps), 1e3 * t.upload, 1e3 * t.minmax, 1e3 * t.reduce, 1e3 * t.compact, 1e3 * t.readback,
        1e3 * t.total);
  }
  fmt::print("CPU twin (double, every pair): {:.1f} ms, surviving {}\n", cpu_ms, cpu.surviving_pairs);

  // Clearance: the hierarchy over all faces, then the driver on the kept faces.
  const double tol = rel_tol * std::max(nurbs::model_size(vase), nurbs::model_size(teapot));
  auto t0 = Clock::now();
  const queries::PreparedModel pa = queries::prepare_model(gpu, fa, tol), pb = queries::prepare_model(gpu, fb, tol);
  gpu.finish();
  fmt::print("tolerance {:.3g}: prepare all faces {:.1f} ms\n", tol, ms_since(t0));
  const auto timed = [&](const queries::PreparedModel& a, const queries::PreparedModel& b, double& ms) {
    std::vector<double> t;
    queries::Clearance c;
    for (int r = 0; r < std::max(1, reps); ++r) {
      const auto t1 = Clock::now();
      c = queries::clearance(gpu, a, b, motion);
      t.push_back(ms_since(t1));
    }
    std::sort(t.begin(), t.end());
    ms = t[t.size() / 2];
    return c;
  };
  double all_ms = 0, kept_ms = 0;
  const queries::Clearance all = timed(pa, pb, all_ms);
  print_clearance("clearance, hierarchy over all faces", all, all_ms);
  t0 = Clock::now();
  const queries::PreparedModel qa = queries::prepare_model(gpu, subset(fa, faithful.faces_a), tol),
                               qb = queries::prepare_model(gpu, subset(fb, faithful.faces_b), tol);
  gpu.finish();
  const double prep_kept = ms_since(t0);
  fmt::print("prepare kept faces {:.1f} ms\n", prep_kept);
  const queries::Clearance kept = timed(qa, qb, kept_ms);
  print_clearance("clearance, kept faces only (face ids of the subsets)", kept, kept_ms);
  fmt::print(
      "voxel stage + clearance on kept faces: {:.1f} ms (paper) / {:.1f} ms (tiles culled), + {:.1f} ms "
      "preparing them, against {:.1f} ms for the hierarchy over all faces; distances differ by {:.3g}\n",
      1e3 * faithful.timings.total + kept_ms, 1e3 * culled.timings.total + kept_ms, prep_kept, all_ms,
      kept.distance - all.distance);
  return 0;
}
