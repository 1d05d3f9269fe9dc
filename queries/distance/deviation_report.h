#pragma once
/// \file deviation_report.h
/// A scan's deviation from its model, as inspection software reports it: per point the deviation
/// (the signed distance when asked, negative inside, else the distance) with its bound, the
/// summary, the share of points within given tolerances (and how many are so certainly, their
/// bound included), and the points coloured by deviation for a PLY.
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "nurbs/triangle_mesh.h"
#include "queries/distance/point_query.h"

namespace queries {

/// The points within one tolerance D (model units) of the model.
struct DeviationBand {
  double within = 0.0;     ///< D
  long long points = 0;    ///< |deviation| <= D
  long long certain = 0;   ///< |deviation| + bound <= D: within D whatever the error
  long long possible = 0;  ///< |deviation| - bound <= D: may be within D
  double share = 0.0;      ///< points / answers found
};

struct DeviationReport {
  bool signed_values = false;
  std::vector<double> deviation;  ///< per point; NaN where no answer was found
  std::vector<double> bound;      ///< per point, the answer's bound (NaN where none)
  long long found = 0;
  double min = 0.0, max = 0.0, mean = 0.0, rms = 0.0;  ///< over the found answers
  std::vector<DeviationBand> bands;                    ///< one per tolerance asked, ascending
};

/// The report of `r`'s answers: signed when r carries signed distances. `within`: tolerances
/// (model units, positive), reported ascending.
[[nodiscard]] DeviationReport deviation_report(const PointQueryResult& r, std::span<const double> within);

/// The colour of a deviation: green within `green` (the first band, or the query's tolerance),
/// then towards red for points outside (positive) and blue inside (negative), full at `full`
/// (the largest |deviation|); grey where none was found.
[[nodiscard]] glm::dvec3 deviation_colour(double deviation, double green, double full);

/// The points as a point cloud (no triangles) coloured by deviation_colour, with the per-point value
/// "deviation" (NaN where none was found), for nurbs::io::write_mesh_file (PLY).
[[nodiscard]] nurbs::TriangleMesh deviation_cloud(std::span<const glm::dvec3> points, const DeviationReport& report,
                                                  double green);
/// The same with the colour scale's end given: full red or blue at |deviation| >= `full`.
[[nodiscard]] nurbs::TriangleMesh deviation_cloud(std::span<const glm::dvec3> points, std::span<const double> deviation,
                                                  double green, double full);

}  // namespace queries
