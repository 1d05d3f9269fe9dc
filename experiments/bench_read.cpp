// Read time of model files (IGES, STEP, .bpt) in process: the fastest of N reads of each, with the
// STEP parser's share. Prints one JSON object per file; asserts nothing about speed.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "nurbs/io/read_model.h"
#include "nurbs/io/step_file.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Read time of model files: the fastest of --repeat reads"};
  std::vector<std::string> files;
  int repeat = 5;
  app.add_option("FILES", files, "Model files")->required();
  app.add_option("--repeat", repeat, "Reads of each file")->check(CLI::Range(1, 1000));
  CLI11_PARSE(app, argc, argv);
  for (const std::string& file : files) {
    double best = 1e300, parse = 1e300;
    size_t faces = 0;
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = Clock::now();
      const nurbs::Model m = nurbs::io::read_model(file);
      best = std::min(best, seconds_since(t0));
      faces = 0;
      for (const nurbs::Body& b : m.bodies) faces += b.faces.size();
    }
    nlohmann::json out = {{"file", file}, {"faces", faces}, {"read_seconds", best}};
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (nurbs::io::looks_like_step(text.str())) {
      for (int k = 0; k < repeat; ++k) {
        const auto t0 = Clock::now();
        (void)nurbs::io::parse_step_file(text.str(), file);
        parse = std::min(parse, seconds_since(t0));
      }
      out["parse_seconds"] = parse;
    }
    fmt::print("{}\n", out.dump());
  }
  return 0;
}
