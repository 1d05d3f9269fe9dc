#pragma once
/// \file grid_report.h
/// What the grid of one face achieves for a tolerance: the certified knot-aligned grid
/// (certified_grid.h), how tight its bound is against sampled second derivatives, and, for
/// comparison, the former uniform grid of the same tolerance (one step over the whole domain,
/// K_e = +infinity where it crosses a C^0 knot line).
#include "nurbs/distance/certified_grid.h"

namespace nurbs {

struct FaceGridReport {
  FilipBound bound;  ///< the bounds the grid was chosen by
  CertifiedGrid grid;
  /// K_e of the grid from the bounds / K_e from sampled second derivatives (sampled_bound) on the
  /// same cells: >= 1; how many times the bound overstates the deviation's second-order term.
  double bound_ratio = 1.0;
  int uniform_n = 0, uniform_m = 0;  ///< uniform grid by choose_grid (cells), capped at 4096 x 4096
  double uniform_k_e = 0.0;          ///< its K_e (+infinity on a C^0 surface)
  [[nodiscard]] long long uniform_samples() const { return (uniform_n + 1LL) * (uniform_m + 1LL); }
};

/// The report for a tolerance in model units. with_uniform = false skips the uniform comparison.
[[nodiscard]] FaceGridReport grid_report(const Surface& s, double tolerance, const GridLimits& limits = {},
                                         bool with_uniform = true);

}  // namespace nurbs
