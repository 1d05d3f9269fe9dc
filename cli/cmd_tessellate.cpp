// `nurbsgl tessellate MODEL --eps E [--relative] ...`: trimmed NURBS faces to a triangle mesh with a
// guaranteed (or approximate) error, after Balázs, Guthe and Klein, through the library's front door
// nurbs::tess::mesh_model (nurbs/tessellation/model_mesh.h: the request's checks, the guaranteed
// mode's own checks, the failing faces). No GPU.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/paper_switch.h"
#include "nurbs/tessellation/model_mesh.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_tessellate_impl {

struct TessArgs {
  std::string path, output;
  nurbs::tess::ModelMeshOptions mesh;
  bool eps_given = false;
  std::string mode = "guaranteed", method = "kdtree", split = "midpoint", cell_bound = "filip",
              evaluation = "coherent";
  bool no_simplify = false, json = false, paper_rectangles = false;
  bool keep_polylines = false;
  PaperPreset preset;  ///< --paper
};

nlohmann::json stats_json(const nurbs::tess::TessellateStats& s) {
  return {{"conversion", s.trim.seconds_conversion},
          {"trim_approximation", s.trim.seconds_approximation},
          {"surface_approximation", s.seconds_surface},
          {"trimming", s.seconds_trimming},
          {"triangulation", s.seconds_triangulation},
          {"evaluation", s.seconds_evaluation},
          {"total", s.seconds}};
}

void print_text(const TessArgs& a, const nurbs::tess::ModelMesh& m) {
  const nurbs::tess::TessellateResult& r = m.result;
  a.preset.print_text();
  fmt::print("model        {} ({} faces, size {:.6g})\n", a.path, r.stats.faces, m.size);
  fmt::print("eps          {:.6g} ({:.3g} of the size), {} error, {}\n", m.eps, m.eps / m.size, a.mode, a.method);
  fmt::print("triangles    {}  vertices {}  trim edges {}  open edges {}\n", r.stats.triangles, r.stats.vertices,
             r.stats.trim_edges, m.edges.open);
  if (a.mesh.tess.watertight && m.edges.open > 0) {  // where the cracks are, by face
    std::string list;
    for (const auto& [f, n] : m.edges.open_by_face) list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", f, n);
    fmt::print("open edges   on {} faces: {}\n", m.edges.open_by_face.size(), list);
  }
  fmt::print(
      "seconds      {:.3f} (CPU: conversion {:.3f}, trim loops {:.3f}, surface {:.3f}, trimming {:.3f}, "
      "triangulation {:.3f}, evaluation {:.3f})\n",
      r.stats.seconds, r.stats.trim.seconds_conversion, r.stats.trim.seconds_approximation, r.stats.seconds_surface,
      r.stats.seconds_trimming, r.stats.seconds_triangulation, r.stats.seconds_evaluation);
  if (const auto& dev = m.deviation)
    fmt::print("deviation    {:.6g} (surface to mesh {:.6g}, mesh to surface {:.6g}; {} + {} samples, {:.2f} s){}\n",
               dev->max(), dev->surface_to_mesh, dev->mesh_to_surface, dev->surface_samples, dev->mesh_samples,
               dev->seconds,
               dev->max() <= m.eps       ? ""
               : !m.guaranteed           ? "  (above eps: approximate mode)"
               : dev->max() <= m.bound() ? "  (above eps, within the file's edge gaps: the bound below)"
                                         : "  ABOVE eps");
  for (const std::string& f : m.over_eps) fmt::print("outside trim {}  ABOVE eps\n", f);
  for (const std::string& f : m.off_eps) fmt::print("off surface  {}  ABOVE eps\n", f);
  if (!a.output.empty()) fmt::print("written      {}\n", a.output);
  for (const auto& f : r.failures) fmt::print("failed       face {}: {}\n", f.face, f.reason);
  for (const std::string& f : m.uncertified) fmt::print("uncertified  {}\n", f);
  if (m.gap > 0.0)
    fmt::print("edge gap     the file's edges lie up to {:.6g} off their faces: the mesh is within {:.6g} of them\n",
               m.gap, m.bound());
  if (r.stats.sliver_holes > 0)
    fmt::print("sliver holes {} closed, up to {:.3g} wide: the mesh is within {:.6g} of the faces\n",
               r.stats.sliver_holes, r.fill_width, m.bound());
}

