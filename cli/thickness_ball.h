#pragma once
/// \file thickness_ball.h
/// `thickness --ball`: the rolling-ball thickness (nurbs/raycast/ball_thickness.h) of the ray
/// samples, the closest points by the batched point query of Krishnamurthy et al.
/// (queries/point_batch.h) on the GPU, its bounds carried into each ball's.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/common.h"
#include "nurbs/model.h"
#include "nurbs/raycast/ball_thickness.h"
#include "nurbs/raycast/thickness.h"

namespace gpgpu {
class Gpu;
}

namespace cli {

/// The JSON of a thickness summary: {"min", "max", "mean", "median"} (-1 when there is none).
inline nlohmann::json summary_json(const nurbs::ray::ThicknessSummary& s) {
  return {{"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"median", s.median}};
}

struct BallArgs {
  bool enabled = false;
  double tolerance = 1e-5;  ///< the point query's grids (K_e), relative to the model size
  std::string engine = "auto";  ///< where the batched descent runs: auto, gpu, cpu (distance --engine)
};

struct BallResult {
  std::vector<nurbs::ray::BallThickness> samples;  ///< per thickness ray, in ThicknessRays order
  nurbs::ray::BallFigures figures;
  double prepare_seconds = 0.0, seconds = 0.0, tolerance = 0.0;
  std::string engine;  ///< the engine used: gpu or cpu
  long long walks_cut = 0;                      ///< queries whose GPU walk ran out of loop budget (searched on the CPU)
  long long cells_tested = 0;                   ///< over all rounds
  double gpu_seconds = 0.0, cpu_seconds = 0.0;  ///< the point queries' GPU passes and CPU finishing
};

/// Starts from half of each ray's thickness (the model size where the ray missed). `gpu` may be
/// null: then a context is started from the global options (exit 3 when none starts).
[[nodiscard]] BallResult ball_thickness(const nurbs::Model& model, const nurbs::ray::ThicknessRays& rays,
                                        const std::vector<nurbs::ray::Hit>& hits, double size, const BallArgs& args,
                                        const GlobalOptions& global, gpgpu::Gpu* gpu);

/// JSON: thickness min / median / mean / max, samples where the ball is thinner than the ray by
/// more than its bound, rounds, queries, unconverged samples, seconds; below_min_wall when given.
[[nodiscard]] nlohmann::json ball_json(const BallResult& r, const std::vector<nurbs::ray::Hit>& hits, double min_wall);

}  // namespace cli
