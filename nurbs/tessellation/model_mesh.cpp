#include "nurbs/tessellation/model_mesh.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/stopwatch.h"

namespace nurbs::tess {

ModelMeshOptions ModelMeshOptions::paper() const {
  ModelMeshOptions o = *this;
  o.tess.subdivision = Subdivision::KdTree;
  o.tess.cell_bound = CellBound::ControlNet;
  o.tess.split = CurveSplit::Midpoint;
  o.tess.simplify = true;
  o.tess.thin_polylines = false;
  o.tess.coherent_evaluation = true;
  o.tess.rectangle_faces = false;
  o.tess.watertight = false;
  return o;
}

std::vector<PaperSwitch> ModelMeshOptions::paper_switches() {
  return {{"method", "§5.2"},         {"cell-bound", "§5.2"}, {"split", "§5.1"},
          {"no-simplify", "§5.1"},    {"keep-polylines", "§4"}, {"evaluation", "§8"},
          {"paper-rectangles", "§5.1"}, {"watertight", "§3"}};
}

std::string ModelMesh::failure() const {
  if (!result.failures.empty())
    return fmt::format("{} of {} faces could not be tessellated", result.failures.size(), result.stats.faces);
  if (!over_eps.empty())
    return fmt::format("guaranteed mode: {} face(s) with triangles outside their trim by more than eps {:.6g}: {}",
                       over_eps.size(), eps, fmt::join(over_eps, "; "));
  if (!off_eps.empty())
    return fmt::format("guaranteed mode: {} face(s) with triangles off their surface by more than eps {:.6g}: {}",
                       off_eps.size(), eps, fmt::join(off_eps, "; "));
  // The faces' file edges lie off them by up to the gap: the mesh is certified within bound().
  if (deviation && guaranteed && deviation->max() > bound())
    return bound() > eps ? fmt::format("measured deviation {:.6g} exceeds eps {:.6g} plus the file's edge gaps, {:.6g}",
                                       deviation->max(), eps, bound())
                         : fmt::format("measured deviation {:.6g} exceeds eps {:.6g}", deviation->max(), eps);
  if (solid_open > 0)
    return fmt::format("--watertight: {} open edges on faces of closed solids, where the file's faces do not meet "
                       "within the trim loops' tolerance: {}",
                       solid_open, fmt::join(solid_cracks, "; "));
  if (!model_reason.empty()) return model_reason;
  if (!uncertified.empty() && guaranteed)
    return fmt::format("guaranteed mode: {} face(s) with a trim the reader could not make valid, their mesh not "
                       "certified: {}",
                       uncertified.size(), fmt::join(uncertified, "; "));
  return {};
}

ModelMesh mesh_model(const LoadedModel& loaded, const ModelMeshOptions& options) {
  const Model& model = loaded.model;
  ModelMesh out;
  out.size = loaded.checked_size();
  out.eps = options.relative ? options.eps * out.size : options.eps;
  const double eps = out.eps;
  if (!(eps > 0) || !std::isfinite(eps))
    throw RequestError(fmt::format("--eps: {} is not a positive tolerance", eps));
  if (const double least = kMinRelativeEps * out.size; !(eps >= least * (1 - 1e-12)))
    throw RequestError(fmt::format("--eps {:g}: below {:.6g}, the smallest usable ({:g} of the model size {:g}; the "
                                   "triangle count grows as 1/eps)",
                                   options.eps, least, kMinRelativeEps, out.size));
  std::vector<TrimmedSurface> faces = world_faces(model);
  std::vector<char> in_solid;  // per face: its body is a closed solid (empty for chosen faces)
  for (const Body& b : model.bodies) in_solid.insert(in_solid.end(), b.faces.size(), b.closed ? 1 : 0);
  if (!options.faces.empty()) {
    in_solid.clear();
    std::vector<TrimmedSurface> chosen;
    for (int index : options.faces) {
      if (index < 0 || index >= int(faces.size()))
        throw RequestError(fmt::format("--face {}: the model has faces 0..{}", index, int(faces.size()) - 1));
      chosen.push_back(faces[size_t(index)]);
    }
    faces = std::move(chosen);
  }
  TessellateOptions o = options.tess;
  o.eps = eps;
  o.weld = std::min(model.resolution, 0.1 * eps);
  out.guaranteed = o.mode == TessMode::Guaranteed;
  try {
    out.result = tessellate(faces, o, options.progress);
  } catch (const WorkLimitError& e) {
    const double least = options.relative ? e.least_eps / out.size : e.least_eps;
    throw RequestError(fmt::format("--eps {:g}: about {:.3g} surface cells, above --max-cells {} (estimated before the "
                                   "work from the cells at 64, 256 and 1024 times eps); --eps {:.2g}{} or more fits",
                                   options.eps, double(e.estimated_cells), o.max_cells, least,
                                   options.relative ? " --relative" : ""));
  }
  TessellateResult& r = out.result;
  // Guaranteed mode, always, on each face's own vertices (before a weld gives a seam vertex one
  // side's (u, v): a triangle beside the seam would then span the domain): triangles whose centroid
  // or edge midpoints lie off their face's surface by more than eps (triangles_off_surface: one
  // evaluation per sample), or outside its trim farther than eps from its boundary
  // (triangles_outside_trim, cheap); such a face fails, named.
  const double largest_gap = largest_edge_gap(faces);
  if (out.guaranteed) {
    auto t0 = std::chrono::steady_clock::now();
    // Watertight, a face's boundary vertices may move onto a neighbour's loop across both faces'
    // edge gaps (watertight.h): its triangles may lie that much farther off.
    std::vector<double> extra;
    if (o.watertight && largest_gap > 0.0)
      for (const TrimmedSurface& f : faces) extra.push_back(f.edge_gap + largest_gap);
    out.off_surface = triangles_off_surface(faces, r.mesh, eps, extra);
    out.surface_check_seconds = nurbs::seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    out.outside = triangles_outside_trim(faces, r.mesh, eps);
    out.trim_check_seconds = nurbs::seconds_since(t0);
  }
  // Watertight: the mesh's shared boundary vertices made one (welded as the tessellator welds
  // them), and its edges counted as they are. Otherwise each face keeps its vertices, and the count
  // welds as the tessellator does (the file's resolution, at least 1e-9 of the largest face's
  // control box; with 1e-9 of the sampled model size, smaller, the vase shell showed 4 seam cracks
  // of 2e-7).
  if (o.watertight) {
    r.mesh = weld_mesh(r.mesh, r.weld_tolerance, &out.collapsed);
    r.stats.triangles = (long long)r.mesh.triangles.size(), r.stats.vertices = (long long)r.mesh.positions.size();
  }
  out.edges = o.watertight ? count_edges_as_indexed(r.mesh) : count_edges(r.mesh, r.weld_tolerance);
  // Watertight: open edges on the faces of a closed solid are cracks the mesh should not have
  // (where the file's faces do not meet within the loops' tolerance).
  if (o.watertight)
    for (const auto& [f, n] : out.edges.open_by_face)
      if (f >= 0 && size_t(f) < in_solid.size() && in_solid[size_t(f)]) {
        out.solid_open += n;
        out.solid_cracks.push_back(fmt::format("face {} (id {}): {}", f, faces[size_t(f)].face_id, n));
      }
  if (options.check) {
    DeviationOptions d;
    d.samples = options.check_samples;
    d.boundary_tolerance = 1e-3 * eps;
    d.threads = o.threads;
    out.deviation = measure_deviation(faces, r.mesh, d);
  }
  // Faces whose trim the reader could not make valid: their mesh is not certified (the material
  // region is not known); faces whose file edges lie off the surface: the mesh is within eps of the
  // face as read, and within eps plus the gap of the file's edges (nurbs/model_report.h).
  // Watertight, a shared edge's vertices move onto the other face's loop, up to both gaps away.
  out.gap = (o.watertight ? 2.0 : 1.0) * largest_gap;
  for (size_t f = 0; f < faces.size(); ++f) {
    if (!faces[f].trim_problem.empty())
      out.uncertified.push_back(fmt::format("face {} (id {}): {}", f, faces[f].face_id, faces[f].trim_problem));
  }
  for (size_t f = 0; f < out.outside.size(); ++f)
    if (out.outside[f].triangles > 0)
      out.over_eps.push_back(fmt::format("face {} (id {}): {} triangles, {:.6g} outside", f, faces[f].face_id,
                                         out.outside[f].triangles, out.outside[f].distance));
  for (size_t f = 0; f < out.off_surface.size(); ++f)
    if (out.off_surface[f].triangles > 0)
      out.off_eps.push_back(fmt::format("face {} (id {}): {} triangles, {:.6g} off the surface", f, faces[f].face_id,
                                        out.off_surface[f].triangles, out.off_surface[f].distance));
  out.model_reason = loaded.report.uncertified_reason(options.accept_partial);
  out.faces = std::move(faces);
  return out;
}

}  // namespace nurbs::tess
