#pragma once
/// \file common.h
/// What every `nurbsgl` subcommand shares: global options, exit codes, GPU start-up.
#include <chrono>
#include <fmt/format.h>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/io/point_cloud.h"
#include "nurbs/io/point_cloud.h"
#include "nurbs/model.h"
#include "nurbs/model_report.h"

namespace cli {

/// Exit codes of the nurbsgl executable (documented in README.md and --help).
enum ExitCode : int {
  kOk = 0,
  kFailed = 1,    ///< a check failed, or an internal error
  kBadInput = 2,  ///< bad command line or unreadable / malformed input file
  kNoGl = 3,      ///< no OpenGL backend could start
};

/// Bad command line, environment or input detected after parsing (e.g. NURBSGL_GL=vulkan): exit code 2.
/// what() is the whole message, naming the option or variable and the problem.
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlobalOptions {
  std::string gl = "";   ///< --gl; empty = NURBSGL_GL, else auto
  std::string dump_dir;  ///< --dump DIR: EXR dumps of the textures a command produces
  bool profile = false;  ///< --profile: per-pass GPU/CPU time table on stderr
  int gl_threads = -1;   ///< --gl-threads: llvmpipe's rasterizer threads (gpgpu::ContextOptions)
  /// --accept-partial: answers on a model whose reader dropped faces may be certified, on the
  /// faces read (nurbs::ModelReport::uncertified_reason).
  bool accept_partial = false;
  /// --strict: an answer over the tolerance only by the file's precision (edges that lie off their
  /// faces: limited_by_file) exits 1 as any other answer over it; without it such answers exit 0.
  bool strict = false;
};

/// A model read for a command, with the reader's report (nurbs/model_report.h).
using LoadedModel = nurbs::LoadedModel;

/// Reads the model file `path` (nurbs::io::read_model) and says on stderr, prefixed by `command`,
/// what the reader dropped, could not repair or read otherwise than the file says.
[[nodiscard]] LoadedModel load_model(const std::string& path, const std::string& command);

/// What every command's JSON says about its model (the fields add_model_json lists), as one object:
/// clearance's "model_a" and "model_b".
[[nodiscard]] nlohmann::json model_json(const nurbs::ModelReport& report, const GlobalOptions& global);

/// The fields every command's JSON carries about its model: faces_in_file, faces_read,
/// faces_dropped [{entity, reason}], invalid_trims [{face, face_id, problem}], edge_gaps [{face,
/// face_id, gap}], read_warnings and partial_accepted.
void add_model_json(nlohmann::json& j, const nurbs::ModelReport& report, const GlobalOptions& global);

/// Throws CommandFailed (exit 1) with the reason when answers on the model are not certified as a
/// whole (faces dropped without --accept-partial). Called after a command printed its answers.
void require_certified(const nurbs::ModelReport& report, const GlobalOptions& global);

/// Starts the GPU for a command (backend from --gl, else NURBSGL_GL, else auto), with dumps and
/// profiling as asked. Throws BadInput (exit 2) for an unknown NURBSGL_GL and gpgpu::NoGlError
/// (exit 3) when nothing starts.
std::unique_ptr<gpgpu::Gpu> start_gpu(const GlobalOptions& options);

/// Prints the profiler's per-pass table on stderr when --profile was given.
void report_profile(gpgpu::Gpu& gpu, const GlobalOptions& options);

/// Progress on stderr once a piece of work has run for a second: "what: done/total unit", redrawn
/// in place on a terminal, one line per half second otherwise.
class Progress {
 public:
  Progress(std::string what, std::string unit);
  void update(long long done, long long total);
  ~Progress();  ///< ends the line when one was drawn on a terminal

 private:
  std::string what_, unit_;
  std::chrono::steady_clock::time_point start_;
  double last_ = 0.0;
  bool shown_ = false;
};

/// An options value that steers a library query to a person watching: progress of `unit` on stderr
/// (Progress) and the query's lines prefixed by `command`.
struct CommandProgress {
  std::function<void(size_t, size_t)> progress;
  std::function<void(const std::string&)> log;
};
[[nodiscard]] CommandProgress command_progress(const std::string& command, const std::string& unit);

/// The whole text of the input file `path` given with `option` (--points, --rays, --motion); "-"
/// reads standard input. BadInput (exit 2) "OPTION PATH: PROBLEM" when it is missing, a directory or
/// cannot be read (nurbs/io/input_file.h).
[[nodiscard]] std::string read_input_text(const std::string& path, const std::string& option);

/// The points of the file `path` given with `option` (a scan or a list of points, any format of
/// nurbs/io/point_cloud.h; "-" reads standard input). BadInput (exit 2) "OPTION PATH: ..." for a
/// file that cannot be read or is malformed.
[[nodiscard]] nurbs::io::PointCloud read_points_file(const std::string& path, const std::string& option, double limit);

/// Before a command's work: BadInput (exit 2) naming `option` unless `path` can be written
/// (nurbs::io::check_writable). Empty `path`: nothing to check.
void check_output(const std::string& path, const std::string& option);

/// `text` appended to a CSV row as one quoted field (quotes doubled).
void append_csv_quoted(fmt::memory_buffer& buf, std::string_view text);

/// Writes `header` then `rows` lines to `path` (nurbs::io::write_file: a temporary file renamed),
/// line k formatted by row(buffer, k): the rows formatted in contiguous shares on every hardware
/// thread, written in order (the same file as one thread makes).
void write_rows(const std::string& path, std::string_view header, size_t rows,
                const std::function<void(fmt::memory_buffer&, size_t)>& row);

/// Prints a command's one JSON object on stdout, and notes that it did: an error raised after it
/// is reported as text only (stdout keeps one object).
void print_json(const nlohmann::json& j);
/// print_json of j with j[key] the array of element(0) .. element(count - 1), each built and written
/// in turn (the same text as one tree holding them all, without holding them: a batch of 20,000
/// answers as one tree costs more than the query).
void print_json_streamed(nlohmann::json j, const std::string& key, size_t count,
                         const std::function<nlohmann::json(size_t)>& element);
[[nodiscard]] bool json_printed();

/// The subcommand names closest to `word` (edit distance at most 2, or `word` a prefix), for a
/// did-you-mean.
[[nodiscard]] std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& names);

/// The model's length unit as text (nurbs::unit_name): what the distances a command prints are in.
using nurbs::unit_name;

}  // namespace cli
