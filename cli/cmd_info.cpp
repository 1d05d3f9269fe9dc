// `nurbsgl info MODEL`: what a model file holds (faces, degrees, control points, trims, box,
// model size, skipped IGES entities). No GPU needed.
#include <chrono>
#include <fmt/format.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli/bounds_report.h"
#include "cli/commands.h"
#include "cli/validators.h"
#include "nurbs/io/model_summary.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"

namespace cli {

void add_info(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand("info", "Describe a model file (.igs/.iges/.stp/.step/.bpt): faces, bodies, degrees, trims, size");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto per_face = std::make_shared<bool>(false);
  auto bounds = std::make_shared<bool>(false);
  auto tolerance = std::make_shared<double>(1e-4);
  cmd->add_option("MODEL", *path, "Model file")->required();
  cmd->add_flag("--bounds", *bounds,
                "Also report per face the Filip bound against sampled second derivatives and the certified grid");
  cmd->add_option("--tolerance", *tolerance, "For --bounds: the grids' K_e, relative to the model size")
      ->check(relative_tolerance())
      ->capture_default_str();
  cmd->add_flag("--json", *json, "Print one JSON object instead of text");
  cmd->add_flag("--faces", *per_face, "Also list every face");
  cmd->callback([&global, path, json, per_face, bounds, tolerance] {
    nurbs::io::IgesReadLog log;
    const auto t0 = std::chrono::steady_clock::now();
    const nurbs::Model model = nurbs::io::read_model(*path, &log);
    const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const nurbs::io::ModelSummary s = nurbs::io::summarize(model);
    const nurbs::ModelReport report = nurbs::model_report(model);
    // A size that no tolerance can refer to (0, or overflowed) is bad input, as queries treat it.
    if (const auto problems = nurbs::validate_model_size(s.size); s.faces > 0 && !problems.empty())
      throw nurbs::io::ReadError(model.source, "", problems.front());
    if (*json) {
      nlohmann::json j = nurbs::io::to_json(s);
      j["reader"] = {{"loops_reoriented", log.reoriented_loops}, {"outer_loops_fixed", log.outer_loops_fixed},
                     {"loops_reordered", log.reordered_loops},
                     {"domain_loops_added", log.domain_loops_added},
                     {"gaps_closed", log.gaps_closed}, {"loops_wrapped", log.loops_wrapped},           {"ranges_restricted", log.ranges_restricted},
                     {"trim_problems", log.trim_problems},       {"faces_dropped", log.warnings},
                     {"seconds", read_seconds}};
      if (*bounds) j["bounds"] = bounds_report(model, *tolerance, false);
      add_model_json(j, report, global);
      print_json(j);
      return;
    }
    fmt::print("{}", nurbs::io::to_text(s, *per_face));
    fmt::print(
        "reader             {} loops reoriented, {} faces whose declared outer loop lay inside another, {} loops with "
        "curves chained again, {} domain loops added, {} trim gaps closed, {} curves/surfaces restricted to their "
        "declared parameter range; read in {:.3f} s\n",
        log.reoriented_loops, log.outer_loops_fixed, log.reordered_loops, log.domain_loops_added, log.gaps_closed, log.ranges_restricted,
        read_seconds);
    fmt::print("trim problems      {}\n", log.trim_problems.size());
    for (size_t i = 0; i < log.trim_problems.size() && i < 20; ++i) fmt::print("  {}\n", log.trim_problems[i]);
    if (log.trim_problems.size() > 20) fmt::print("  ... ({} more; --json lists all)\n", log.trim_problems.size() - 20);
    // Dropped faces and read warnings are in the summary above; the faces kept with doubts here.
    nurbs::ModelReport kept = report;
    kept.dropped.clear(), kept.warnings.clear();
    for (const std::string& line : kept.lines(20)) fmt::print("read               {}\n", line);
    if (*bounds) fmt::print("{}", bounds_text(bounds_report(model, *tolerance, s.faces > 20 && isatty(STDERR_FILENO))));
  });
}

}  // namespace cli
