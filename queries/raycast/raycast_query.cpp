#include "queries/raycast/raycast_query.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/surface_eval.h"
#include "nurbs/system_memory.h"

namespace queries {

HitDoubts::HitDoubts(const nurbs::ModelReport& report, bool accept_partial, RayMethod cast)
    : model(report.uncertified_reason(accept_partial)),
      invalid_trim(report.invalid_trim_reason()),
      method(nearest_hits_doubt(cast)) {}

std::string HitDoubts::beyond_model(std::string_view not_certified) const {
  std::string out = invalid_trim.empty() ? std::string() : fmt::format("{}: {}", not_certified, invalid_trim);
  if (!method.empty()) out += (out.empty() ? "" : "; ") + method;
  return out;
}

std::string HitDoubts::failure(std::string_view not_certified) const {
  return model.empty() ? beyond_model(not_certified) : model;
}

void check_engine_request(const RayCasterOptions& caster, bool gpu) {
  if (gpu && caster.method != RayMethod::Bvh) throw nurbs::RequestError("--engine gpu: only --method bvh runs on the GPU");
  if (!gpu && caster.bvh_build == BvhBuild::Gpu) throw nurbs::RequestError("--bvh-build gpu needs --engine gpu");
}

double hit_residual(const nurbs::ray::Scene& scene, const nurbs::ModelReport& report) {
  // A hit counts on a face within the closed test's reach of its loops' polygons, which lie within
  // the flattening tolerance (half that reach) of the trim curves: in space, that far in (u, v) at
  // the surface's largest speed (speed_bounds).
  double outside = 0.0;
  for (size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].loops.empty()) continue;
    const double reach = scene.material->edge_reach[f];
    const glm::dvec2 speed = nurbs::speed_bounds(scene.faces[f].surface);
    outside = std::max(outside, (std::sqrt(2.0) * reach + 0.5 * reach) * (speed.x + speed.y));
  }
  return scene.options.exact_residual * scene.size + report.largest_gap() + outside;
}

Raycast raycast(const nurbs::LoadedModel& model, const std::vector<nurbs::ray::Ray>& rays, double t_min,
                const RaycastOptions& options, gpgpu::Gpu* gpu) {
  check_engine_request(options.caster, options.gpu);
  if (options.gpu && !gpu) throw std::logic_error("raycast: the GPU caster needs a GL context");
  (void)model.checked_size();  // a model no tolerance can refer to is refused before the work
  Raycast out;
  RayCaster caster(nurbs::world_faces(model.model), options.caster, options.gpu ? gpu : nullptr);
  out.method = caster.method();
  out.doubts = HitDoubts(model.report, options.accept_partial, out.method);
  const nurbs::ray::Scene& scene = caster.scene();
  out.scene_faces = scene.faces.size(), out.scene_patches = scene.patches.size(), out.scene_size = scene.size;
  out.hits = caster.cast(rays, t_min, options.progress);
  out.peak_memory = nurbs::peak_resident_memory();
  out.figures = caster.figures();
  for (const nurbs::ray::Hit& h : out.hits) out.hit_count += h.face >= 0 ? 1 : 0;
  out.hit_residual = hit_residual(scene, model.report);
  return out;
}

}  // namespace queries
