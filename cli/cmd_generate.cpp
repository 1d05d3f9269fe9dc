// `nurbsgl generate NAME -o FILE`: writes one of the generated test models as IGES (our writer),
// e.g. the paper's test pair. No GPU needed.
#include <fmt/format.h>

#include <functional>
#include <map>

#include "cli/commands.h"
#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/io/iges_writer.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_generate_impl {

nurbs::Model single_face(const std::string& name, nurbs::TrimmedSurface face) {
  nurbs::Model m;
  m.source = "nurbsgl generate " + name;
  face.face_id = 0;
  face.name = name;
  m.bodies.push_back(nurbs::Body{name, {std::move(face)}, glm::dmat4(1.0), {}});
  return m;
}

nurbs::TrimmedSurface untrimmed(nurbs::Surface s) {
  nurbs::TrimmedSurface f;
  f.surface = std::move(s);
  return f;
}

}  // namespace cmd_generate_impl

void add_generate(CLI::App& app, const GlobalOptions& /*global*/) {
  using namespace cmd_generate_impl;
  static const std::map<std::string, std::function<nurbs::TrimmedSurface(uint64_t)>> generators{
      {"paper-199x33", [](uint64_t) { return untrimmed(models::wavy_surface_199x33()); }},
      {"paper-100x105", [](uint64_t) { return untrimmed(models::wavy_surface_100x105()); }},
      {"paper-100x105-trimmed", [](uint64_t) { return models::trimmed_wavy_surface_100x105(); }},
      {"sphere", [](uint64_t) { return untrimmed(models::rational_sphere(10.0)); }},
      {"torus", [](uint64_t) { return untrimmed(models::rational_torus(20.0, 5.0)); }},
      {"cylinder", [](uint64_t) { return untrimmed(models::rational_cylinder(10.0, 30.0)); }},
      {"random-trimmed", [](uint64_t seed) { return models::random_trimmed_surface(seed); }},
  };
  std::string names;
  for (const auto& [k, v] : generators) names += (names.empty() ? "" : ", ") + k;
  auto* cmd = app.add_subcommand("generate", "Write a generated test model as IGES: " + names);
  auto name = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto seed = std::make_shared<uint64_t>(1);
  cmd->add_option("NAME", *name, "Model to generate")->required()->check([](const std::string& n) {
    return generators.count(n) ? std::string() : "unknown model '" + n + "'";
  });
  cmd->add_option("-o,--output", *out, "IGES file to write")->required();
  cmd->add_option("--seed", *seed, "Seed of random-trimmed")->capture_default_str();
  cmd->callback([name, out, seed] {
    nurbs::io::write_iges_file(*out, single_face(*name, generators.at(*name)(*seed)));
    fmt::print("wrote {} ({})\n", *out, *name);
  });
}

}  // namespace cli
