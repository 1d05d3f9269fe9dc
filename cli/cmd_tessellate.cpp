// `nurbsgl tessellate MODEL --eps E [--relative] ...`: trimmed NURBS faces to a triangle mesh with a
// guaranteed (or approximate) error, after Balázs, Guthe and Klein (nurbs/tessellation/). No GPU.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/paper_preset.h"
#include "cli/validators.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/tessellation/mesh_topology.h"
#include "nurbs/tessellation/tessellate.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_tessellate_impl {

struct TessArgs {
  std::string path, output;
  double eps = 1e-3;
  bool relative = false, eps_given = false;
  std::string mode = "guaranteed", method = "kdtree", split = "midpoint", cell_bound = "filip",
              evaluation = "coherent";
  bool no_simplify = false, check = false, json = false, watertight = false, paper_rectangles = false;
  bool keep_polylines = false;
  int check_samples = 48, threads = 0;
  long long max_cells = nurbs::tess::TessellateOptions{}.max_cells;
  double loop_share = 0.45;
  std::vector<int> faces;  ///< --face; empty = all
  PaperPreset preset;      ///< --paper
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

void run(const GlobalOptions& global, const TessArgs& a) {
  const LoadedModel loaded = load_model(a.path, "tessellate");
  const nurbs::Model& model = loaded.model;
  const double size = checked_model_size(model, a.path);
  // Without --eps: 1e-3 of the model size, the reference setting of the experiments.
  const double eps = a.eps_given ? (a.relative ? a.eps * size : a.eps) : 1e-3 * size;
  if (!(eps > 0) || !std::isfinite(eps)) throw BadInput(fmt::format("--eps: {} is not a positive tolerance", eps));
  if (const double least = nurbs::tess::kMinRelativeEps * size; !(eps >= least * (1 - 1e-12)))
    throw BadInput(fmt::format("--eps {:g}: below {:.6g}, the smallest usable ({:g} of the model size {:g}; the "
                               "triangle count grows as 1/eps)",
                               a.eps, least, nurbs::tess::kMinRelativeEps, size));
  std::string out_error;
  if (!a.output.empty()) try {
      (void)nurbs::io::mesh_format_of(a.output);
    } catch (const std::invalid_argument& e) {
      throw BadInput(fmt::format("-o: {}", e.what()));
    }
  check_output(a.output, "-o");
  std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
  std::vector<char> in_solid;  // per face: its body is a closed solid (empty with --face)
  for (const nurbs::Body& b : model.bodies) in_solid.insert(in_solid.end(), b.faces.size(), b.closed ? 1 : 0);
  if (!a.faces.empty()) {
    in_solid.clear();
    std::vector<nurbs::TrimmedSurface> chosen;
    for (int index : a.faces) {
      if (index < 0 || index >= int(faces.size()))
        throw BadInput(fmt::format("--face {}: the model has faces 0..{}", index, int(faces.size()) - 1));
      chosen.push_back(faces[size_t(index)]);
    }
    faces = std::move(chosen);
  }
  nurbs::tess::TessellateOptions o;
  o.eps = eps;
  o.mode = a.mode == "approximate" ? nurbs::tess::TessMode::Approximate : nurbs::tess::TessMode::Guaranteed;
  o.subdivision = a.method == "quadtree" ? nurbs::tess::Subdivision::Quadtree : nurbs::tess::Subdivision::KdTree;
  o.cell_bound = a.cell_bound == "net" ? nurbs::tess::CellBound::ControlNet : nurbs::tess::CellBound::Filip;
  o.split = a.split == "arbitrary" ? nurbs::tess::CurveSplit::Arbitrary : nurbs::tess::CurveSplit::Midpoint;
  o.simplify = !a.no_simplify;
  o.thin_polylines = !a.keep_polylines;
  o.coherent_evaluation = a.evaluation == "coherent";
  o.loop_share = a.loop_share;
  o.threads = a.threads;
  o.watertight = a.watertight;
  o.rectangle_faces = !a.paper_rectangles;
  o.weld = std::min(model.resolution, 0.1 * eps);
  o.max_cells = a.max_cells;

  nurbs::tess::TessellateResult r;
  try {
    Progress progress("tessellate", "faces");  // on stderr once the work has taken a second
    r = nurbs::tess::tessellate(faces, o, [&](int done, int total) { progress.update(done, total); });
  } catch (const nurbs::tess::WorkLimitError& e) {
    const double least = a.eps_given && a.relative ? e.least_eps / size : e.least_eps;
    throw BadInput(fmt::format("--eps {:g}: about {:.3g} surface cells, above --max-cells {} (estimated before the "
                               "work from the cells at 64, 256 and 1024 times eps); --eps {:.2g}{} or more fits",
                               a.eps_given ? a.eps : eps, double(e.estimated_cells), a.max_cells, least,
                               a.eps_given && a.relative ? " --relative" : ""));
  }
  // Watertight: the mesh is written with its shared boundary vertices made one (welded as the
  // tessellator welds them), and its edges are counted as written. Otherwise each face keeps its
  // vertices, and the count welds as the tessellator does (the file's resolution, at least 1e-9 of
  // the largest face's control box; with 1e-9 of the sampled model size, smaller, the vase shell
  // showed 4 seam cracks of 2e-7).
  // Guaranteed mode, always, on each face's own vertices (before a weld gives a seam vertex one
  // side's (u, v): a triangle beside the seam would then span the domain): triangles whose centroid
  // or edge midpoints lie off their face's surface by more than eps (triangles_off_surface: one
  // evaluation per sample), or outside its trim farther than eps from its boundary
  // (triangles_outside_trim, cheap); such a face fails the command, named.
  std::vector<nurbs::tess::OutsideTrim> off_surface, outside;
  double surface_check_seconds = 0.0, trim_check_seconds = 0.0;
  if (o.mode == nurbs::tess::TessMode::Guaranteed) {
    auto t0 = std::chrono::steady_clock::now();
    off_surface = nurbs::tess::triangles_off_surface(faces, r.mesh, eps);
    surface_check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t0 = std::chrono::steady_clock::now();
    outside = nurbs::tess::triangles_outside_trim(faces, r.mesh, eps);
    trim_check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  long long collapsed = 0;
  if (a.watertight) {
    r.mesh = nurbs::tess::weld_mesh(r.mesh, r.weld_tolerance, &collapsed);
    r.stats.triangles = (long long)r.mesh.triangles.size(), r.stats.vertices = (long long)r.mesh.positions.size();
  }
  if (!a.output.empty()) nurbs::io::write_mesh_file(a.output, r.mesh);
  const nurbs::tess::EdgeCounts edges = a.watertight ? nurbs::tess::count_edges_as_indexed(r.mesh)
                                                     : nurbs::tess::count_edges(r.mesh, r.weld_tolerance);

  // Watertight: open edges on the faces of a closed solid are cracks the mesh should not have
  // (where the file's faces do not meet within the loops' tolerance); they fail the command.
  long long solid_open = 0;
  std::vector<std::string> solid_cracks;
  if (a.watertight)
    for (const auto& [f, n] : edges.open_by_face)
      if (f >= 0 && size_t(f) < in_solid.size() && in_solid[size_t(f)]) {
        solid_open += n;
        solid_cracks.push_back(fmt::format("face {} (id {}): {}", f, faces[size_t(f)].face_id, n));
      }

  nurbs::tess::Deviation dev;
  if (a.check) {
    nurbs::tess::DeviationOptions d;
    d.samples = a.check_samples;
    d.boundary_tolerance = 1e-3 * eps;
    d.threads = a.threads;
    dev = nurbs::tess::measure_deviation(faces, r.mesh, d);
  }
  const bool guaranteed = o.mode == nurbs::tess::TessMode::Guaranteed;
  const bool check_failed = a.check && guaranteed && dev.max() > eps;
  // Faces whose trim the reader could not make valid: their mesh is not certified (the material
  // region is not known); faces whose file edges lie off the surface: the mesh is within eps of the
  // face as read, and within eps plus the gap of the file's edges (nurbs/model_report.h).
  std::vector<std::string> uncertified;
  double gap = 0.0;
  for (size_t f = 0; f < faces.size(); ++f) {
    gap = std::max(gap, faces[f].edge_gap);
    if (!faces[f].trim_problem.empty())
      uncertified.push_back(fmt::format("face {} (id {}): {}", f, faces[f].face_id, faces[f].trim_problem));
  }
  std::vector<std::string> over_eps, off_eps;
  for (size_t f = 0; f < outside.size(); ++f)
    if (outside[f].triangles > 0)
      over_eps.push_back(fmt::format("face {} (id {}): {} triangles, {:.6g} outside", f, faces[f].face_id,
                                     outside[f].triangles, outside[f].distance));
  for (size_t f = 0; f < off_surface.size(); ++f)
    if (off_surface[f].triangles > 0)
      off_eps.push_back(fmt::format("face {} (id {}): {} triangles, {:.6g} off the surface", f, faces[f].face_id,
                                    off_surface[f].triangles, off_surface[f].distance));

  if (a.json) {
    // Watertight: the faces that still have open edges (where the file's faces do not meet within the
    // loops' tolerance), with their counts; empty without --watertight, where every face's border is open.
    nlohmann::json open_edge_faces = nlohmann::json::array();
    if (a.watertight)
      for (const auto& [f, n] : edges.open_by_face)
        open_edge_faces.push_back({{"face", f}, {"face_id", f >= 0 ? faces[size_t(f)].face_id : -1}, {"open_edges", n}});
    nlohmann::json j = {{"model", a.path},
                        {"eps", eps},
                        {"eps_relative", eps / size},
                        {"mode", a.mode},
                        {"method", a.method},
                        {"cell_bound", a.cell_bound},
                        {"loop_share", a.loop_share},
                        {"faces", r.stats.faces},
                        {"failed_faces", r.stats.failed_faces},
                        {"triangles", r.stats.triangles},
                        {"vertices", r.stats.vertices},
                        {"trim_edges", r.stats.trim_edges},
                        {"open_edges", edges.open},
                        {"edges", edges.edges},
                        {"cells", r.stats.cells},
                        {"degenerate_triangles", r.stats.degenerate_triangles},
                        {"collapsed_triangles", r.stats.collapsed_triangles},
                        {"watertight",
                         {{"enabled", a.watertight},
                          {"open_edge_faces", open_edge_faces},
                          {"solid_open_edges", solid_open},
                          {"collapsed_triangles", collapsed},
                          {"shared_vertices", r.stats.shared_vertices},
                          {"t_junction_splits", r.stats.t_junction_splits}}},
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
    j["bound"] = eps + gap;  // of the mesh from the file's faces: eps, plus the largest edge gap
    j["uncertified_faces"] = uncertified;
    add_model_json(j, loaded.report, global);
    // The switches of --paper as used: the cell bound is guaranteed mode's; watertight meshes loop
    // every boundary, as --paper-rectangles does.
    j["preset"] = a.preset.json({{"cell-bound", guaranteed ? nlohmann::json(a.cell_bound) : nlohmann::json()},
                                 {"paper-rectangles", a.paper_rectangles || a.watertight}});
    nlohmann::json failures = nlohmann::json::array();
    for (const auto& f : r.failures) failures.push_back({{"face", f.face}, {"reason", f.reason}});
    j["failures"] = failures;
    if (guaranteed) {
      nlohmann::json list = nlohmann::json::array();
      for (size_t f = 0; f < outside.size(); ++f)
        if (outside[f].triangles > 0)
          list.push_back({{"face", f},
                          {"face_id", faces[f].face_id},
                          {"triangles", outside[f].triangles},
                          {"distance", outside[f].distance}});
      j["trim_check"] = {{"faces_over_eps", list}, {"seconds", trim_check_seconds}};
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
      j["surface_check"] = {{"faces_over_eps", off}, {"max_distance", worst}, {"seconds", surface_check_seconds}};
    }
    if (a.check) {
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
    print_json(j);
  } else {
    a.preset.print_text();
    fmt::print("model        {} ({} faces, size {:.6g})\n", a.path, r.stats.faces, size);
    fmt::print("eps          {:.6g} ({:.3g} of the size), {} error, {}\n", eps, eps / size, a.mode, a.method);
    fmt::print("triangles    {}  vertices {}  trim edges {}  open edges {}\n", r.stats.triangles, r.stats.vertices,
               r.stats.trim_edges, edges.open);
    if (a.watertight && edges.open > 0) {  // where the cracks are, by face
      std::string list;
      for (const auto& [f, n] : edges.open_by_face) list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", f, n);
      fmt::print("open edges   on {} faces: {}\n", edges.open_by_face.size(), list);
    }
    fmt::print(
        "seconds      {:.3f} (CPU: conversion {:.3f}, trim loops {:.3f}, surface {:.3f}, trimming {:.3f}, "
        "triangulation {:.3f}, evaluation {:.3f})\n",
        r.stats.seconds, r.stats.trim.seconds_conversion, r.stats.trim.seconds_approximation, r.stats.seconds_surface,
        r.stats.seconds_trimming, r.stats.seconds_triangulation, r.stats.seconds_evaluation);
    if (a.check)
      fmt::print("deviation    {:.6g} (surface to mesh {:.6g}, mesh to surface {:.6g}; {} + {} samples, {:.2f} s){}\n",
                 dev.max(), dev.surface_to_mesh, dev.mesh_to_surface, dev.surface_samples, dev.mesh_samples,
                 dev.seconds,
                 dev.max() <= eps ? ""
                 : guaranteed     ? "  ABOVE eps"
                                  : "  (above eps: approximate mode)");
    for (const std::string& f : over_eps) fmt::print("outside trim {}  ABOVE eps\n", f);
    for (const std::string& f : off_eps) fmt::print("off surface  {}  ABOVE eps\n", f);
    if (!a.output.empty()) fmt::print("written      {}\n", a.output);
    for (const auto& f : r.failures) fmt::print("failed       face {}: {}\n", f.face, f.reason);
    for (const std::string& f : uncertified) fmt::print("uncertified  {}\n", f);
    if (gap > 0.0)
      fmt::print("edge gap     the file's edges lie up to {:.6g} off their faces: the mesh is within {:.6g} of them\n",
                 gap, eps + gap);
  }
  for (const auto& f : r.failures)
    fmt::print(stderr, "nurbsgl: tessellate: {}: face {}: {}\n", a.path, f.face, f.reason);
  if (!r.failures.empty())
    throw CommandFailed(fmt::format("{} of {} faces could not be tessellated", r.failures.size(), r.stats.faces));
  if (!over_eps.empty())
    throw CommandFailed(fmt::format("guaranteed mode: {} face(s) with triangles outside their trim by more than eps "
                                    "{:.6g}: {}",
                                    over_eps.size(), eps, fmt::join(over_eps, "; ")));
  if (!off_eps.empty())
    throw CommandFailed(fmt::format("guaranteed mode: {} face(s) with triangles off their surface by more than eps "
                                    "{:.6g}: {}",
                                    off_eps.size(), eps, fmt::join(off_eps, "; ")));
  if (check_failed) throw CommandFailed(fmt::format("measured deviation {:.6g} exceeds eps {:.6g}", dev.max(), eps));
  if (solid_open > 0)
    throw CommandFailed(fmt::format("--watertight: {} open edges on faces of closed solids, where the file's faces do "
                                    "not meet within the trim loops' tolerance: {}",
                                    solid_open, fmt::join(solid_cracks, "; ")));
  require_certified(loaded.report, global);
  if (!uncertified.empty() && guaranteed)
    throw CommandFailed(fmt::format("guaranteed mode: {} face(s) with a trim the reader could not make valid, their "
                                    "mesh not certified: {}",
                                    uncertified.size(), fmt::join(uncertified, "; ")));
}

}  // namespace cmd_tessellate_impl

void add_tessellate(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_tessellate_impl;
  auto* cmd = app.add_subcommand(
      "tessellate", "Triangulate a model's trimmed faces within a geometric error (Balazs, Guthe, Klein 2004)");
  auto a = std::make_shared<TessArgs>();
  cmd->add_option("MODEL", a->path, "Model file (.igs/.iges/.bpt)")->required();
  cmd->add_option_function<double>(
         "--eps", [a](double v) { a->eps = v, a->eps_given = true; },
         "Maximum distance between the faces and the mesh, absolute (model units) unless --relative; default "
         "1e-3 of the model size")
      ->check(positive_number("a positive distance"));
  cmd->add_flag("--relative", a->relative, "--eps is a fraction of the model size");
  cmd->add_option("--mode", a->mode,
                  "guaranteed: the error is proven (trims and cells each within eps/2); approximate: the paper's "
                  "surface-point estimate, fewer triangles, no guarantee")
      ->check(CLI::IsMember({"guaranteed", "approximate"}))
      ->capture_default_str();
  auto* method =
      cmd->add_option("--method", a->method, "kdtree: the paper's subdivision; quadtree: [Kah02], for comparison")
          ->check(CLI::IsMember({"kdtree", "quadtree"}))
          ->capture_default_str();
  auto* cell_bound =
      cmd->add_option("--cell-bound", a->cell_bound,
                      "Guaranteed mode, the cells' proven bound: net = the paper's control-net test (2 eps_bilin + "
                      "twist/4); filip = also Filip's second-derivative bound of each cell, the smaller kept (fewer "
                      "triangles, still proven)")
          ->check(CLI::IsMember({"filip", "net"}))
          ->capture_default_str();
  cmd->add_option("--loop-share", a->loop_share,
                  "Guaranteed mode: the share of eps for the trim loops; the cells get the rest")
      ->check(finite_range(0.05, 0.95))
      ->capture_default_str();
  auto* split =
      cmd->add_option("--split", a->split, "Trim curve subdivision: midpoint or arbitrary (at the worst control point)")
          ->check(CLI::IsMember({"midpoint", "arbitrary"}))
          ->capture_default_str();
  auto* watertight = cmd->add_flag(
      "--watertight", a->watertight,
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
  // --paper: the kd-tree (5.2) with the control-net bound (5.2, the conservative error), trim curves
  // split at their midpoint (5.1, Table 2) and their loops simplified (5.1), every loop approximated
  // by polylines (5.1), each face on its own (3), vertices evaluated coherently (8). --mode stays
  // free: the paper gives both errors.
  auto& preset = a->preset;
  preset.add_flag(cmd, "Balazs, Guthe, Klein");
  preset.govern(method, a->method, std::string("kdtree"), "§5.2");
  preset.govern(cell_bound, a->cell_bound, std::string("net"), "§5.2");
  preset.govern(split, a->split, std::string("midpoint"), "§5.1");
  preset.govern(no_simplify, a->no_simplify, false, "§5.1");
  preset.govern(keep_polylines, a->keep_polylines, true, "§4");
  preset.govern(evaluation, a->evaluation, std::string("coherent"), "§8");
  preset.govern(paper_rectangles, a->paper_rectangles, true, "§5.1");
  preset.govern(watertight, a->watertight, false, "§3");
  cmd->add_option("-o,--output", a->output, "Write the mesh: .obj, .ply or .stl");
  cmd->add_flag("--check", a->check,
                "Measure the deviation (face samples to mesh, mesh samples to faces); exit 1 when above eps in "
                "guaranteed mode");
  auto* check_samples = cmd->add_option("--check-samples", a->check_samples, "For --check: a N x N (u, v) grid per face")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  cmd->add_option("--face", a->faces,
                  "Face index (repeatable); default: all faces. Face numbers in the output "
                  "count the chosen faces");
  cmd->add_option("--threads", a->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  cmd->add_option("--max-cells", a->max_cells,
                  "The most surface cells (about two triangles each) the model may need, estimated before the "
                  "work; above it exit 2 with the eps that fits (0: no limit)")
      ->check(CLI::Range(0LL, 1LL << 40))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object instead of text");
  cmd->callback([&global, a, check_samples] {
    a->preset.apply();
    // Options that would do nothing are refused.
    if (a->relative && !a->eps_given) throw BadInput("--relative: needs --eps");
    if (check_samples->count() > 0 && !a->check) throw BadInput("--check-samples: needs --check");
    run(global, *a);
  });
}

}  // namespace cli