/// The JSON object of a mesh (the fields are a contract: README.md).
nlohmann::json mesh_json(const TessArgs& a, const nurbs::tess::ModelMesh& m, const nurbs::tess::ModelMeshOptions& options,
                         const LoadedModel& loaded, const GlobalOptions& global) {
  const nurbs::tess::TessellateResult& r = m.result;
  const auto& faces = m.faces;
  const double eps = m.eps, size = m.size;
  const bool watertight = options.tess.watertight;
  // Watertight: the faces that still have open edges (where the file's faces do not meet within the
  // loops' tolerance), with their counts; empty without --watertight, where every face's border is open.
  nlohmann::json open_edge_faces = nlohmann::json::array();
  if (watertight)
    for (const auto& [f, n] : m.edges.open_by_face)
      open_edge_faces.push_back({{"face", f}, {"face_id", f >= 0 ? faces[size_t(f)].face_id : -1}, {"open_edges", n}});
  nlohmann::json j = {{"model", a.path},
                      {"eps", eps},
                      {"eps_relative", eps / size},
                      {"mode", a.mode},
                      {"method", a.method},
                      {"cell_bound", a.cell_bound},
                      {"loop_share", options.tess.loop_share},
                      {"faces", r.stats.faces},
                      {"failed_faces", r.stats.failed_faces},
                      {"triangles", r.stats.triangles},
                      {"vertices", r.stats.vertices},
                      {"trim_edges", r.stats.trim_edges},
                      {"open_edges", m.edges.open},
                      {"edges", m.edges.edges},
                      {"cells", r.stats.cells},
                      {"degenerate_triangles", r.stats.degenerate_triangles},
                      {"collapsed_triangles", r.stats.collapsed_triangles},
                      {"flipped_slivers", r.stats.flipped_slivers},
                      {"watertight",
                       {{"enabled", watertight},
                        {"open_edge_faces", open_edge_faces},
                        {"solid_open_edges", m.solid_open},
                        {"collapsed_triangles", m.collapsed},
                        {"edge_shared", r.stats.edge_shared},
                        {"shared_vertices", r.stats.shared_vertices},
                        {"t_junction_splits", r.stats.t_junction_splits},
                        {"sliver_holes", r.stats.sliver_holes},
                        {"fill_width", r.fill_width}}},
                      {"trim",
                       {{"curve_pieces", r.stats.trim.curve_pieces},
                        {"edges_before_simplification", r.stats.trim.edges_before},
                        {"edges_after_simplification", r.stats.trim.edges_after},
                        {"crossings_fixed", r.stats.trim.crossings_fixed},
                        {"crossing_refined_faces", r.stats.trim.crossing_refined_faces},
                        {"polyline_points_thinned", r.stats.trim.thinned_points},
                        {"rectangle_faces", r.stats.trim.rectangle_faces},
                        {"lifted_degree_max", r.stats.trim.lifted_degree_max},
                        {"lift_error_max", r.stats.trim.lift_error_max}}},
                      {"seconds", stats_json(r.stats)}};
  j["bound"] = m.bound();  // of the mesh from the file's faces: eps, plus the largest edge gap
  j["uncertified_faces"] = m.uncertified;
  add_model_json(j, loaded.report, global);
  // The switches of --paper as used: the cell bound is guaranteed mode's; watertight meshes loop
  // every boundary, as --paper-rectangles does.
  j["preset"] = a.preset.json({{"cell-bound", m.guaranteed ? nlohmann::json(a.cell_bound) : nlohmann::json()},
                               {"paper-rectangles", a.paper_rectangles || watertight}});
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : r.failures) failures.push_back({{"face", f.face}, {"reason", f.reason}});
  j["failures"] = failures;
  if (m.guaranteed) {
    const auto& outside = m.outside;
    const auto& off_surface = m.off_surface;
    nlohmann::json list = nlohmann::json::array();
    for (size_t f = 0; f < outside.size(); ++f)
      if (outside[f].triangles > 0)
        list.push_back({{"face", f},
                        {"face_id", faces[f].face_id},
                        {"triangles", outside[f].triangles},
                        {"distance", outside[f].distance}});
    j["trim_check"] = {{"faces_over_eps", list}, {"seconds", m.trim_check_seconds}};
    nlohmann::json off = nlohmann::json::array();
    double worst = 0.0;
    for (size_t f = 0; f < off_surface.size(); ++f) {
      worst = std::max(worst, off_surface[f].distance);
      if (off_surface[f].triangles > 0)
        off.push_back({{"face", f},
                       {"face_id", faces[f].face_id},
                       {"triangles", off_surface[f].triangles},
                       {"distance", off_surface[f].distance}});
    }
    j["surface_check"] = {{"faces_over_eps", off}, {"max_distance", worst}, {"seconds", m.surface_check_seconds}};
  }
  if (m.deviation) {
    const nurbs::tess::Deviation& dev = *m.deviation;
    // Per face: its triangles and measured deviation.
    std::vector<long long> triangles(faces.size(), 0);
    for (const int f : r.mesh.triangle_face)
      if (f >= 0 && size_t(f) < faces.size()) ++triangles[size_t(f)];
    nlohmann::json per_face = nlohmann::json::array();
    for (size_t f = 0; f < faces.size(); ++f) {
      const double s2m = f < dev.face_surface_to_mesh.size() ? dev.face_surface_to_mesh[f] : 0.0;
      const double m2s = f < dev.face_mesh_to_surface.size() ? dev.face_mesh_to_surface[f] : 0.0;
      per_face.push_back({{"face", f},
                          {"face_id", faces[f].face_id},
                          {"triangles", triangles[f]},
                          {"surface_to_mesh", s2m},
                          {"mesh_to_surface", m2s},
                          {"max_deviation", std::max(s2m, m2s)}});
    }
    j["check"] = {{"faces", per_face},
                  {"max_deviation", dev.max()},
                  {"surface_to_mesh", dev.surface_to_mesh},
                  {"mesh_to_surface", dev.mesh_to_surface},
                  {"worst_face", dev.worst_face},
                  {"surface_samples", dev.surface_samples},
                  {"mesh_samples", dev.mesh_samples},
                  {"seconds", dev.seconds},
                  {"within_eps", dev.max() <= eps}};
  }
  if (!a.output.empty()) j["output"] = a.output;
  return j;
}

