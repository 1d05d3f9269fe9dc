#include "queries/distance/deviation_report.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>

namespace queries {

DeviationReport deviation_report(const PointQueryResult& r, std::span<const double> within) {
  DeviationReport out;
  out.signed_values = !r.signed_distance.empty();
  const size_t n = r.answers.size();
  out.deviation.assign(n, std::nan(""));
  out.bound.assign(n, std::nan(""));
  std::vector<double> bands(within.begin(), within.end());
  std::sort(bands.begin(), bands.end());
  for (const double d : bands) out.bands.push_back({d});
  double sum = 0.0, sum2 = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const PointDistance& a = r.answers[k];
    if (!a.found) continue;
    const double v = out.signed_values ? r.signed_distance[k] : a.distance;
    out.deviation[k] = v, out.bound[k] = a.bound;
    out.min = out.found == 0 ? v : std::min(out.min, v);
    out.max = out.found == 0 ? v : std::max(out.max, v);
    ++out.found;
    sum += v, sum2 += v * v;
    for (DeviationBand& b : out.bands) {
      b.points += std::abs(v) <= b.within;
      b.certain += std::abs(v) + a.bound <= b.within;
      b.possible += std::abs(v) - a.bound <= b.within;
    }
  }
  if (out.found > 0) {
    out.mean = sum / double(out.found);
    out.rms = std::sqrt(sum2 / double(out.found));
    for (DeviationBand& b : out.bands) b.share = double(b.points) / double(out.found);
  }
  return out;
}

glm::dvec3 deviation_colour(double deviation, double green, double full) {
  if (!std::isfinite(deviation)) return {0.5, 0.5, 0.5};
  const double a = std::abs(deviation);
  if (a <= green) return {0.1, 0.75, 0.2};
  // From yellow (outside) or cyan (inside) just beyond the band to red or blue at the largest.
  const double t = full > green ? std::clamp((a - green) / (full - green), 0.0, 1.0) : 1.0;
  if (deviation > 0.0) return glm::mix(glm::dvec3(1.0, 0.9, 0.1), glm::dvec3(0.85, 0.05, 0.05), t);
  return glm::mix(glm::dvec3(0.1, 0.85, 0.9), glm::dvec3(0.05, 0.1, 0.85), t);
}

nurbs::TriangleMesh deviation_cloud(std::span<const glm::dvec3> points, std::span<const double> deviation,
                                    double green, double full) {
  nurbs::TriangleMesh m;
  m.positions.assign(points.begin(), points.end());
  m.colors.reserve(points.size());
  for (const double d : deviation) m.colors.push_back(deviation_colour(d, green, full));
  m.values.assign(deviation.begin(), deviation.end());  // NaN where no answer was found
  m.values_name = "deviation";
  return m;
}

nurbs::TriangleMesh deviation_cloud(std::span<const glm::dvec3> points, const DeviationReport& report,
                                    double green) {
  return deviation_cloud(points, report.deviation, green, std::max(std::abs(report.min), std::abs(report.max)));
}

}  // namespace queries
