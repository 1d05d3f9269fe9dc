#pragma once
/// \file model_summary.h
/// What `nurbsgl info MODEL [--json]` prints: faces, degrees, control-point counts, rational or
/// not, trim loops, bounding box and model size (sampled, with the control-point box diagonal
/// beside it as an upper bound), skipped IGES entities, and what the reader left out or read
/// differently: the file's face count, the dropped faces with their reasons, the read warnings.
#include <glm/vec3.hpp>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "nurbs/model.h"

namespace nurbs::io {

struct FaceSummary {
  int body = 0;      ///< index into Model::bodies
  int face_id = -1;  ///< TrimmedSurface::face_id (IGES: directory entry number)
  std::string name;
  int degree_u = 0, degree_v = 0;
  int count_u = 0, count_v = 0;  ///< control points along u and v
  bool rational = false;
  int outer_loops = 0, inner_loops = 0, trim_curves = 0;
};

struct BodySummary {
  std::string name;
  std::string instance;  ///< Body::instance: where an assembly places it
  int faces = 0;
};

struct ModelSummary {
  std::string source;
  double unit_scale_to_mm = 1.0;
  int bodies = 0;
  int faces = 0;
  int trimmed_faces = 0;  ///< faces with at least one loop
  int rational_faces = 0;
  int control_points = 0;  ///< total over all faces
  int max_degree_u = 0, max_degree_v = 0;
  int outer_loops = 0, inner_loops = 0, trim_curves = 0;
  /// Box of all control points after body transforms, in file units. It contains the surfaces
  /// (convex hull property of positive weights) but may be larger than their tight box.
  glm::dvec3 bbox_min{0.0}, bbox_max{0.0};
  /// Box of sampled surface points (nurbs::model_box): the model's own box, slightly inside the
  /// true one on curved faces.
  glm::dvec3 sampled_min{0.0}, sampled_max{0.0};
  /// nurbs::model_size: diagonal of the sampled box (ACIS-style), file units. Sampled, hence a
  /// lower estimate of the true box diagonal: a spike between samples can be missed.
  double size = 0.0;
  /// Diagonal of the control-point box: an upper bound of the true box diagonal.
  double control_size = 0.0;
  std::map<int, int> skipped_entities;
  std::map<std::string, int> skipped_types;  ///< STEP entity types not read
  int faces_in_file = -1;                    ///< Model::faces_in_file (-1: not counted)
  std::vector<DroppedFace> faces_dropped;    ///< Model::dropped_faces
  std::vector<std::string> read_warnings;    ///< Model::read_warnings
  std::vector<BodySummary> body_list;
  std::vector<FaceSummary> face_list;
};

/// Collects the summary of `model`.
ModelSummary summarize(const Model& model);

/// One face's line of the summary (degrees, control points, loops); body left 0.
FaceSummary summarize_face(const TrimmedSurface& face);

/// Human-readable text, one fact per line; with `per_face` a line per face follows.
std::string to_text(const ModelSummary& s, bool per_face = false);

/// JSON object with the same facts ("faces" is the count, "face_list" the per-face array,
/// "skipped_entities" maps IGES type numbers (as strings) and STEP type names to counts,
/// "body_list" names each body, its faces and where an assembly places it, "faces_in_file" the
/// file's face count, "faces_dropped" [{"entity", "reason"}], "read_warnings" the reader's lines).
nlohmann::json to_json(const ModelSummary& s);

}  // namespace nurbs::io
