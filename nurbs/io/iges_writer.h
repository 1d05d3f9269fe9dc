#pragma once
/// \file iges_writer.h
/// A minimal IGES 5.3 writer for Models, the inverse of iges_reader.h for what a Model holds:
/// untrimmed faces as independent 128 surfaces; trimmed faces as 144 over a 128, each loop a 142
/// whose parameter-space curve is a 102 composite of 126 curves (z = 0). Body transforms are
/// applied to the control points; bodies are not kept (all faces are written flat).
#include <filesystem>
#include <ostream>
#include <string>

#include "nurbs/model.h"

namespace nurbs::io {

/// Writes `model` as IGES to `out`; `file_name` goes into the global section (G4). Units from
/// model.unit_scale_to_mm (1 mm, 25.4 in, 10 cm, 1000 m, 304.8 ft, 0.001 micron, 0.0254 mil).
/// Reals are written with the shortest text that reads back to the same double, so a round
/// trip through read_iges is exact. Throws std::invalid_argument for an unknown unit scale, a face
/// with more than one outer loop, or inconsistent array sizes (bad points/knots/weights counts).
void write_iges(std::ostream& out, const Model& model, const std::string& file_name = "model.igs");

/// write_iges into a string.
std::string write_iges_text(const Model& model, const std::string& file_name = "model.igs");

/// write_iges into a file; throws std::runtime_error when it cannot be written.
void write_iges_file(const std::filesystem::path& path, const Model& model);

}  // namespace nurbs::io
