#include "viewer/thickness_view.h"

#include <algorithm>
#include <chrono>

#include "nurbs/raycast/thickness.h"
#include "queries/raycast/thickness_map.h"

namespace viewer {

void ThicknessView::compute(const nurbs::LoadedModel& model, long long samples) {
  const auto t0 = std::chrono::steady_clock::now();
  queries::ThicknessMapOptions o;  // the CLI's defaults, on the CPU
  o.samples = samples;
  const queries::ThicknessMap m = queries::thickness_map(model, o, nullptr);
  uncertified = m.failure();
  thickness_.clear();
  for (const nurbs::ray::Hit& h : m.hits)
    if (h.face >= 0) thickness_.push_back(static_cast<float>(h.t));
  std::sort(thickness_.begin(), thickness_.end());
  rays = static_cast<long long>(m.rays.rays.size());
  hits = static_cast<long long>(thickness_.size());
  lo = m.lo, hi = m.hi;
  // The shader colours by the scalar (its legend and threshold) and lights both sides.
  std::vector<double> per_vertex;
  const nurbs::TriangleMesh mesh = nurbs::ray::thickness_mesh(m.samples, m.thickness, lo, hi, &per_vertex);
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