/// The settings of the command line as the front door takes them.
nurbs::tess::ModelMeshOptions mesh_options(const TessArgs& a, const GlobalOptions& global) {
  nurbs::tess::ModelMeshOptions m = a.mesh;
  if (!a.eps_given) m.eps = 1e-3, m.relative = true;  // the reference setting of the experiments
  nurbs::tess::TessellateOptions& o = m.tess;
  o.mode = a.mode == "approximate" ? nurbs::tess::TessMode::Approximate : nurbs::tess::TessMode::Guaranteed;
  o.subdivision = a.method == "quadtree" ? nurbs::tess::Subdivision::Quadtree
                  : a.method == "grid"   ? nurbs::tess::Subdivision::Grid
                                         : nurbs::tess::Subdivision::KdTree;
  o.cell_bound = a.cell_bound == "net" ? nurbs::tess::CellBound::ControlNet : nurbs::tess::CellBound::Filip;
  o.split = a.split == "arbitrary" ? nurbs::tess::CurveSplit::Arbitrary : nurbs::tess::CurveSplit::Midpoint;
  o.simplify = !a.no_simplify;
  o.thin_polylines = !a.keep_polylines;
  o.coherent_evaluation = a.evaluation == "coherent";
  o.rectangle_faces = !a.paper_rectangles;
  m.accept_partial = global.accept_partial;
  return m;
}

