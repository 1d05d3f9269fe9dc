#include "nurbs/io/read_model.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <string>

#include "nurbs/io/bpt_reader.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/step_file.h"
#include "nurbs/io/step_reader.h"

namespace nurbs::io {

namespace {

/// The first `bytes` of the file (fewer when it is shorter or cannot be read).
std::string file_start(const std::filesystem::path& path, size_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string text(bytes, '\0');
  in.read(text.data(), std::streamsize(bytes));
  text.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return text;
}

}  // namespace

ModelFormat sniff_model_format(const std::string& start) {
  if (looks_like_step(start)) return ModelFormat::Step;
  // IGES 5.3 §2.1: fixed 80-column records, the section letter in column 73 and the sequence number
  // in 74-80; the file opens with the Start section ('S'), or the Global section where the Start
  // section is empty.
  const size_t end = start.find('\n');
  std::string line = start.substr(0, end);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.size() >= 73 && line.size() <= 82 && (line[72] == 'S' || line[72] == 'G')) {
    const std::string number = line.substr(73);
    const bool numbered = std::any_of(number.begin(), number.end(), [](unsigned char c) { return std::isdigit(c); }) &&
                          std::all_of(number.begin(), number.end(),
                                      [](unsigned char c) { return std::isdigit(c) || c == ' '; });
    if (numbered) return ModelFormat::Iges;
  }
  return ModelFormat::Unknown;
}

Model read_model(const std::filesystem::path& path, IgesReadLog* log) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (!std::filesystem::exists(path)) throw ReadError(path.string(), "", "no such file");
  if (ext == ".bpt") return read_bpt(path);
  const ModelFormat named = ext == ".igs" || ext == ".iges"   ? ModelFormat::Iges
                            : ext == ".stp" || ext == ".step" ? ModelFormat::Step
                                                              : ModelFormat::Unknown;
  const ModelFormat held = std::filesystem::is_regular_file(path) ? sniff_model_format(file_start(path, 4096))
                                                                   : ModelFormat::Unknown;
  // The content decides where it is plainly STEP or IGES (CAD systems and users rename files); the
  // name decides otherwise, so that a damaged file gets its own reader's message.
  const ModelFormat format = held != ModelFormat::Unknown ? held : named;
  if (format == ModelFormat::Unknown)
    throw ReadError(path.string(), "",
                    "unknown model format '" + ext +
                        "' (nurbsgl reads .igs, .iges, .stp, .step and .bpt, and IGES or STEP content under any name)");
  Model model = format == ModelFormat::Iges ? read_iges(path, {}, log) : read_step(path, log);
  const auto name = [](ModelFormat f) { return std::string(f == ModelFormat::Iges ? "IGES" : "STEP"); };
  if (named != ModelFormat::Unknown && named != format)
    model.read_warnings.insert(model.read_warnings.begin(), "the file holds " + name(format) + ", not " +
                                                                name(named) + " as its name '" +
                                                                path.extension().string() + "' says: read as " +
                                                                name(format));
  return model;
}

LoadedModel load_model(const std::filesystem::path& path) {
  LoadedModel m{read_model(path), {}, path};
  m.report = model_report(m.model);
  return m;
}

}  // namespace nurbs::io
