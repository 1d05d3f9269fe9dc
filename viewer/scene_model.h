#pragma once
/// \file scene_model.h
/// One model as the viewer holds it: the faces read from the file (world coordinates), its size,
/// its tessellation (nurbs/tessellation, Balázs et al.) on the GPU for display, CPU picking of a
/// face under the cursor, and the overlays of a picked face (control net, trim loops).
#include <glm/mat4x4.hpp>
#include <optional>
#include <string>
#include <vector>

#include "nurbs/model.h"
#include "nurbs/model_ops.h"
#include "nurbs/model_report.h"
#include "nurbs/tessellation/model_mesh.h"
#include "nurbs/tessellation/tessellate.h"
#include "viewer/camera.h"
#include "viewer/draw_buffers.h"

namespace viewer {

struct SceneModel {
  std::string path;
  nurbs::LoadedModel loaded;                 ///< the model as every query's front door takes it
  std::vector<nurbs::TrimmedSurface> faces;  ///< nurbs::world_faces of the file
  nurbs::Box box;                            ///< sampled box (nurbs::model_box)
  double size = 0.0;                         ///< nurbs::model_size, the scale of relative tolerances
  nurbs::tess::TessellateResult tess;
  glm::dvec3 mesh_min{0.0}, mesh_max{0.0};  ///< box of the tessellation (trimmed material only): framing
  double tess_eps = 0.0;                    ///< absolute eps of `tess`
  std::string tess_failure;                 ///< why `tess` is not certified within tess_eps (ModelMesh::failure)
  double tess_seconds = 0.0;
  MeshBuffers buffers;
};

/// Reads `path` (nurbs::io::load_model). Throws nurbs::io::ReadError with the reader's message, or
/// nurbs::RequestError naming the file when its size cannot scale a tolerance (empty model).
void load_scene_model(SceneModel& out, const std::string& path);

/// Tessellates the model within `eps_relative` x its size in `mode` through the library's front door
/// (nurbs::tess::mesh_model, with its checks of a guaranteed mesh, as `nurbsgl tessellate`), uploads
/// the mesh; `scalar` (per mesh vertex) is kept empty here, thickness mode uploads its own mesh.
/// Throws nurbs::RequestError for an eps the model cannot be meshed at (the mesh stays).
void tessellate_scene_model(SceneModel& m, double eps_relative, nurbs::tess::TessMode mode);

struct Pick {
  int face = -1;  ///< index into SceneModel::faces
  double t = 0.0;
  glm::dvec3 point{0.0};  ///< world, after `motion`
};

/// The nearest triangle of `mesh` (moved by the rigid `motion`) hit by `ray` (Möller-Trumbore in
/// double, both sides), or nothing.
[[nodiscard]] std::optional<Pick> pick(const nurbs::TriangleMesh& mesh, const glm::dmat4& motion, const Ray& ray);

/// Adds the control net of `face` (lines between neighbouring control points) to `batch`, in the
/// model's own frame.
void add_control_net(const nurbs::TrimmedSurface& face, const glm::vec3& color, LineBatch& batch);

/// Adds the trim loops of `face` mapped onto the surface (the boundary of its parameter domain when
/// it is untrimmed) to `batch`, in the model's own frame: the face's edges.
void add_trim_loops(const nurbs::TrimmedSurface& face, const glm::vec3& color, LineBatch& batch);

}  // namespace viewer
