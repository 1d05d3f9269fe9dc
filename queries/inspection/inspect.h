#pragma once
/// \file inspect.h
/// The front door of scan inspection (`nurbsgl inspect`, Model.inspect, nurbsgl.dask.inspect): a
/// scan placed into the model's frame (a given rigid motion, then the best fit when asked,
/// best_fit.h), every point's deviation (signed where the model's solids are closed) with its
/// certified bound and the outward normal at its closest point, and per inspection band a verdict
/// that holds whatever the bound: certainly within, certainly outside, or undecided.
#include <array>
#include <functional>
#include <glm/mat4x4.hpp>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "queries/distance/point_query.h"
#include "queries/inspection/best_fit.h"

namespace queries {

struct InspectOptions {
  /// The inspection bands D1 < D2 < ... (model units): a point is within a band when |deviation| <= D.
  std::vector<double> within;
  /// Points farther than this from the model (model units) are outliers: counted, not judged.
  double max_distance = std::numeric_limits<double>::infinity();
  /// The certification tolerance, model units; 0: the smallest band / 10, or 1e-5 of the model size
  /// when there is no band.
  double tolerance = 0.0;
  glm::dmat4 transform{1.0};  ///< scan into model coordinates, applied first (a rigid motion)
  bool align = false;         ///< best fit after `transform` (best_fit.h)
  BestFitOptions fit;         ///< its settings (start, max_distance and step are set by inspect)
  /// The distance query's settings (engine, path, cache, accept_partial); inspect sets its tolerance
  /// and asks for signed distances where the model's solids are closed. A verdict is judged from a
  /// certified answer's bound, whether or not it meets the tolerance.
  PointQueryOptions query;

  /// Throws nurbs::RequestError naming the field for a value the door refuses: a band that is not
  /// positive and finite or not ascending, max_distance not positive, a negative or non-finite
  /// tolerance, a transform that is not a rigid motion, a fit sample of 0.
  void check() const;
};

/// The verdicts of one band over the inliers.
struct BandVerdicts {
  double within = 0.0;              ///< D
  long long certainly_within = 0;   ///< |deviation| + bound <= D
  long long certainly_outside = 0;  ///< |deviation| - bound > D
  long long undecided = 0;          ///< the bound straddles D, or the answer is not certified
  double share_within = 0.0;        ///< |deviation| <= D, of the inliers answered
  double share_above = 0.0;         ///< deviation > D
  double share_below = 0.0;         ///< deviation < -D
};

struct InspectStatistics {
  long long points = 0;                                             ///< in the scan
  long long inliers = 0;                                            ///< answered within max_distance
  long long outliers = 0;                                           ///< answered beyond it
  long long not_found = 0;                                          ///< no answer
  double min = 0.0, max = 0.0, mean = 0.0, sigma = 0.0, rms = 0.0;  ///< of the inliers' deviations
  /// The inliers' deviations at these percentiles.
  static constexpr std::array<double, 7> kPercentiles{1, 5, 25, 50, 75, 95, 99};
  std::array<double, 7> percentiles{};
};

/// Per point, its verdict in one band.
enum class Verdict : char { Within, Outside, Undecided, Outlier, NotFound };

struct InspectResult {
  std::vector<glm::dvec3> points;  ///< the scan in model coordinates
  /// Per point; answers.signed_distance when signed, answers.normals the outward normal at the
  /// closest point.
  PointQueryResult answers;
  bool signed_values = false;
  std::string unsigned_reason;    ///< why the deviations are unsigned (the model's solids not closed)
  std::vector<double> deviation;  ///< per point: signed distance, or distance (NaN where none)
  std::vector<char> outlier;      ///< per point
  std::vector<Verdict> verdicts;  ///< per point and band: verdicts[k * bands + b]
  bool aligned = false;
  /// The motion applied (transform, or the fit's); with the fit, its rms is that of every inlier's
  /// deviation under the fit's robust weights (Tukey's biweight at their own robust scale).
  Alignment alignment;
  double tolerance = 0.0;  ///< model units
  std::vector<BandVerdicts> bands;
  InspectStatistics stats;
  long long undecided_points = 0;  ///< inliers with a band undecided or an answer not certified
  /// Wall time: preparing the model for the queries, the best fit, the deviations of every point.
  double prepare_seconds = 0.0, fit_seconds = 0.0, query_seconds = 0.0;

  /// Why the inspection is not certain (exit 1), for people: every class counted, the four most
  /// frequent reasons an answer is not certified named (the others counted); empty when every
  /// inlier's verdicts are certain (and the fit, when asked, converged).
  [[nodiscard]] std::string failure() const;
};

/// Inspects `scan` (scan coordinates) against `model`. Throws nurbs::RequestError for refused
/// options (InspectOptions::check) or a model the distance query refuses. `progress`: lines for people.
[[nodiscard]] InspectResult inspect(gpgpu::Gpu& gpu, const nurbs::LoadedModel& model, std::span<const glm::dvec3> scan,
                                    const InspectOptions& options,
                                    const std::function<void(const std::string&)>& log = nullptr);

}  // namespace queries
