#pragma once
/// \file best_fit.h
/// Beyond the papers: the best fit of a scan to its model, as inspection software runs it before
/// measuring (a scan comes out of the scanner's frame). Robust point-to-plane ICP on the exact
/// faces: each round the sample's certified closest points (PointQuery) and the faces' outward
/// normals there; the rigid motion minimising the weighted squared distances to those tangent
/// planes (linearised rotation, 6 x 6 normal equations); points farther than `max_distance`
/// rejected and the rest weighted by Tukey's biweight at 4.685 times the residuals' robust scale
/// (1.4826 x their median absolute value), never below the query's tolerance.
#include <cmath>
#include <glm/mat4x4.hpp>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "queries/distance/point_query.h"

namespace queries {

struct BestFitOptions {
  /// Points of the scan the fit iterates on (spread evenly over the scan, in its order).
  size_t sample = 20000;
  int max_iterations = 60;
  /// Points farther than this from the model (model units) are not fitted (fixtures, outliers).
  double max_distance = std::numeric_limits<double>::infinity();
  /// Fit on these faces only (indices into PointQuery::faces(), datum faces); empty: every face.
  std::vector<int> faces;
  /// The motion the fit starts from (scan into model coordinates).
  glm::dmat4 start{1.0};
  /// When the sample's median distance to the model is above a tenth of its size (the scan is far
  /// off), the fit starts with the translation between the model's box centre and the sample's
  /// (between its 2nd and 98th percentiles per axis).
  bool coarse_start = true;
  /// Converged when a round moves no sampled point more than this (model units).
  double step = 0.0;  ///< 0: a thousandth of the query's tolerance
};

struct Alignment {
  glm::dmat4 matrix{1.0};     ///< scan into model coordinates
  double rms = 0.0;           ///< of the fitted points' distances to the model after the fit
  long long points_used = 0;  ///< fitted in the last round (within max_distance, weight > 0)
  int iterations = 0;
  bool converged = false;
  bool coarse_start = false;  ///< the fit began by matching the box centres
  std::string problem;        ///< why it did not converge (empty when it did)
};

/// Tukey's biweight, the fit's robust weight: its reach is 4.685 times the robust scale of
/// `residuals` (1.4826 times the median of their absolute values), at least 4.685 x `floor`.
[[nodiscard]] double tukey_reach(std::vector<double> residuals, double floor);
/// The weight of residual `e` at that reach: (1 - (e / reach)^2)^2 within it, 0 beyond.
[[nodiscard]] inline double tukey_weight(double e, double reach) {
  const double u = e / reach;
  return std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
}

/// `matrix` applied to `p` (a rigid motion: rotation and translation).
[[nodiscard]] glm::dvec3 apply(const glm::dmat4& matrix, const glm::dvec3& p);

/// Whether `m` is a rigid motion (orthonormal rotation of determinant +1 within 1e-6, last row
/// 0 0 0 1); `why` says what is wrong otherwise.
[[nodiscard]] bool rigid_motion(const glm::dmat4& m, std::string* why = nullptr);

/// The best fit of `scan` (scan coordinates) to the model `query` answers for. Throws
/// nurbs::RequestError for bad options (a sample of 0, max_iterations < 1, a face out of range).
[[nodiscard]] Alignment best_fit(PointQuery& query, std::span<const glm::dvec3> scan, const BestFitOptions& options);

}  // namespace queries
