#pragma once
/// \file certified_grid.h
/// Knot-aligned, piecewise-uniform parameter grids whose every cell is within a tolerance of the
/// surface: the grid on which Krishnamurthy et al. §2.2 evaluate a surface, with the Filip
/// bound of Eq. (4) (nurbs/distance/filip_bound.h) applied per cell instead of once with one step.
///
/// Why knot-aligned. Eq. (4) needs the surface C^1 inside a cell. Across a knot line of full
/// multiplicity (piecewise Bézier data from VDA-FS or CATIA, C^0 at every patch line) a uniform grid
/// whose lines miss the knots has cells with no bound at all (K = +infinity). Here the knot lines
/// where the surface is less than C^1 are always grid lines, so every cell is C^1 and K is finite.
///
/// Why piecewise-uniform. Between kept knot lines ("segments") each direction has its own step, so
/// a flat span gets few samples and a curved one many: cell (a, b) of segments a (along u) and b
/// (along v) needs (1/8)(h_a^2 M1_ab + 2 h_a g_b M2_ab + g_b^2 M3_ab) <= tolerance with h_a, g_b the
/// steps and M_ab the bounds of the patches it covers. The counts are chosen to minimise the number
/// of samples (sum n_a + 1)(sum m_b + 1) under all these constraints (see certified_grid()).
#include <string>
#include <vector>

#include "nurbs/distance/filip_bound.h"

namespace nurbs {

/// A tensor grid of sample parameters: sample (i, j) is S(u[i], v[j]); cell (i, j) is
/// [u[i], u[i+1]] x [v[j], v[j+1]]. Both lists increase strictly and start and end at the domain ends.
struct ParamGrid {
  std::vector<double> u, v;
  [[nodiscard]] int cells_u() const { return static_cast<int>(u.size()) - 1; }
  [[nodiscard]] int cells_v() const { return static_cast<int>(v.size()) - 1; }
  [[nodiscard]] long long samples() const {
    return static_cast<long long>(u.size()) * static_cast<long long>(v.size());
  }
  /// The smallest step along either direction.
  [[nodiscard]] double min_step() const;
};

/// The uniform grid of n x m cells over du x dv (sample i at du.min + du.width() i / n, the last one
/// exactly du.max).
[[nodiscard]] ParamGrid uniform_param_grid(Interval du, Interval dv, int n, int m);

/// K (or K_e) of cell (i, j) of the grid: filip_k_rect on its rectangle.
[[nodiscard]] double grid_cell_k(const FilipBound& b, const ParamGrid& g, int i, int j, KNorm norm = KNorm::Component);

/// Max of grid_cell_k over all cells, computed per distinct (step, overlapped patches) group of
/// columns and rows rather than per cell, so a 4096^2 grid costs O(segments^2) here.
[[nodiscard]] double grid_k(const FilipBound& b, const ParamGrid& g, KNorm norm = KNorm::Component);

/// Limits on one face's grid.
struct GridLimits {
  long long max_samples = 1LL << 26;  ///< 64 M samples (2 GiB of RGBA32F points + normals)
};

/// A grid chosen for a tolerance, with what it achieves.
struct CertifiedGrid {
  ParamGrid grid;
  std::vector<double> lines_u, lines_v;  ///< kept knot lines (segment ends, domain ends included)
  std::vector<int> cells_u, cells_v;     ///< cells per segment
  double k = 0.0;                        ///< max per-cell K (paper's per-coordinate bound, grows AABBs)
  double k_e = 0.0;                      ///< max per-cell K_e (Euclidean, certifies distances)
  double tolerance = 0.0;                ///< the K_e asked for
  bool meets_tolerance = false;          ///< k_e <= tolerance
  std::string reason;                    ///< why not, when it does not
};

/// Chooses the knot-aligned grid with the fewest samples whose per-cell K_e (or K, by `norm`) is at
/// most `tolerance` (absolute, model units). Two segmentations are tried and the smaller grid kept:
/// every distinct knot a grid line (each span its own step: adapts to the curvature of each span),
/// or only the knot lines where the surface is not C^1 (fewer forced lines). For each, the counts
/// come from a scan over the share of the tolerance given to the v term, each followed by exact
/// alternating maximisation of the steps (largest h_a for the chosen g_b, then largest g_b for those
/// h_a). When the grid would exceed limits.max_samples, the counts are scaled down to fit and the
/// result says it does not meet the tolerance, and why; likewise for a non-finite bound.
[[nodiscard]] CertifiedGrid certified_grid(const FilipBound& b, double tolerance, const GridLimits& limits = {},
                                           KNorm norm = KNorm::Euclidean);

/// K (or K_e) of every segment pair of a certified grid, row-major (segment a along u fastest): all
/// cells of a pair share their steps, so this is the largest per-cell bound in each. Finite for
/// every grid certified_grid returns (its lines include every non-C^1 knot line); +infinity for a
/// pair crossed by a non-C^1 line (e.g. a uniform grid described as one segment).
[[nodiscard]] std::vector<double> segment_k(const FilipBound& b, const CertifiedGrid& g, KNorm norm = KNorm::Euclidean);

}  // namespace nurbs
