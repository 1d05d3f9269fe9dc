#include "cli/thickness_ball.h"

#include <algorithm>
#include <chrono>

#include "nurbs/model_ops.h"
#include "queries/ball_nearest.h"
#include "queries/point_query.h"
#include "queries/prepared_model.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace thickness_ball_impl {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace thickness_ball_impl

BallResult ball_thickness(const nurbs::Model& model, const nurbs::ray::ThicknessRays& rays,
                          const std::vector<nurbs::ray::Hit>& hits, double size, const BallArgs& args,
                          const GlobalOptions& global, gpgpu::Gpu* gpu) {
  using namespace thickness_ball_impl;
  BallResult out;
  std::unique_ptr<gpgpu::Gpu> own;
  if (!gpu) {
    own = start_gpu(global);
    gpu = own.get();
  }
  const auto t0 = std::chrono::steady_clock::now();
  out.tolerance = args.tolerance * size;
  const queries::PreparedModel prepared = queries::prepare_model(*gpu, nurbs::world_faces(model), out.tolerance);
  queries::PointBatch batch(*gpu, prepared);
  const queries::BatchEngine engine = queries::choose_engine(
      args.engine == "cpu" ? queries::EngineChoice::Cpu
      : args.engine == "gpu" ? queries::EngineChoice::Gpu : queries::EngineChoice::Auto, *gpu);
  out.engine = queries::engine_name(engine);
  batch.set_engine(engine);
  gpu->finish();
  out.prepare_seconds = since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  std::vector<glm::dvec3> points, inward;
  std::vector<double> start;
  for (size_t r = 0; r < rays.rays.size(); ++r) {
    points.push_back(rays.rays[r].origin);
    inward.push_back(rays.rays[r].direction);
    start.push_back(hits[r].face >= 0 ? 0.5 * hits[r].t : 0.0);
  }
  Progress progress("thickness: rolling ball", "samples");
  const nurbs::ray::NearestFn query = queries::ball_nearest(batch);
  const nurbs::ray::NearestFn nearest = [&](const std::vector<glm::dvec3>& centres, const std::vector<double>& within) {
    progress.update(static_cast<long long>(points.size() - centres.size()), static_cast<long long>(points.size()));
    auto answer = query(centres, within);
    const queries::PointBatchStats& st = batch.stats();
    out.walks_cut += st.cut, out.cells_tested += st.cells_tested;
    out.gpu_seconds += st.gpu_seconds, out.cpu_seconds += st.cpu_seconds;
    return answer;
  };
  nurbs::ray::BallOptions o;
  o.tolerance = 1e-6 * size;
  o.max_radius = size;
  out.samples = nurbs::ray::ball_thickness(points, inward, start, nearest, o, &out.figures);
  progress.update(static_cast<long long>(points.size()), static_cast<long long>(points.size()));
  out.seconds = since(t1);
  return out;
}

nlohmann::json ball_json(const BallResult& r, const std::vector<nurbs::ray::Hit>& hits, double min_wall) {
  using namespace thickness_ball_impl;
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
                      {"engine", r.engine},
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
