#pragma once
/// \file model_mesh.h
/// The front door of the tessellation (Balázs, Guthe, Klein): a model's faces to one triangle mesh
/// within eps of them, with everything a caller needs decided in one place. The request is checked
/// before the work (eps above kMinRelativeEps of the model size, the cells within max_cells), the
/// weld follows the file's resolution, and the guaranteed mode checks its own result: triangles off
/// their surface or outside their trim by more than eps, open edges on the faces of a closed solid
/// in a watertight mesh, faces whose trim the reader could not make valid, and, when asked, the
/// deviation measured both ways. ModelMesh::failure says what fails, naming the faces.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nurbs/model_report.h"
#include "nurbs/paper_switch.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/tessellation/mesh_topology.h"
#include "nurbs/tessellation/tessellate.h"

namespace nurbs::tess {

struct ModelMeshOptions {
  double eps = 1e-3;     ///< the mesh's largest distance from the faces
  bool relative = true;  ///< eps is a fraction of the model size; false: model units
  /// The tessellator's settings; its eps and weld are set from the request and the model.
  TessellateOptions tess;
  std::vector<int> faces;  ///< the faces to mesh (indices into world_faces); empty: all
  bool check = false;      ///< measure the deviation (measure_deviation) on a check_samples^2 grid per face
  int check_samples = 48;
  bool accept_partial = false;  ///< a mesh of a model whose reader dropped faces may be certified
  std::function<void(int done, int total)> progress;  ///< faces tessellated

  /// These options with every setting the paper fixes: the kd-tree with the control-net bound
  /// (§5.2), trim curves split at their midpoint and their loops simplified (§5.1), every segment of
  /// a polyline lifted (§4), every loop approximated by polylines (§5.1), vertices evaluated
  /// coherently (§8), each face on its own (§3). The mode stays: the paper gives both errors.
  [[nodiscard]] ModelMeshOptions paper() const;
  [[nodiscard]] static std::vector<PaperSwitch> paper_switches();
};

struct ModelMesh {
  /// The mesh (welded to shared vertices when watertight), its figures and the faces that failed.
  TessellateResult result;
  std::vector<TrimmedSurface> faces;  ///< the faces meshed: triangle_face indexes them
  double size = 0.0;                  ///< model_size
  double eps = 0.0;                   ///< model units
  double gap = 0.0;  ///< the largest edge gap of the faces (nurbs/model_report.h), twice it when watertight
  /// Of the mesh from the file's faces: eps plus the largest edge gap, plus the widest sliver hole
  /// the watertight mesh closed (TessellateResult::fill_width).
  [[nodiscard]] double bound() const { return eps + gap + result.fill_width; }
  bool guaranteed = true;

  /// Guaranteed mode: per face, the triangles outside its trim, or off its surface, by more than eps.
  std::vector<OutsideTrim> outside, off_surface;
  double trim_check_seconds = 0.0, surface_check_seconds = 0.0;
  long long collapsed = 0;  ///< triangles the watertight weld collapsed
  EdgeCounts edges;         ///< as written: indexed when watertight, welded within the weld tolerance else
  /// Watertight: open edges on the faces of closed solids (cracks), in all and per face for people.
  long long solid_open = 0;
  std::vector<std::string> solid_cracks;
  std::optional<Deviation> deviation;  ///< when checked
  /// For people, one line a face: outside the trim by more than eps, off the surface by more than
  /// eps, a trim the reader could not make valid.
  std::vector<std::string> over_eps, off_eps, uncertified;
  std::string model_reason;  ///< ModelReport::uncertified_reason

  /// Why the mesh is not certified within bound(), for people; empty when it is. In order: faces
  /// not tessellated, triangles outside a trim or off a surface, the measured deviation, cracks of a
  /// closed solid, a model that lost faces, faces with invalid trims (guaranteed mode).
  [[nodiscard]] std::string failure() const;
};

/// Meshes `model` as `options` ask. Throws nurbs::RequestError for an eps below kMinRelativeEps of
/// the model size or whose estimated cells exceed max_cells (naming the eps that fits), or a face
/// index the model does not have.
[[nodiscard]] ModelMesh mesh_model(const LoadedModel& model, const ModelMeshOptions& options);

}  // namespace nurbs::tess
