#pragma once
/// \file model.h
/// A model: named bodies of trimmed faces, each body with a rigid transform, plus what the reader
/// saw (source file, unit scale, skipped entity types).
#include <glm/mat4x4.hpp>
#include <map>
#include <string>
#include <vector>

#include "trimmed_surface.h"

namespace nurbs {

struct Body {
  std::string name;
  std::vector<TrimmedSurface> faces;
  glm::dmat4 transform{1.0};  ///< rigid: rotation + translation, applied to every face
  /// Where an assembly places it: the chain of usage occurrences from the top ("A/B"), empty when
  /// the file has no assembly structure.
  std::string instance;
  /// The file states that the faces bound a solid (an IGES 186, a STEP MANIFOLD_SOLID_BREP or
  /// BREP_WITH_VOIDS): a watertight mesh of them has no open edges.
  bool closed = false;
  /// Why a solid the file states closed is read as open (`closed` false), e.g. "2 of its edges bound
  /// one face only (edge #30 of face #52)"; empty otherwise.
  std::string not_closed{};
  /// The reader dropped `count` of its faces (said where dropped): a closed solid that lost faces
  /// bounds no inside as read, and is open from then on.
  void lose_faces(size_t count) {
    if (!closed || count == 0) return;
    closed = false;
    not_closed = std::to_string(count) + " of its faces were dropped";
  }
};

/// A face entity of the file that the model does not hold, and why.
struct DroppedFace {
  std::string entity;  ///< the file's name for it: "D123" (IGES directory entry), "#45" (STEP instance)
  std::string reason;
};

struct Model {
  std::vector<Body> bodies;
  std::string source;             ///< file the model came from, or the generator's name
  double unit_scale_to_mm = 1.0;  ///< from the IGES global section (parameter 14/15)
  /// The writer's stated resolution in model units (IGES global parameter 19: points closer than
  /// this are meant to be one point; OpenCASCADE writes its largest edge tolerance); 0 = not given.
  double resolution = 0.0;
  std::map<int, int> skipped_entities;  ///< IGES entity type -> count, for entities not read
  std::map<std::string, int> skipped_types;  ///< STEP entity type -> count, for geometry not read
  /// Face entities the file defines (read or dropped); -1 when the reader does not count them.
  int faces_in_file = -1;
  /// Faces of the file left out of the model, each naming its entity and the reason. A model that
  /// lost a face is another model: no answer on it is certified unless the caller accepts the
  /// partial model (model_report.h).
  std::vector<DroppedFace> dropped_faces;
  /// What else the reader read differently from the letter of the file (a damaged record the
  /// geometry never reaches, a string whose count runs past its end), each naming file line or entity.
  std::vector<std::string> read_warnings;
};

}  // namespace nurbs
