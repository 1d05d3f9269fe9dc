#include "cli/deviation_outputs.h"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <vector>

#include "cli/common.h"

extern char** environ;

namespace cli {
namespace {

std::string python() {
  const char* env = std::getenv("NURBSGL_PYTHON");
  return env && *env ? env : NURBSGL_PYTHON;
}

/// Runs python with `args`; its exit status (127 when it does not start).
int run_python(const std::vector<std::string>& args) {
  std::vector<std::string> all{python()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return 127;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace

void check_histogram_python() {
  if (run_python({"-c", "import matplotlib, numpy"}) != 0)
    throw BadInput(fmt::format("--histogram: {} cannot import matplotlib and numpy (apt install python3-matplotlib "
                               "python3-numpy, or NURBSGL_PYTHON=an interpreter that has them)",
                               python()));
}

void write_histogram(const std::filesystem::path& png, const queries::DeviationReport& report,
                     std::span<const double> within, const std::string& unit) {
  // The deviations go over as raw little-endian doubles in a temporary file beside the PNG.
  const std::filesystem::path data = png.string() + fmt::format(".{}.f64", getpid());
  {
    std::ofstream out(data, std::ios::binary);
    out.write(reinterpret_cast<const char*>(report.deviation.data()),
              std::streamsize(report.deviation.size() * sizeof(double)));
    if (!out) throw BadInput(fmt::format("--histogram {}: cannot write {}", png.string(), data.string()));
  }
  const int status = run_python({"-c", kHistogramScript, data.string(), png.string(), unit,
                                 report.signed_values ? "1" : "0", fmt::format("{}", fmt::join(within, ","))});
  std::error_code ignored;
  std::filesystem::remove(data, ignored);
  if (status != 0)
    throw BadInput(fmt::format("--histogram {}: {} could not draw it (exit {})", png.string(), python(), status));
}

nlohmann::json deviation_json(const queries::DeviationReport& report) {
  nlohmann::json bands = nlohmann::json::array();
  for (const queries::DeviationBand& b : report.bands)
    bands.push_back({{"distance", b.within},
                     {"points", b.points},
                     {"share", b.share},
                     {"certain", b.certain},
                     {"possible", b.possible}});
  return {{"signed", report.signed_values}, {"points", report.found}, {"min", report.min}, {"max", report.max},
          {"mean", report.mean}, {"rms", report.rms}, {"within", bands}};
}

void print_deviation(const queries::DeviationReport& report, const std::string& unit) {
  fmt::print("{}deviation of {} points ({}): min {:.6g}, max {:.6g}, mean {:.6g}, rms {:.6g}\n",
             report.signed_values ? "signed " : "", report.found, unit, report.min, report.max, report.mean,
             report.rms);
  for (const queries::DeviationBand& b : report.bands)
    fmt::print("  within {:g} {}: {} points, {:.2f} % ({} certainly, {} possibly, their bounds included)\n",
               b.within, unit, b.points, 100.0 * b.share, b.certain, b.possible);
}

}  // namespace cli
