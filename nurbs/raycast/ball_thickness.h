#pragma once
/// \file ball_thickness.h
/// Rolling-ball wall thickness beside the ray thickness (beyond Lemasson et al.): at a
/// surface sample p with unit inward normal n, the diameter of the largest ball tangent to the
/// surface at p on the material side with no surface point inside it. A ray along n measures the
/// chord to the opposite wall; the ball also feels walls beside the ray (a wedge, a rib meeting a
/// plate at an angle, a fillet's neighbourhood), so 2 r <= the ray thickness at every sample.
///
/// Shrinking ball (Ma, Bae, Choi and Rossignac, "3D medial axis point approximation using nearest
/// neighbors and the normal field", 2012), all samples in one batch per round:
///   r_0 = half the ray thickness (the ball through p and the ray's hit), or `max_radius`;
///   c = p + r n; q = the closest surface point to c (a batched point-distance query, e.g.
///   queries::PointBatch, Krishnamurthy et al.; its bound b);
///   if none is nearer than r - tolerance - b, or |c - q| >= r - (b + tolerance): the ball is empty
///   up to the query's accuracy, stop;
///   else r = |q - p|^2 / (2 n . (q - p)), the ball tangent at p through q (q lies inside the
///   current ball, so n . (q - p) > 0 and the new r is smaller), and repeat.
/// A round's queries are the still-shrinking samples only.
///
/// Bound (first order, per sample, on the diameter): 2 (2 b + tolerance + e). At the stop no
/// surface point is nearer to c than r - 2 b - tolerance (the query's bound on both sides); e is
/// what the last shrinking q moves r by: q is a grid triangle point, the surface within b of it,
/// and r = rho(q) = |q - p|^2 / (2 n . (q - p)) has |grad rho| = 2 r^2 / |q - p|^2 (1/2 for a wall
/// straight across, large where q comes close to p), so e = b 2 r^2 / |q - p|^2. A ball never
/// shrunk (the ray's hit, an exact face point, bounds it) has e = 0. A stated allowance, not a
/// proof: the shell between r - 2 b - tolerance and r near p is not searched.
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

namespace nurbs::ray {

/// The closest surface point to a query point, with its bounds (|distance - true| <= bound,
/// |point - true closest point| <= point_bound); found = false: none nearer than the `within`
/// asked for, up to `bound` (which is then set too).
struct NearestPoint {
  bool found = false;
  double distance = 0.0;
  glm::dvec3 point{0.0};
  double bound = 0.0, point_bound = 0.0;
  int face = -1;
};

/// Closest points of many query points at once (one batch per shrinking round). Only a point
/// nearer than within[i] matters: the function may answer found = false when there is none (a
/// query that prunes by it, queries::PointBatch's `within`, need not visit the many cells that lie
/// about r from a centre on the medial axis, e.g. every cell of a sphere from its centre), or the
/// closest point anyway.
using NearestFn =
    std::function<std::vector<NearestPoint>(const std::vector<glm::dvec3>& points, const std::vector<double>& within)>;

struct BallOptions {
  double tolerance = 0.0;   ///< model units added to the query's bound in the stopping test (> 0)
  double max_radius = 0.0;  ///< start where a sample has no ray thickness (e.g. the model size)
  int max_rounds = 40;
};

struct BallThickness {
  double thickness = -1.0;  ///< 2 r; -1 where the sample had no start radius
  double bound = 0.0;       ///< on the thickness, see the file comment
  int rounds = 0;           ///< queries this sample needed
  bool converged = false;   ///< stopped by the emptiness test (not by max_rounds or a degenerate step)
  glm::dvec3 contact{0.0};  ///< the last closest point (the opposite wall, or p itself when nothing shrank it)
  int contact_face = -1;
};

struct BallFigures {
  int rounds = 0;         ///< batches
  long long queries = 0;  ///< point queries over all rounds
  long long unconverged = 0;
};

/// Ball thickness of every sample: points, unit inward normals and start radii (half the ray
/// thickness; <= 0: options.max_radius, and no sample when that is <= 0 too).
[[nodiscard]] std::vector<BallThickness> ball_thickness(const std::vector<glm::dvec3>& points,
                                                        const std::vector<glm::dvec3>& inward,
                                                        const std::vector<double>& start_radius,
                                                        const NearestFn& nearest, const BallOptions& options,
                                                        BallFigures* figures = nullptr);

}  // namespace nurbs::ray
