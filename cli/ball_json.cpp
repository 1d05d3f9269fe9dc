#include "cli/ball_json.h"

#include <algorithm>

namespace cli {

nlohmann::json ball_json(const queries::BallMap& r, const std::vector<nurbs::ray::Hit>& hits, double min_wall) {
  std::vector<double> v;
  long long thinner = 0, below = 0;
  double worst_bound = 0.0;
  for (size_t i = 0; i < r.samples.size(); ++i) {
    const auto& b = r.samples[i];
    if (b.thickness < 0) continue;
    v.push_back(b.thickness);
    worst_bound = std::max(worst_bound, b.bound);
    thinner += hits[i].face >= 0 && b.thickness < hits[i].t - b.bound;
    below += min_wall > 0 && b.thickness < min_wall;
  }
  nlohmann::json j = {{"samples", v.size()},
                      {"thickness", summary_json(nurbs::ray::summarize_thickness(std::move(v)))},
                      {"bound", worst_bound},
                      {"thinner_than_ray", thinner},
                      {"rounds", r.figures.rounds},
                      {"queries", r.figures.queries},
                      {"unconverged", r.figures.unconverged},
                      {"query_tolerance", r.tolerance},
                      {"walks_cut", r.walks_cut},
                      {"engine", queries::engine_name(r.engine)},
                      {"cells_tested", r.cells_tested},
                      {"seconds",
                       {{"prepare", r.prepare_seconds},
                        {"shrink", r.seconds},
                        {"query_gpu", r.gpu_seconds},
                        {"query_cpu", r.cpu_seconds}}}};
  if (min_wall > 0) j["below_min_wall"] = below;
  return j;
}

}  // namespace cli
