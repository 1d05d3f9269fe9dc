#include "viewer/thickness_view.h"

#include <algorithm>
#include <chrono>

#include "nurbs/raycast/thickness.h"
#include "queries/ray_caster.h"

namespace viewer {

void ThicknessView::compute(const std::vector<nurbs::TrimmedSurface>& faces, long long samples) {
  const auto t0 = std::chrono::steady_clock::now();
  queries::RayCaster caster(faces, queries::RayCasterOptions{});  // the CLI's defaults, on the CPU
  const nurbs::ray::Scene& scene = caster.scene();
  nurbs::ray::ThicknessOptions o;
  o.spacing = nurbs::ray::spacing_for_samples(scene, samples);
  const nurbs::ray::CastFn cast = [&](const std::vector<nurbs::ray::Ray>& r, double t_min) {
    return caster.cast(r, t_min);
  };
  const nurbs::ray::ThicknessSamples s = nurbs::ray::thickness_samples(scene, o, cast);
  const nurbs::ray::ThicknessRays r = nurbs::ray::thickness_rays(s);
  const std::vector<nurbs::ray::Hit> h = cast(r.rays, o.start_offset * scene.size);

  nurbs::ray::SampleThickness th(s.faces.size());
  for (size_t f = 0; f < s.faces.size(); ++f) th[f].assign(s.faces[f].uv.size(), -1.0);
  thickness_.clear();
  for (size_t k = 0; k < h.size(); ++k) {
    if (h[k].face < 0) continue;
    th[size_t(r.source[k].first)][size_t(r.source[k].second)] = h[k].t;
    thickness_.push_back(static_cast<float>(h[k].t));
  }
  std::sort(thickness_.begin(), thickness_.end());
  rays = static_cast<long long>(r.rays.size());
  hits = static_cast<long long>(thickness_.size());
  lo = thickness_.empty() ? 0.0 : thickness_.front();
  hi = thickness_.empty() ? 0.0 : thickness_.back();
  // The shader colours by the scalar (its legend and threshold) and lights both sides.
  std::vector<double> per_vertex;
  const nurbs::TriangleMesh mesh = nurbs::ray::thickness_mesh(s, th, lo, hi, &per_vertex);
  buffers.upload(mesh, std::vector<float>(per_vertex.begin(), per_vertex.end()));
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ready_ = true;
}

long long ThicknessView::below(double threshold) const {
  return std::lower_bound(thickness_.begin(), thickness_.end(), static_cast<float>(threshold)) - thickness_.begin();
}

double ThicknessView::quantile(double q) const {
  if (thickness_.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::clamp(q, 0.0, 1.0) * double(thickness_.size() - 1));
  return thickness_[k];
}

}  // namespace viewer
