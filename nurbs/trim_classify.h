#pragma once
/// \file trim_classify.h
/// Point-in-trim classification of (u, v) against a face's trim loops (Krishnamurthy et al. §5.3:
/// the CPU reference for the trim texture). Loops are flattened adaptively to polygons within a
/// tolerance, then each loop's winding number is computed exactly on the polygon.
#include <cstddef>
#include <glm/vec2.hpp>
#include <utility>
#include <vector>

#include "nurbs/knot_vector.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs {

/// Polyline through C(u) at parameters chosen by adaptive bisection of each Bézier segment until the
/// curve points at 1/4, 1/2 and 3/4 of every piece lie within `tolerance` (parameter-space units) of
/// the chord (degree-1 polynomial segments are exact). First and last points are C(u_min), C(u_max);
/// consecutive duplicates are dropped.
[[nodiscard]] std::vector<glm::dvec2> flatten_curve(const Curve2& curve, double tolerance);

/// Flattened loops of a face; loop k is closed implicitly (last point joins the first).
struct TrimPolygons {
  std::vector<std::vector<glm::dvec2>> loops;
  std::vector<bool> outer;  ///< copied from TrimLoop::outer
  Interval domain_u, domain_v;
};

/// Flattens every loop (curves concatenated in order, junction duplicates dropped).
[[nodiscard]] TrimPolygons flatten_trim(const TrimmedSurface& face, double tolerance);

/// The (u, v) tolerance the queries flatten a face's loops with: 1e-6 of the narrower side of its
/// domain, so that the polygons stray from the curves by at most 1e-6 of the face's extent along
/// either parameter (1e-6 of the wider side of a domain 59 by 1 lets the polygons stray 6e-5 of
/// the face's extent along the narrow one).
[[nodiscard]] double query_flatten_tolerance(const Surface& s);

/// The (u, v) tolerance a mesh's checks flatten a face's loops with (which samples are material):
/// 1e-7 of the wider side of its domain, far below any eps the tessellation accepts.
[[nodiscard]] double mesh_flatten_tolerance(const Surface& s);

/// Winding number of a closed polygon around p (Sunday's crossing rule: upward edges count +1 when p
/// is strictly left, downward edges -1 when strictly right, half-open in y so a vertex on the ray is
/// counted once). CCW loops give +1 inside.
[[nodiscard]] int winding_number(const std::vector<glm::dvec2>& polygon, glm::dvec2 p);

/// Whether segment ab meets the closed box [lo, hi] (Liang-Barsky clipping).
[[nodiscard]] bool segment_meets_box(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi);

/// Signed area (shoelace): > 0 for counter-clockwise polygons.
[[nodiscard]] double signed_area(const std::vector<glm::dvec2>& polygon);

/// True when (u, v) is material: inside the domain, inside some outer loop (or no outer loops: the
/// domain rectangle is the outer boundary, as for untrimmed faces and IGES 144 faces with only holes)
/// and inside no inner loop. "Inside a loop" = non-zero winding, so mis-oriented loops still classify
/// right; orientation is checked and fixed separately (trim_loops.h). Points within the flattening
/// tolerance of a trim curve may go either way.
[[nodiscard]] bool is_material(const TrimPolygons& trim, glm::dvec2 uv);

/// is_material with the same answer, bit for bit, in far fewer steps: each loop's edges sorted into
/// horizontal bands of its box, so a winding number (Sunday's rule counts only the edges whose
/// half-open v range holds the point) reads only the point's band. For many points of one face
/// (the batched projection, the refinement, the tessellation's trim check).
/// BandedTrim's bands per loop at most (one per 4 edges below that).
inline constexpr int kMaxBands = 4096;

class BandedTrim {
 public:
  BandedTrim() = default;
  explicit BandedTrim(const TrimPolygons& trim);  ///< `trim` must outlive this
  [[nodiscard]] bool is_material(glm::dvec2 uv) const;
  /// Whether an edge of the loops meets the closed box [lo, hi] (reads only the bands of its v range).
  [[nodiscard]] bool meets_box(glm::dvec2 lo, glm::dvec2 hi) const;
  /// The loops' edges meeting the closed box [lo, hi], at most `limit` (each edge once): a box that
  /// one straight edge crosses is cut in two by it.
  [[nodiscard]] std::vector<std::pair<glm::dvec2, glm::dvec2>> edges_in_box(glm::dvec2 lo, glm::dvec2 hi,
                                                                           size_t limit) const;

 private:
  struct Loop {
    double v0 = 0.0, height = 1.0;
    double u0 = 1e300, u1 = -1e300;  ///< the loop's u range
    std::vector<std::vector<int>> bands;  ///< edge indices per band
  };
  [[nodiscard]] int winding(size_t k, glm::dvec2 p) const;
  [[nodiscard]] static size_t band(const Loop& l, double v);
  const TrimPolygons* trim_ = nullptr;
  std::vector<Loop> loops_;
};

/// Distance in (u, v) from p to the nearest edge of the flattened loops (+inf without loops).
[[nodiscard]] double distance_to_loops(const TrimPolygons& trim, glm::dvec2 p);

/// Convenience: flatten_trim + is_material for one point (flatten once for many points instead).
[[nodiscard]] bool is_material(const TrimmedSurface& face, glm::dvec2 uv, double tolerance);

}  // namespace nurbs
