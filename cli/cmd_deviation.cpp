// `nurbsgl deviation MODEL MESH [--eps E [--relative]] [--samples N] [--json]`: how far any triangle
// mesh (ours, OpenCASCADE's, a CAD exporter's) lies from a model's trimmed faces, measured the same way
// as `tessellate --check` (nurbs/tessellation/mesh_check.h). No GPU.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/validators.h"
#include "nurbs/io/mesh_reader.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/tessellation/mesh_parameters.h"
#include "nurbs/tessellation/tessellate.h"
#include "nurbs/tessellation/triangle_bvh.h"
#include "nurbs/trim_classify.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_deviation_impl {

struct DeviationArgs {
  std::string model, mesh;
  double eps = 0.0;
  bool eps_given = false, relative = false, json = false, no_parameters = false;
  int samples = 48, threads = 0;
};

void run(const GlobalOptions& global, const DeviationArgs& a) {
  if (a.relative && !a.eps_given) throw BadInput("--relative: needs --eps");
  const auto start = std::chrono::steady_clock::now();
  const LoadedModel loaded = load_model(a.model, "deviation");
  const nurbs::Model& model = loaded.model;
  const double size = nurbs::checked_model_size(model, a.model);
  const double eps = a.relative ? a.eps * size : a.eps;
  if (a.eps_given && (!(eps > 0) || !std::isfinite(eps)))
    throw BadInput(fmt::format("--eps: {} is not a positive tolerance", eps));
  const nurbs::TriangleMesh mesh = nurbs::io::read_mesh_file(a.mesh, nurbs::coordinate_limit(nurbs::model_box(model)));
  if (mesh.triangles.empty()) throw BadInput(fmt::format("{}: the mesh has no triangles", a.mesh));
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  nurbs::tess::DeviationOptions o;
  o.samples = a.samples;
  // The boundary polylines as `tessellate --check` makes them for the same eps, so that both
  // commands measure a mesh alike; without --eps the default (1e-6 of the model size).
  // An eps below the tessellator's smallest (nurbs::tess::kMinRelativeEps) still gets polylines of work
  // bounded by the model, not by the number.
  o.boundary_tolerance = a.eps_given ? 1e-3 * std::max(eps, nurbs::tess::kMinRelativeEps * size) : 0.0;
  o.threads = a.threads;
  const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
  const int threads = nurbs::thread_count(a.threads);
  const auto t_uv = std::chrono::steady_clock::now();
  const nurbs::TriangleMesh measured =
      a.no_parameters ? mesh : nurbs::tess::with_face_parameters(faces, mesh, std::max(64, a.samples), threads);
  const double uv_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_uv).count();
  const nurbs::tess::Deviation d = nurbs::tess::measure_deviation(faces, measured, o);
  const bool above = a.eps_given && !(d.max() <= eps);

  if (a.json) {
    nlohmann::json j = {{"model", a.model},
                        {"mesh", a.mesh},
                        {"model_size", size},
                        {"faces", faces.size()},
                        {"triangles", mesh.triangles.size()},
                        {"vertices", mesh.positions.size()},
                        {"max_deviation", d.max()},
                        {"surface_to_mesh", d.surface_to_mesh},
                        {"mesh_to_surface", d.mesh_to_surface},
                        {"worst_face", d.worst_face},
                        {"samples", a.samples},
                        {"surface_samples", d.surface_samples},
                        {"mesh_samples", d.mesh_samples},
                        {"seconds", d.seconds},
                        {"read_seconds", read_seconds},
                        {"parameter_seconds", uv_seconds}};
    if (a.eps_given) j["eps"] = eps, j["within_eps"] = !above;
    add_model_json(j, loaded.report, global);
    print_json(j);
  } else {
    fmt::print("model        {} ({} faces, size {:.6g})\n", a.model, faces.size(), size);
    fmt::print("mesh         {} ({} triangles, {} vertices)\n", a.mesh, mesh.triangles.size(), mesh.positions.size());
    fmt::print("deviation    {:.6g} (surface to mesh {:.6g}, mesh to surface {:.6g}; worst face {})\n", d.max(),
               d.surface_to_mesh, d.mesh_to_surface, d.worst_face);
    fmt::print("samples      {0} x {0} per face: {1} surface + {2} mesh samples\n", a.samples, d.surface_samples,
               d.mesh_samples);
    fmt::print("seconds      {:.3f} (reading {:.3f}, vertex (u, v) {:.3f})\n", d.seconds, read_seconds, uv_seconds);
    if (a.eps_given) fmt::print("eps          {:.6g}: {}\n", eps, above ? "ABOVE" : "within");
  }
  if (above) throw CommandFailed(fmt::format("measured deviation {:.6g} exceeds eps {:.6g}", d.max(), eps));
  require_certified(loaded.report, global);
}

}  // namespace cmd_deviation_impl

void add_deviation(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_deviation_impl;
  auto* cmd = app.add_subcommand(
      "deviation", "Measure how far a triangle mesh (.stl/.ply/.obj, from any program) lies from a model's faces");
  auto a = std::make_shared<DeviationArgs>();
  cmd->add_option("MODEL", a->model, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option("MESH", a->mesh, "Mesh file: .stl (binary or ASCII), .ply (ASCII or binary little endian), .obj")
      ->required();
  cmd->add_option_function<double>(
         "--eps", [a](double v) { a->eps = v, a->eps_given = true; },
         "Exit 1 when the measured deviation exceeds this (model units unless --relative)")
      ->check(positive_number("a positive distance"));
  cmd->add_flag("--relative", a->relative, "--eps is a fraction of the model size");
  cmd->add_option("--samples", a->samples, "A N x N (u, v) grid of samples per face")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  cmd->add_option("--threads", a->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  cmd->add_flag("--no-parameters", a->no_parameters,
                "Measure the mesh as it is, without first finding each vertex's face and (u, v) by projection");
  cmd->add_flag("--json", a->json, "Print one JSON object instead of text");
  cmd->callback([&global, a] { run(global, *a); });
}

}  // namespace cli
