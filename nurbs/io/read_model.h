#pragma once
/// \file read_model.h
/// One entry point for every model format nurbsgl reads, chosen by file extension.
#include <filesystem>

#include "nurbs/io/iges_reader.h"
#include "nurbs/model.h"
#include "nurbs/model_report.h"

namespace nurbs::io {

/// .igs / .iges (any case): IGES 5.3 (iges_reader.h); .stp / .step: STEP (step_reader.h); .bpt:
/// Bézier patches (bpt_reader.h).
/// Throws ReadError naming the file for a missing file, an unknown extension or malformed content.
/// `log` (optional) receives what the IGES or STEP reader repaired and found (empty for .bpt).
Model read_model(const std::filesystem::path& path, IgesReadLog* log = nullptr);

/// read_model with the reader's report (model_report): the model every query's front door takes.
[[nodiscard]] LoadedModel load_model(const std::filesystem::path& path);

}  // namespace nurbs::io
