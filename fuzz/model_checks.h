#pragma once
/// \file model_checks.h
/// What every command does with a model before its query, for the fuzz targets to run on each model
/// a reader accepts: its size and that size's validation (cli::checked_model_size), the faces in
/// world coordinates, each surface's own validation.
#include "nurbs/model.h"
#include "nurbs/model_ops.h"
#include "nurbs/validate.h"

namespace fuzz {

inline void whole_model_checks(const nurbs::Model& model) {
  const double size = nurbs::model_size(model);
  if (!nurbs::validate_model_size(size).empty()) return;  // refused by every command
  (void)nurbs::coordinate_limit(nurbs::model_box(model));
  for (const nurbs::TrimmedSurface& f : nurbs::world_faces(model)) (void)nurbs::validate(f.surface);
}

}  // namespace fuzz
