// `nurbsgl info MODEL`: what a model file holds (faces, degrees, control points, trims, box,
// model size, skipped IGES entities). No GPU needed.
#include "cli/commands.h"

#include "nurbs/io/model_summary.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace cli {

void add_info(CLI::App& app, const GlobalOptions& /*global*/) {
  auto* cmd = app.add_subcommand("info", "Describe a model file (.igs/.iges/.bpt): faces, degrees, trims, size");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto per_face = std::make_shared<bool>(false);
  cmd->add_option("MODEL", *path, "Model file")->required();
  cmd->add_flag("--json", *json, "Print one JSON object instead of text");
  cmd->add_flag("--faces", *per_face, "Also list every face");
  cmd->callback([path, json, per_face] {
    const nurbs::Model model = nurbs::io::read_model(*path);
    const nurbs::io::ModelSummary s = nurbs::io::summarize(model);
    const nurbs::Box box = nurbs::model_box(model);
    if (*json) {
      nlohmann::json j = nurbs::io::to_json(s);
      j["sampled_bbox"] = {{"min", {box.min.x, box.min.y, box.min.z}}, {"max", {box.max.x, box.max.y, box.max.z}}};
      j["model_size"] = box.diagonal();
      fmt::print("{}\n", j.dump(2));
      return;
    }
    fmt::print("{}", nurbs::io::to_text(s, *per_face));
    fmt::print("sampled bbox       [{:.6g} {:.6g} {:.6g}] - [{:.6g} {:.6g} {:.6g}]\n", box.min.x, box.min.y, box.min.z,
               box.max.x, box.max.y, box.max.z);
    fmt::print("model size         {:.6g} (diagonal of the sampled bbox; relative tolerances refer to it)\n",
               box.diagonal());
  });
}

}  // namespace cli
