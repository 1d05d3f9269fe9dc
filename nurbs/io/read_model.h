#pragma once
/// \file read_model.h
/// One entry point for every model format nurbsgl reads, chosen by the file's content where it is
/// plainly STEP or IGES, else by its extension.
#include <filesystem>

#include "nurbs/io/iges_reader.h"
#include "nurbs/model.h"
#include "nurbs/model_report.h"

namespace nurbs::io {

/// What the start of a file holds: STEP (ISO-10303-21; after any white space), IGES (a first record
/// of 80 columns with the section letter S or G in column 73 and a sequence number after it), or
/// neither.
enum class ModelFormat { Unknown, Step, Iges };
[[nodiscard]] ModelFormat sniff_model_format(const std::string& start);

/// .bpt: Bézier patches (bpt_reader.h). Otherwise the content's format (sniff_model_format of the
/// first 4 KiB) where it is STEP or IGES, else the extension's: .igs / .iges (any case): IGES 5.3
/// (iges_reader.h); .stp / .step: STEP (step_reader.h). A file whose content and extension disagree
/// is read by its content, with a read warning that says so (Model::read_warnings).
/// Throws ReadError naming the file for a missing file, an unknown format or malformed content.
/// `log` (optional) receives what the IGES or STEP reader repaired and found (empty for .bpt).
Model read_model(const std::filesystem::path& path, IgesReadLog* log = nullptr);

/// read_model with the reader's report (model_report): the model every query's front door takes.
[[nodiscard]] LoadedModel load_model(const std::filesystem::path& path);

}  // namespace nurbs::io
