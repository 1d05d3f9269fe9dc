#pragma once
/// \file thickness_map.h
/// The front door of the wall-thickness map (Lemasson et al.): samples on every face, a ray from
/// each along the inward normal (faces oriented by ray parity), the thickness the distance to the
/// nearest valid hit; optionally the rolling-ball thickness of the same samples, the closest points
/// by the batched point query of Krishnamurthy et al. (point_batch.h) with its bounds carried into
/// each ball's. Everything a caller needs decided in one place: the spacing from a sample count
/// (a spacing finer than the most samples refused before the work), the ray caster and its device,
/// the per-sample map, the summary, the reader's doubts (a face with an invalid trim may add or
/// hide a wall anywhere: nothing is certified; an edge gap widens every thickness by the gap) and
/// the method's (nearest_hits_doubt: the BVH and DACRT may miss a wall a ray grazes).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "nurbs/paper_switch.h"
#include "nurbs/raycast/ball_thickness.h"
#include "nurbs/raycast/thickness.h"
#include "queries/engine.h"
#include "queries/raycast/ray_caster.h"
#include "queries/raycast/raycast_query.h"

namespace queries {

/// The most samples a thickness map takes (and the finest spacing, that of this many).
inline constexpr long long kMaxThicknessSamples = 100'000'000;

struct ThicknessMapOptions {
  long long samples = 20000;  ///< about this many samples over the model's area
  double spacing = 0.0;       ///< > 0: the samples' spacing in model units instead
  RayCasterOptions caster;    ///< method, threads, bicubic tolerance, DACRT thresholds, BVH build
  bool gpu = false;           ///< cast on the GPU (the fragment-shader pass, bvh only), else on the CPU
  bool ball = false;          ///< also the rolling-ball thickness of every sample
  double ball_tolerance = 1e-5;  ///< its point query's grids (K_e), relative to the model size
  EngineChoice ball_engine = EngineChoice::Auto;  ///< where its batched descent runs
  double min_wall = 0.0;  ///< > 0: count the samples thinner than this (model units)
  bool accept_partial = false;  ///< a map of a model whose reader dropped faces may be certified
  /// Called as rays are cast: what is cast ("thickness: orientation", "thickness", "thickness:
  /// rolling ball"), done, total.
  std::function<void(const std::string& what, long long done, long long total)> progress;

  /// These options with every setting the paper fixes: the BVH method (§3.2) on the GPU (§3.2-3.4),
  /// its tree built there from Morton keys (§3.2).
  [[nodiscard]] ThicknessMapOptions paper() const;
  [[nodiscard]] static std::vector<nurbs::PaperSwitch> paper_switches();
};

/// The rolling-ball thickness of a map's samples.
struct BallMap {
  std::vector<nurbs::ray::BallThickness> samples;  ///< per thickness ray, in ThicknessRays order
  nurbs::ray::BallFigures figures;
  double prepare_seconds = 0.0, seconds = 0.0, tolerance = 0.0;
  BatchEngine engine = BatchEngine::Gpu;
  long long walks_cut = 0;     ///< queries whose GPU walk ran out of loop budget (searched on the CPU)
  long long cells_tested = 0;  ///< over all rounds
  double gpu_seconds = 0.0, cpu_seconds = 0.0;  ///< the point queries' GPU passes and CPU finishing
};

struct ThicknessMap {
  nurbs::ray::ThicknessSamples samples;
  nurbs::ray::ThicknessRays rays;
  std::vector<nurbs::ray::Hit> hits;         ///< per ray
  nurbs::ray::SampleThickness thickness;     ///< per face and sample, -1 where no ray or no hit
  nurbs::ray::ThicknessSummary summary;      ///< of the hits
  long long hit_count = 0, below_min_wall = 0;
  double lo = 0.0, hi = 0.0;  ///< thinnest and thickest hit
  size_t thinnest = 0;        ///< the ray of the thinnest hit (when hit_count > 0)
  double spacing = 0.0, size = 0.0;
  /// How far a hit may lie from the file's faces: the caster's exact residual plus the largest edge gap.
  double hit_residual = 0.0;
  std::optional<BallMap> ball;
  nurbs::ray::SampleThickness ball_thickness;  ///< per face and sample, as `thickness`
  RayCasterFigures figures;
  size_t scene_faces = 0, scene_patches = 0;
  double scene_size = 0.0;  ///< the ray scene's size (nurbs::ray::Scene::size): the bicubic tolerance's scale
  double orientation_seconds = 0.0, cast_seconds = 0.0, seconds = 0.0;
  long long peak_memory = -1;  ///< the process's peak resident bytes once the last ray was cast
  HitDoubts doubts;

  /// HitDoubts::beyond_model of the thickness (the JSON's `uncertified`).
  [[nodiscard]] std::string doubt() const { return doubts.beyond_model("the thickness is not certified"); }
  /// Why the map is not certified, for people; empty when it is.
  [[nodiscard]] std::string failure() const { return doubts.failure("the thickness is not certified"); }
};

/// The thickness map of `model`. `gpu`: the context of the GPU caster and of the ball's point query
/// (needed when options.gpu or options.ball; else may be null). Throws nurbs::RequestError for a
/// spacing finer than kMaxThicknessSamples allows, or the GPU without the BVH method (or a GPU BVH
/// build without the GPU).
[[nodiscard]] ThicknessMap thickness_map(const nurbs::LoadedModel& model, const ThicknessMapOptions& options,
                                         gpgpu::Gpu* gpu);

/// The rolling-ball thickness of `rays` (from half of each ray's thickness in `hits`; the model size
/// where the ray missed) with the batched point query at `tolerance` (model units) on `gpu`.
[[nodiscard]] BallMap ball_map(gpgpu::Gpu& gpu, const nurbs::Model& model, const nurbs::ray::ThicknessRays& rays,
                               const std::vector<nurbs::ray::Hit>& hits, double size, double tolerance,
                               EngineChoice engine,
                               const std::function<void(long long done, long long total)>& progress = {});

}  // namespace queries
