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
};

}  // namespace nurbs
