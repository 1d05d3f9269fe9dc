#include "nurbs/io/read_model.h"

#include <algorithm>
#include <cctype>

#include "nurbs/io/bpt_reader.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/step_reader.h"

namespace nurbs::io {

Model read_model(const std::filesystem::path& path, IgesReadLog* log) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (!std::filesystem::exists(path)) throw ReadError(path.string(), "", "no such file");
  if (ext == ".igs" || ext == ".iges") return read_iges(path, {}, log);
  if (ext == ".stp" || ext == ".step") return read_step(path, log);
  if (ext == ".bpt") return read_bpt(path);
  throw ReadError(path.string(), "", "unknown model format '" + ext + "' (nurbsgl reads .igs, .iges, .stp, .step and .bpt)");
}

LoadedModel load_model(const std::filesystem::path& path) {
  LoadedModel m{read_model(path), {}, path};
  m.report = model_report(m.model);
  return m;
}

}  // namespace nurbs::io
