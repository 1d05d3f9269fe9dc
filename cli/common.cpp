#include "cli/common.h"

#include "nurbs/parallel.h"

#include "cli/commands.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <iostream>
#include <utility>

#include "nurbs/io/input_file.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"

namespace cli {

LoadedModel load_model(const std::string& path, const std::string& command) {
  LoadedModel m = nurbs::io::load_model(path);
  for (const std::string& line : m.report.lines()) fmt::print(stderr, "{}: {}: {}\n", command, path, line);
  return m;
}

nlohmann::json model_json(const nurbs::ModelReport& r, const GlobalOptions& global) {
  nlohmann::json dropped = nlohmann::json::array(), trims = nlohmann::json::array(), gaps = nlohmann::json::array();
  for (const nurbs::DroppedFace& d : r.dropped) dropped.push_back({{"entity", d.entity}, {"reason", d.reason}});
  for (const nurbs::FaceNote& n : r.invalid_trims)
    trims.push_back({{"face", n.face}, {"face_id", n.face_id}, {"problem", n.problem}});
  for (const nurbs::FaceNote& n : r.edge_gaps) gaps.push_back({{"face", n.face}, {"face_id", n.face_id}, {"gap", n.gap}});
  return {{"faces_in_file", r.faces_in_file >= 0 ? nlohmann::json(r.faces_in_file) : nlohmann::json()},
          {"faces_read", r.faces_read},
          {"faces_dropped", dropped},
          {"invalid_trims", trims},
          {"edge_gaps", gaps},
          {"read_warnings", r.warnings},
          {"partial_accepted", r.partial() && global.accept_partial}};
}

void add_model_json(nlohmann::json& j, const nurbs::ModelReport& report, const GlobalOptions& global) {
  j.update(model_json(report, global));
}

void require_certified(const nurbs::ModelReport& report, const GlobalOptions& global) {
  if (const std::string why = report.uncertified_reason(global.accept_partial); !why.empty()) throw CommandFailed(why);
}

std::unique_ptr<gpgpu::Gpu> start_gpu(const GlobalOptions& options) {
  gpgpu::ContextOptions ctx;
  try {
    ctx.backend = options.gl.empty() ? gpgpu::backend_from_env() : gpgpu::parse_backend(options.gl);
  } catch (const std::invalid_argument& e) {
    // --gl is checked by CLI11 while parsing, so this is the environment variable.
    throw BadInput(fmt::format("NURBSGL_GL={}: {}", std::getenv("NURBSGL_GL"), e.what()));
  }
  ctx.software_threads = options.gl_threads;
  auto gpu = std::make_unique<gpgpu::Gpu>(ctx);
  // A software renderer where hardware exists is a setting to change, not a fact to accept.
  if (const std::string& note = gpu->info().hardware_unused; !note.empty()) fmt::print(stderr, "nurbsgl: {}\n", note);
  if (!options.dump_dir.empty()) gpu->set_dump_dir(options.dump_dir);
  gpu->profiler().set_enabled(options.profile);
  gpu->profiler().set_sync(options.profile);
  return gpu;
}

Progress::Progress(std::string what, std::string unit)
    : what_(std::move(what)), unit_(std::move(unit)), start_(std::chrono::steady_clock::now()) {}

void Progress::update(long long done, long long total) {
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (t < 1.0 || (t - last_ < 0.5 && done < total)) return;
  last_ = t;
  shown_ = true;
  const bool tty = isatty(STDERR_FILENO);
  fmt::print(stderr, "{}{}: {}/{} {}", tty ? "\r" : "", what_, done, total, unit_);
  if (!tty) fmt::print(stderr, "\n");
}

Progress::~Progress() {
  if (shown_ && isatty(STDERR_FILENO)) fmt::print(stderr, "\n");
}

void report_profile(gpgpu::Gpu& gpu, const GlobalOptions& options) {
  if (!options.profile) return;
  std::fflush(stdout);  // the table follows the command's own output, also when stdout is a pipe
  fmt::print(stderr, "\n{}", gpu.profiler().table());
}

CommandProgress command_progress(const std::string& command, const std::string& unit) {
  auto bar = std::make_shared<Progress>(command, unit);
  return {[bar](size_t done, size_t total) { bar->update((long long)done, (long long)total); },
          [command](const std::string& line) { fmt::print(stderr, "{}: {}\n", command, line); }};
}

std::string read_input_text(const std::string& path, const std::string& option) {
  try {
    return path == "-" ? nurbs::io::read_input_stream(std::cin, "stdin") : nurbs::io::read_input_file(path);
  } catch (const nurbs::io::ReadError& e) {
    throw BadInput(option + " " + e.what());
  }
}

nurbs::io::PointCloud read_points_file(const std::string& path, const std::string& option, double limit) {
  try {
    return path == "-" ? nurbs::io::read_point_cloud(std::cin, "stdin", limit)
                       : nurbs::io::read_point_cloud_file(path, limit);
  } catch (const nurbs::io::ReadError& e) {
    throw BadInput(option + " " + e.what());
  }
}

void append_csv_quoted(fmt::memory_buffer& buf, std::string_view text) {
  buf.push_back('"');
  for (const char c : text) {
    if (c == '"') buf.push_back('"');
    buf.push_back(c);
  }
  buf.push_back('"');
}

void check_output(const std::string& path, const std::string& option) {
  if (path.empty()) return;
  try {
    nurbs::io::check_writable(path);
  } catch (const nurbs::io::WriteError& e) {
    throw BadInput(option + ": " + e.what());
  }
}

void write_rows(const std::string& path, std::string_view header, size_t rows,
                const std::function<void(fmt::memory_buffer&, size_t)>& row) {
  std::vector<fmt::memory_buffer> parts(nurbs::share_count(rows, 4096));
  nurbs::for_shares(rows, parts.size(), [&](size_t share, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) row(parts[share], k);
  });
  nurbs::io::write_file(path, [&](std::ostream& out) {
    out.write(header.data(), std::streamsize(header.size()));
    for (const fmt::memory_buffer& b : parts) out.write(b.data(), std::streamsize(b.size()));
  });
}

