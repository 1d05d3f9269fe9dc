#pragma once
/// \file raycast_query.h
/// The front door of ray casting a model (Lemasson et al.; the certified mesh method beyond it):
/// the caster built on the CPU or the GPU, the rays cast with progress, and everything that decides
/// whether the hits are certified, in one place: the reader's doubts (faces dropped; a face with an
/// invalid trim may hide or add a hit anywhere; an edge gap widens where a hit near an edge lies,
/// in hit_residual) and the method's (nearest_hits_doubt). The command line and Python take their
/// hits from here.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "queries/raycast/ray_caster.h"

namespace queries {

/// What stands against certifying a caster's hits, for people (each empty where nothing does).
struct HitDoubts {
  std::string model;         ///< ModelReport::uncertified_reason (faces dropped)
  std::string invalid_trim;  ///< ModelReport::invalid_trim_reason
  std::string method;        ///< nearest_hits_doubt of the method cast

  HitDoubts() = default;
  HitDoubts(const nurbs::ModelReport& report, bool accept_partial, RayMethod cast);
  /// The reasons beyond the model's: the invalid trim (after `not_certified`, as "the hits are not
  /// certified") and the method's; empty when nothing but the model's stands.
  [[nodiscard]] std::string beyond_model(std::string_view not_certified) const;
  /// Why the hits are not certified, the model's reason first; empty when they are.
  [[nodiscard]] std::string failure(std::string_view not_certified) const;
};

/// Refuses (nurbs::RequestError) a caster's request the engines cannot run: the GPU pass (`gpu`)
/// with a method other than the BVH, or the BVH built on the GPU without it. The checks of both
/// front doors, raycast and thickness_map.
void check_engine_request(const RayCasterOptions& caster, bool gpu);

/// How far a hit point of `scene`'s caster may lie from the file's faces: the exact step's residual,
/// the largest edge gap the reader found, and how far outside its trim a hit on a face's edge may
/// lie (Scene::is_material_closed: its reach in (u, v) at the surface's speed_bounds).
[[nodiscard]] double hit_residual(const nurbs::ray::Scene& scene, const nurbs::ModelReport& report);

struct RaycastOptions {
  RayCasterOptions caster;      ///< method, threads, bicubic and mesh tolerances, DACRT thresholds, BVH build
  bool gpu = false;             ///< the fragment-shader pass (the BVH method only), else the CPU
  bool accept_partial = false;  ///< hits on a model whose reader dropped faces may be certified
  std::function<void(long long done, long long total)> progress;  ///< called as rays are cast
};

struct Raycast {
  std::vector<nurbs::ray::Hit> hits;  ///< per ray, in input order
  long long hit_count = 0;
  RayMethod method = RayMethod::Mesh;  ///< the method cast (RayCaster::method)
  double hit_residual = 0.0;  ///< hit_residual of the scene and the model
  RayCasterFigures figures;
  size_t scene_faces = 0, scene_patches = 0;
  double scene_size = 0.0;     ///< nurbs::ray::Scene::size: the bicubic tolerance's scale
  long long peak_memory = -1;  ///< the process's peak resident bytes once the last ray was cast
  HitDoubts doubts;

  /// HitDoubts::beyond_model of the hits (the JSON's `uncertified`).
  [[nodiscard]] std::string doubt() const { return doubts.beyond_model("the hits are not certified"); }
  /// Why the hits are not certified, for people; empty when they are.
  [[nodiscard]] std::string failure() const { return doubts.failure("the hits are not certified"); }
};

/// The nearest hits (t > t_min) of `rays` (unit directions) on `model`'s faces. `gpu`: the context
/// of the GPU pass (needed when options.gpu, else may be null). Throws nurbs::RequestError for the
/// GPU without the BVH method, a GPU BVH build without the GPU, or a model whose size no tolerance
/// can refer to (nurbs::checked_model_size).
[[nodiscard]] Raycast raycast(const nurbs::LoadedModel& model, const std::vector<nurbs::ray::Ray>& rays, double t_min,
                              const RaycastOptions& options, gpgpu::Gpu* gpu);

}  // namespace queries
