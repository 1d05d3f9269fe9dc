#include "queries/distance/ball_nearest.h"

namespace queries {

nurbs::ray::NearestFn ball_nearest(PointBatch& batch, bool twin) {
  return [&batch, twin](const std::vector<glm::dvec3>& centres, const std::vector<double>& within) {
    std::vector<double> below(centres.size());
    for (size_t i = 0; i < centres.size(); ++i)
      below[i] = within[i] - batch.model_bound() - 2.0 * batch.slack(centres[i]);
    std::vector<PointDistance> d;
    if (twin) {
      for (size_t i = 0; i < centres.size(); ++i) d.push_back(batch.query_cpu(centres[i], below[i]));
    } else {
      d = batch.query(centres, below);
    }
    std::vector<nurbs::ray::NearestPoint> out;
    out.reserve(d.size());
    for (size_t i = 0; i < d.size(); ++i) {
      const PointDistance& e = d[i];
      const double bound = e.found ? e.bound : batch.model_bound() + 2.0 * batch.slack(centres[i]);
      out.push_back({e.found, e.distance, e.point, bound, e.point_bound, e.face});
    }
    return out;
  };
}

}  // namespace queries