namespace {
bool g_json_printed = false;

/// The JSON text, indented by 2. Names a file gives its faces and bodies need not be UTF-8 (IGES
/// Hollerith strings, STEP strings in the writer's code page): invalid bytes become U+FFFD.
std::string json_text(const nlohmann::json& j) { return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace); }
}  // namespace

void print_json(const nlohmann::json& j) {
  fmt::print("{}\n", json_text(j));
  std::fflush(stdout);
  g_json_printed = true;
}

void print_json_streamed(nlohmann::json j, const std::string& key, size_t count,
                         const std::function<nlohmann::json(size_t)>& element) {
  // The array's place in the object's text (keys sorted, as dump has them), found by a marker.
  const std::string marker = "\x01nurbsgl-streamed-array\x01";
  j[key] = marker;
  const std::string text = json_text(j);
  const std::string quoted = nlohmann::json(marker).dump();
  const size_t at = text.find(quoted);
  if (at == std::string::npos) throw std::logic_error("print_json_streamed: the marker is not in the text");
  std::string out = text.substr(0, at);
  if (count == 0) {
    out += "[]";
  } else {
    // The array at depth 1: elements indented by 4, their members by 6, as dump(2) writes them.
    out += "[\n";
    for (size_t k = 0; k < count; ++k) {
      const std::string e = json_text(element(k));
      out += "    ";
      for (const char c : e) {
        out += c;
        if (c == '\n') out += "    ";
      }
      out += k + 1 < count ? ",\n" : "\n";
      if (out.size() > (1u << 20)) std::fwrite(out.data(), 1, out.size(), stdout), out.clear();
    }
    out += "  ]";
  }
  out += text.substr(at + quoted.size());
  out += "\n";
  std::fwrite(out.data(), 1, out.size(), stdout);
  std::fflush(stdout);
  g_json_printed = true;
}

bool json_printed() { return g_json_printed; }

std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& names) {
  const auto distance = [](const std::string& a, const std::string& b) {  // Levenshtein
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  std::vector<std::string> out;
  for (const std::string& n : names)
    if (distance(word, n) <= 2 || (word.size() >= 2 && n.rfind(word, 0) == 0)) out.push_back(n);
  return out;
}

}  // namespace cli