void run(const GlobalOptions& global, const TessArgs& a) {
  const LoadedModel loaded = load_model(a.path, "tessellate");
  if (!a.output.empty()) try {
      (void)nurbs::io::mesh_format_of(a.output);
    } catch (const std::invalid_argument& e) {
      throw BadInput(fmt::format("-o: {}", e.what()));
    }
  check_output(a.output, "-o");
  nurbs::tess::ModelMeshOptions options = mesh_options(a, global);
  Progress progress("tessellate", "faces");  // on stderr once the work has taken a second
  options.progress = [&](int done, int total) { progress.update(done, total); };
  const nurbs::tess::ModelMesh m = nurbs::tess::mesh_model(loaded, options);
  if (!a.output.empty()) nurbs::io::write_mesh_file(a.output, m.result.mesh);
  if (a.json)
    print_json(mesh_json(a, m, options, loaded, global));
  else
    print_text(a, m);
  for (const auto& f : m.result.failures)
    fmt::print(stderr, "nurbsgl: tessellate: {}: face {}: {}\n", a.path, f.face, f.reason);
  if (const std::string why = m.failure(); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_tessellate_impl

void add_tessellate(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_tessellate_impl;
  auto* cmd = app.add_subcommand(
      "tessellate", "Triangulate a model's trimmed faces within a geometric error (Balazs, Guthe, Klein 2004)");
  auto a = std::make_shared<TessArgs>();
  a->mesh.relative = false;  // --eps in model units unless --relative
  cmd->add_option("MODEL", a->path, "Model file (IGES .igs/.iges, STEP .stp/.step, .bpt; read by its content where that is STEP or IGES)")->required();
  cmd->add_option_function<double>(
         "--eps", [a](double v) { a->mesh.eps = v, a->eps_given = true; },
         "Maximum distance between the faces and the mesh, absolute (model units) unless --relative; default "
         "1e-3 of the model size")
      ->check(positive_number("a positive distance"));
  cmd->add_flag("--relative", a->mesh.relative, "--eps is a fraction of the model size");
  cmd->add_option("--mode", a->mode,
                  "guaranteed: the error is proven (trims and cells each within eps/2); approximate: the paper's "
                  "surface-point estimate, fewer triangles, no guarantee")
      ->check(CLI::IsMember({"guaranteed", "approximate"}))
      ->capture_default_str();
  auto* method =
      cmd->add_option("--method", a->method,
                      "kdtree: the paper's subdivision; quadtree: [Kah02], for comparison; grid: each face's "
                      "knot-aligned grid whose cells' Filip bound meets eps (one pass, faster at small eps, more "
                      "triangles, the same guarantee)")
          ->check(CLI::IsMember({"kdtree", "quadtree", "grid"}))
          ->capture_default_str();
  auto* cell_bound =
      cmd->add_option("--cell-bound", a->cell_bound,
                      "Guaranteed mode, the cells' proven bound: net = the paper's control-net test (2 eps_bilin + "
                      "twist/4); filip = also Filip's second-derivative bound of each cell, the smaller kept (fewer "
                      "triangles, still proven)")
          ->check(CLI::IsMember({"filip", "net"}))
          ->capture_default_str();
  cmd->add_option("--loop-share", a->mesh.tess.loop_share,
                  "Guaranteed mode: the share of eps for the trim loops; the cells get the rest")
      ->check(finite_range(0.05, 0.95))
      ->capture_default_str();
  auto* split =
      cmd->add_option("--split", a->split, "Trim curve subdivision: midpoint or arbitrary (at the worst control point)")
          ->check(CLI::IsMember({"midpoint", "arbitrary"}))
          ->capture_default_str();
  auto* watertight = cmd->add_flag(
      "--watertight", a->mesh.tess.watertight,
      "Faces sharing an edge get the same boundary vertices (no cracks; a closed model has no open edges)");
  auto* paper_rectangles =
      cmd->add_flag("--paper-rectangles", a->paper_rectangles,
                    "Approximate the boundary of a face bounded by its parameter rectangle by loop polylines, as the "
                    "paper does any loop (default: the cells' edges are that boundary, with no loop error)");
  auto* no_simplify = cmd->add_flag("--no-simplify", a->no_simplify, "Skip the trim loop simplification (§5)");
  auto* keep_polylines =
      cmd->add_flag("--keep-polylines", a->keep_polylines,
                    "Lift every segment of a polyline trim curve to 3D, as the paper does (default: dense degree-1 "
                    "trim curves are first thinned in (u, v) within a small share of the loop budget; same bound, "
                    "much less work on B-reps whose pcurves are sampled polylines)");
  auto* evaluation =
      cmd->add_option("--evaluation", a->evaluation,
                      "Mesh vertices on the surface (§8): coherent = basis functions and inner sums reused between "
                      "neighbouring vertices; direct = every vertex evaluated on its own (the same mesh; Table 3's two "
                      "time columns)")
          ->check(CLI::IsMember({"coherent", "direct"}))
          ->capture_default_str();
  // --paper: nurbs::tess::ModelMeshOptions::paper. --mode stays free: the paper gives both errors.
  const nurbs::tess::ModelMeshOptions paper = a->mesh.paper();
  const auto section = [](const char* option) {
    return nurbs::paper_section(nurbs::tess::ModelMeshOptions::paper_switches(), option);
  };
  using namespace nurbs::tess;
  auto& preset = a->preset;
  preset.add_flag(cmd, "Balazs, Guthe, Klein");
  preset.govern(method, a->method, std::string(paper.tess.subdivision == Subdivision::KdTree ? "kdtree" : "quadtree"),
                section("method"));
  preset.govern(cell_bound, a->cell_bound, std::string(paper.tess.cell_bound == CellBound::ControlNet ? "net" : "filip"),
                section("cell-bound"));
  preset.govern(split, a->split, std::string(paper.tess.split == CurveSplit::Midpoint ? "midpoint" : "arbitrary"),
                section("split"));
  preset.govern(no_simplify, a->no_simplify, !paper.tess.simplify, section("no-simplify"));
  preset.govern(keep_polylines, a->keep_polylines, !paper.tess.thin_polylines, section("keep-polylines"));
  preset.govern(evaluation, a->evaluation, std::string(paper.tess.coherent_evaluation ? "coherent" : "direct"),
                section("evaluation"));
  preset.govern(paper_rectangles, a->paper_rectangles, !paper.tess.rectangle_faces, section("paper-rectangles"));
  preset.govern(watertight, a->mesh.tess.watertight, paper.tess.watertight, section("watertight"));
  cmd->add_option("-o,--output", a->output, "Write the mesh: .obj, .ply or .stl");
  cmd->add_flag("--check", a->mesh.check,
                "Measure the deviation (face samples to mesh, mesh samples to faces); exit 1 when above eps in "
                "guaranteed mode");
  auto* check_samples = cmd->add_option("--check-samples", a->mesh.check_samples, "For --check: a N x N (u, v) grid per face")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  cmd->add_option("--face", a->mesh.faces,
                  "Face index (repeatable); default: all faces. Face numbers in the output "
                  "count the chosen faces");
  cmd->add_option("--threads", a->mesh.tess.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  cmd->add_option("--max-cells", a->mesh.tess.max_cells,
                  "The most surface cells (about two triangles each) the model may need, estimated before the "
                  "work; above it exit 2 with the eps that fits (0: no limit)")
      ->check(CLI::Range(0LL, 1LL << 40))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object instead of text");
  cmd->callback([&global, a, check_samples] {
    a->preset.apply();
    // Options that would do nothing are refused.
    if (a->mesh.relative && !a->eps_given) throw BadInput("--relative: needs --eps");
    if (check_samples->count() > 0 && !a->mesh.check) throw BadInput("--check-samples: needs --check");
    run(global, *a);
  });
}

}  // namespace cli
