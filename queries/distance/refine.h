#pragma once
/// \file refine.h
/// The coarse-to-fine search (beyond the paper; Search::CoarseToFine in prepared_model.h).
/// The GPU search over coarse grids (point_distance.h, clearance.h) returns the cells, or cell
/// pairs, whose lower bound is within its least upper bound. Here, in double on the CPU, those
/// cells are subdivided and pruned again until the answer is proven within the tolerance T:
///  - a cell is a parameter rectangle of one face with the surface evaluated at its four corners;
///    its box is the corners' box grown by its K_e (nurbs::filip_k_rect, Euclidean): the surface
///    over the rectangle lies within K_e of its two triangles (Filip et al.), which lie in the box;
///  - upper bound U: the least distance between material surface points: cell corners, the
///    surface at the closest triangle points' (u, v), and Newton projections from the best pair
///    (alternating between the faces; a Newton point that is trimmed away is pulled back to the
///    last material point on the way, so minima on trim edges are reached). Every U is realised
///    by points that the answer returns;
///  - lower bound of a cell (pair): point-box (box-box) distance, Eqs. (9)-(12) and (13)-(20);
///  - a cell (pair) whose lower bound exceeds U is dropped; one whose lower bound is within T of U is
///    settled (nothing inside can beat U by more than T); the others are split 2 x 2 (in a pair,
///    only the side whose slack is not far below the other's: K_e inside the trim, the cell's
///    extent on a trim edge, where the gap shrinks with the size) and tested again;
///  - rectangles with no material corner that no trim edge crosses are culled (entirely trimmed).
/// Result: distance U with bound U - L, L the least lower bound of the settled cells (pairs), so
/// d* lies in [U - bound, U] and bound <= T unless the search stopped at its pair budget (then
/// meets_tolerance is false and the bound is what was proven). NURBSGL_REFINE_DEBUG=1 prints each
/// round (pairs, U, cells to split, least lower bound) on stderr.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "queries/distance/prepared_model.h"

namespace queries {

/// The outcome of a refinement: the proven interval [distance - bound, distance] and where the
/// distance is realised.
struct Refined {
  bool found = false;  ///< false when every cell was culled (no material)
  double distance = 0.0, bound = 0.0;
  glm::dvec3 point_a{0.0}, point_b{0.0};  ///< exact surface points (point_b: the query point, for points)
  glm::dvec2 uv_a{0.0}, uv_b{0.0};
  int face_a = -1, face_b = -1;
  bool on_trim_edge = false;    ///< a cell of the answer has a trimmed corner or a trim edge crosses it
  bool meets_tolerance = true;  ///< bound <= T (false: stopped at max_pairs)
  int rounds = 0;               ///< subdivision rounds
  long long cells = 0;          ///< cells evaluated (four corners each, shared with the parent)
  long long most_pairs = 0;     ///< the largest set of candidates in a round
  long long start_pairs = 0;    ///< refine_all_pairs: the cell pairs its first round tested
};

struct RefineLimits {
  long long max_pairs = 1LL << 21;  ///< candidates per round before the search stops unproven
  int max_rounds = 60;
};

/// Refines the candidate cells `start` of model `m` for the point p to tolerance T.
Refined refine_point(const PreparedModel& m, const std::vector<FaceCell>& start, const glm::dvec3& p, double tolerance,
                     RefineLimits limits = {});

/// Refines the candidate cell pairs `start` of models a and b (b moved by motion_b) to tolerance T.
Refined refine_pairs(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                     const std::vector<std::pair<FaceCell, FaceCell>>& start, double tolerance,
                     RefineLimits limits = {});

/// The cells of every face's grid of m (its coarse grid with Search::CoarseToFine).
[[nodiscard]] long long grid_cell_count(const PreparedModel& m);

/// The whole search of refine_pairs without a GPU descent before it: every grid cell of a and of b
/// (b moved by motion_b) that may hold material; an upper bound U, the least of `upper` (a known
/// bound on the clearance, e.g. FaceCull::upper; +inf: none) and the distance of two material
/// corners; the cells of each side within U of the other side's box; their pairs whose boxes lie
/// within U, refined to tolerance T. The same answer and bound as the GPU descent followed by
/// refine_pairs (the descent only prunes pairs that cannot hold the closest pair). Its first round
/// costs a box test per pair of the kept cells (Refined::start_pairs): nullopt, before that round,
/// when they number more than `max_start_pairs` (< 0: no limit).
std::optional<Refined> refine_all_pairs(const PreparedModel& a, const PreparedModel& b, const glm::dmat4& motion_b,
                                        double tolerance, double upper, long long max_start_pairs = -1,
                                        RefineLimits limits = {});

}  // namespace queries
