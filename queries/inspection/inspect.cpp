#include "queries/inspection/inspect.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "nurbs/request_error.h"

namespace queries {
namespace {

/// The rms of `values` under Tukey's biweight at their own reach (best_fit.h, at least 4.685 x
/// `floor`).
double robust_rms(const std::vector<double>& values, double floor) {
  const double reach = tukey_reach(values, floor);
  double sw = 0.0, swe2 = 0.0;
  for (const double v : values) {
    const double w = tukey_weight(v, reach);
    sw += w, swe2 += w * v * v;
  }
  return sw > 0.0 ? std::sqrt(swe2 / sw) : 0.0;
}

}  // namespace

void InspectOptions::check() const {
  for (size_t b = 0; b < within.size(); ++b) {
    if (!(std::isfinite(within[b]) && within[b] > 0.0))
      throw nurbs::RequestError(fmt::format("within: band {:g} is not a positive finite distance", within[b]));
    if (b > 0 && !(within[b] > within[b - 1]))
      throw nurbs::RequestError(
          fmt::format("within: the bands must ascend ({:g} follows {:g})", within[b], within[b - 1]));
  }
  if (!(max_distance > 0.0))
    throw nurbs::RequestError(fmt::format("max_distance: {:g} is not a positive distance", max_distance));
  if (!(std::isfinite(tolerance) && tolerance >= 0.0))
    throw nurbs::RequestError(fmt::format("tolerance: {:g} is not a finite distance of 0 or more", tolerance));
  std::string why;
  if (!rigid_motion(transform, &why)) throw nurbs::RequestError("transform: not a rigid motion: " + why);
  if (align && fit.sample == 0) throw nurbs::RequestError("fit.sample: at least 1 point");
  if (align && fit.max_iterations < 1) throw nurbs::RequestError("fit.max_iterations: at least 1");
}

std::string InspectResult::failure() const {
  std::vector<std::string> parts;
  if (aligned && !alignment.converged) parts.push_back("the best fit failed: " + alignment.problem);
  if (stats.inliers == 0)
    parts.push_back(fmt::format("no point of {} lies within the maximum distance of the model", stats.points));
  if (undecided_points > 0) {
    std::map<std::string, long long> why;
    long long uncertified = 0;
    for (size_t k = 0; k < points.size(); ++k)
      if (!outlier[k] && answers.answers[k].found && !answers.reasons[k].empty())
        ++why[answers.reasons[k]], ++uncertified;
    std::string line = fmt::format("{} of {} inliers undecided", undecided_points, stats.inliers);
    if (uncertified < undecided_points)
      line += fmt::format(" ({} whose bound straddles a band's limit)", undecided_points - uncertified);
    // The most frequent reasons (ties in their text's order), the rest counted: the CSV names each
    // point's reason.
    std::vector<std::pair<long long, std::string>> ranked;
    for (const auto& [reason, count] : why) ranked.emplace_back(-count, reason);
    std::sort(ranked.begin(), ranked.end());
    constexpr size_t kShown = 4;
    long long rest = 0;
    for (size_t i = 0; i < ranked.size(); ++i) {
      if (i < kShown)
        line += fmt::format("; {} not certified: {}", -ranked[i].first, ranked[i].second);
      else
        rest += -ranked[i].first;
    }
    if (ranked.size() > kShown)
      line += fmt::format("; {} more not certified for {} other reasons", rest, ranked.size() - kShown);
    parts.push_back(line);
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

InspectResult inspect(gpgpu::Gpu& gpu, const nurbs::LoadedModel& model, std::span<const glm::dvec3> scan,
                      const InspectOptions& o, const std::function<void(const std::string&)>& log) {
  o.check();
  if (scan.empty()) throw nurbs::RequestError("scan: no points");
  InspectResult out;
  const double size = model.checked_size();
  out.tolerance = o.tolerance > 0.0 ? o.tolerance : !o.within.empty() ? o.within.front() / 10.0 : 1e-5 * size;
  PointQueryOptions q = o.query;
  q.tolerance = out.tolerance / size;
  q.signed_distance = true;
  std::unique_ptr<PointQuery> query;
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  auto t0 = Clock::now();
  try {
    query = std::make_unique<PointQuery>(gpu, model, q);
    out.signed_values = true;
  } catch (const nurbs::RequestError& e) {
    // Deviations unsigned on a model whose solids the side test cannot use (open shells).
    q.signed_distance = false;
    query = std::make_unique<PointQuery>(gpu, model, q);
    out.unsigned_reason = e.what();
    if (log) log(fmt::format("deviations unsigned: {}", e.what()));
  }
  out.prepare_seconds = seconds(t0);
  t0 = Clock::now();
  out.points.reserve(scan.size());
  for (const glm::dvec3& p : scan) out.points.push_back(apply(o.transform, p));
  out.alignment.matrix = o.transform;
  out.alignment.converged = true;
  if (o.align) {
    BestFitOptions fit = o.fit;
    fit.start = glm::dmat4(1.0);
    fit.max_distance = o.max_distance;
    out.alignment = best_fit(*query, out.points, fit);
    out.aligned = true;
    for (glm::dvec3& p : out.points) p = apply(out.alignment.matrix, p);
    out.alignment.matrix = out.alignment.matrix * o.transform;
    if (log)
      log(fmt::format("best fit: {} rounds, {} points, rms {:.4g}{}", out.alignment.iterations,
                      out.alignment.points_used, out.alignment.rms,
                      out.alignment.converged ? "" : " (" + out.alignment.problem + ")"));
  }
  out.fit_seconds = seconds(t0);
  t0 = Clock::now();
  out.answers = query->query(out.points);
  out.query_seconds = seconds(t0);
  const PointQueryResult& r = out.answers;
  const size_t n = out.points.size(), nb = o.within.size();
  out.deviation.assign(n, std::nan(""));
  out.outlier.assign(n, 0);
  out.verdicts.assign(n * nb, Verdict::NotFound);
  out.bands.resize(nb);
  for (size_t b = 0; b < nb; ++b) out.bands[b].within = o.within[b];
  InspectStatistics& st = out.stats;
  st.points = (long long)n;
  std::vector<double> inlier;
  inlier.reserve(n);
  double sum = 0.0, sum2 = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const PointDistance& d = r.answers[k];
    if (!d.found) {
      ++st.not_found;
      continue;
    }
    const double dev = out.signed_values ? r.signed_distance[k] : d.distance;
    out.deviation[k] = dev;
    if (d.distance > o.max_distance) {
      out.outlier[k] = 1, ++st.outliers;
      for (size_t b = 0; b < nb; ++b) out.verdicts[k * nb + b] = Verdict::Outlier;
      continue;
    }
    inlier.push_back(dev);
    sum += dev, sum2 += dev * dev;
    const bool certified = r.reasons[k].empty();
    bool undecided = !certified;
    for (size_t b = 0; b < nb; ++b) {
      BandVerdicts& band = out.bands[b];
      const double D = band.within, a = std::abs(dev);
      Verdict v = Verdict::Undecided;
      if (certified && a + d.bound <= D) v = Verdict::Within;
      if (certified && a - d.bound > D) v = Verdict::Outside;
      out.verdicts[k * nb + b] = v;
      if (v == Verdict::Within) ++band.certainly_within;
      if (v == Verdict::Outside) ++band.certainly_outside;
      if (v == Verdict::Undecided) ++band.undecided, undecided = true;
      if (a <= D) band.share_within += 1.0;
      if (dev > D) band.share_above += 1.0;
      if (dev < -D) band.share_below += 1.0;
    }
    if (undecided) ++out.undecided_points;
  }
  st.inliers = (long long)inlier.size();
  if (!inlier.empty()) {
    const double m = double(inlier.size());
    st.mean = sum / m;
    st.rms = std::sqrt(sum2 / m);
    st.sigma = std::sqrt(std::max(0.0, sum2 / m - st.mean * st.mean));
    st.min = *std::min_element(inlier.begin(), inlier.end());
    st.max = *std::max_element(inlier.begin(), inlier.end());
    for (size_t i = 0; i < st.percentiles.size(); ++i) {
      const auto at = inlier.begin() + long(std::lround(InspectStatistics::kPercentiles[i] / 100.0 * (m - 1.0)));
      std::nth_element(inlier.begin(), at, inlier.end());
      st.percentiles[i] = *at;
    }
    for (BandVerdicts& band : out.bands) band.share_within /= m, band.share_above /= m, band.share_below /= m;
  }
  if (out.aligned) out.alignment.rms = robust_rms(inlier, out.tolerance);
  return out;
}

}  // namespace queries
