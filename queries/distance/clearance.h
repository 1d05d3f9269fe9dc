#pragma once
/// \file clearance.h
/// Minimum distance between two trimmed NURBS models (Krishnamurthy et al. §5.1-5.3): AABB
/// hierarchies searched level by level on the GPU, the closest triangle pair on the CPU.
///  - Leaves: one box per grid cell of every face of a model's atlas (prepared_model.h), grown by
///    K_e and the float budget; cells with all samples trimmed away are empty (§5.3). Model B's
///    boxes are refitted from its untransformed samples under a rigid motion (glsl/distance/aabb_leaf.frag).
///  - Hierarchy: boxes merged 2x2 into coarser levels up to one root, stored mip-style
///    (glsl/distance/aabb_merge.frag). Over the atlas this covers all faces of a model at once: a
///    hierarchy of the whole object in place of the paper's voxel first stage (§5.4), same pruning.
///  - Descent: from the root pair, the 4x4 child pairs of every surviving pair get the box-box min
///    and max distance (Eqs. 13-20, glsl/distance/aabb_pairs_minmax.frag); a min reduction gives the least
///    upper bound U (ClearanceLimits::upper: from the boxes alone, or also from face samples),
///    pairs with lower bound <= U survive by stream reduction (their records stay on
///    the GPU; one read-back of U and one of the count per level). Pairs per level are recorded
///    (the paper's Fig. 12).
///  - Leaves: the surviving cell pairs are read back; two triangles per cell from the surfaces in
///    double; the closest triangle pair wins (0 when they intersect).
/// Bound: |d - d*| < K_a + K_b (each surface within its K_e of its triangles), K maxed over the
/// surviving cells of each side. With Search::CoarseToFine (refine.h) the candidates are refined
/// until d* is proven in [distance - bound, distance] with bound <= T_a + T_b (the faithful
/// path's K_a + K_b), distance realised by two material surface points.
#include <functional>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <memory>
#include <cmath>
#include <optional>
#include <vector>

#include "gpgpu/gpu.h"
#include "queries/distance/prepared_model.h"

namespace queries {

struct Clearance {
  bool found = false;
  double distance = 0.0;
  double bound = 0.0;                     ///< |distance - true distance| < bound
  glm::dvec3 point_a{0.0}, point_b{0.0};  ///< on the grid triangles; point_b in the moved position
  glm::dvec2 uv_a{0.0}, uv_b{0.0};
  int face_a = -1, face_b = -1;
  std::vector<long long> pairs_per_level;  ///< surviving box pairs after each level (Fig. 12)
  long long leaf_pairs = 0;                ///< cell pairs at the finest level of the GPU search
  // Search::CoarseToFine (refine.h): exact surface points, d* in [distance - bound, distance].
  bool on_trim_edge = false;    ///< a cell of the answer is partly trimmed (the looser §5.3 case)
  bool meets_tolerance = true;  ///< bound <= T (false when the refinement hit its budget)
  int rounds = 0;               ///< subdivision rounds on the CPU
  long long refined_cells = 0;  ///< cells evaluated on the CPU
  long long most_pairs = 0;     ///< largest candidate set of a round
  double refine_seconds = 0.0;  ///< time of the CPU refinement
  long long start_pairs = 0;    ///< clearance_cpu: the cell pairs of its first round
  /// Whether the models meet: a common point of faces face_a and face_b (B moved), found from the
  /// closest pair when the distance is within its bound of zero (intersection.h); false when none
  /// was found (surfaces farther apart than the bound never meet).
  bool intersecting = false;
  glm::dvec3 intersection{0.0};        ///< that point
  double intersection_residual = 0.0;  ///< the distance of the two surface points it joins

  /// Theorem 2 with the other model's closest point as the query point: A's nearest point to
  /// point_b lies within sqrt(4 K d + K^2) of point_a (K = bound, d = distance), and likewise for
  /// B; the paper's "position tolerance" (Fig. 16(b)).
  [[nodiscard]] double point_bound() const { return std::sqrt(4.0 * bound * distance + bound * bound); }
};

/// Texture budget of the faithful descent: a level of more surviving pairs than `chunk_pairs` (or
/// than a 4096^2 target holds children of) runs in chunks (tests shrink it to exercise that path).
struct ClearanceLimits {
  long long chunk_pairs = 4096LL * 4096 / 16;
  /// Texels per reduction pass along each axis for each level's least upper bound (gpgpu/reduce.h):
  /// 2 is the paper's log2 passes; 4 (the default, beyond it) needs half as many.
  int reduce_block = 4;
  /// Texels each level of the stream reduction's count pyramid sums (gpgpu/compact.h): 4, or 16
  /// (the default, beyond it) for half the build passes.
  int compact_fanout = 16;
  /// The least upper bound U of each level: from the box pairs' farthest points (Eqs. 13-16, the
  /// paper's), or also from the distance of a face sample in each node (beyond it: two points of the
  /// faces, a far tighter bound, so fewer pairs survive each level; the same answer). Auto: samples
  /// for the coarse-to-fine search, boxes for the faithful path.
  enum class Upper { Auto, Boxes, Samples };
  Upper upper = Upper::Auto;
  /// A level of the descent whose child pairs number at most this is pruned on the CPU: one
  /// read-back of the pair pass's min/max and records, U and the survivors (lower bound <= U, the
  /// stream reduction's test) computed there, the survivors uploaded. The same pairs survive as
  /// with the GPU passes; it saves the reduction's and the stream reduction's passes, which on
  /// small levels cost more than their data (beyond the paper). 0: every level on the GPU; -1
  /// (auto): 65536 with the coarse-to-fine search, 0 with the faithful path (the paper's passes).
  long long host_pairs = -1;
  /// The descent starts at the finest levels whose node pairs number at most this, with all of
  /// them: the levels above prune little and cost a pair pass, a reduction and a compaction each
  /// (beyond the paper). 1: at the two roots, as the paper (§5.1, the pairs per level of Fig. 12).
  long long start_pairs = 4096;
};

/// Whether the descent bounds U with face samples: ClearanceLimits::upper, Auto resolved for the
/// search (samples with coarse-to-fine, boxes with the faithful path).
[[nodiscard]] bool upper_from_samples(const ClearanceLimits& limits, bool coarse_to_fine);
/// ClearanceLimits::host_pairs, -1 resolved for the search (65536 with coarse-to-fine, 0 with the
/// faithful path).
[[nodiscard]] long long host_pairs_used(const ClearanceLimits& limits, bool coarse_to_fine);

/// Model A's box hierarchy kept between the queries of a motion sequence (A does not move): pass the
/// same cache to every clearance() call; it is built on the first and reused while `a` is the same
/// model and no face filter `faces_a` is given (a filter builds a fresh hierarchy, uncached). It
/// holds GL textures: destroy it before the GPU's context.
class ClearanceCache {
 public:
  ClearanceCache();
  ~ClearanceCache();
  ClearanceCache(const ClearanceCache&) = delete;
  ClearanceCache& operator=(const ClearanceCache&) = delete;
  struct Impl;
  std::unique_ptr<Impl> impl;
};

/// The tolerance each model of a clearance query is prepared at, so that the answer's bound (K_a +
/// K_b, or the coarse-to-fine refinement's, to the sum of both models' tolerances) is within the
/// requested tolerance T: the rule of every answer (bound <= T), as a point query's.
[[nodiscard]] constexpr double clearance_model_tolerance(double tolerance) { return 0.5 * tolerance; }

/// The clearance between model `a` and model `b` moved by `motion_b` (rigid). A model in several
/// atlases (prepare_model) has a hierarchy per atlas; every atlas pair is searched, the least
/// upper bound shared between them, and the leaf pairs of all go to the triangle step.
/// `faces_a` / `faces_b` (optional, one flag per face): only these faces take part, e.g. the faces
/// of the pairs kept by the §5.4 voxel stage (voxel_stage.h); the others get empty leaf boxes.
Clearance clearance(gpgpu::Gpu& gpu, const PreparedModel& a, const PreparedModel& b,
                    const glm::dmat4& motion_b = glm::dmat4(1.0), const std::vector<char>* faces_a = nullptr,
                    const std::vector<char>* faces_b = nullptr, const ClearanceLimits& limits = {},
                    ClearanceCache* cache = nullptr);

/// The clearance of the coarse-to-fine search (Search::CoarseToFine, prepare_geometry: no atlases)
/// without the GPU: the grid cell pairs within an upper bound (`upper`, or one from material
/// corners) refined in double (refine_all_pairs). The same answer and bound as clearance() with the
/// GPU descent; for small models, where the GPU's set-up (a GL context, its programs, the atlases)
/// costs more than the whole search (beyond the paper). nullopt when the first round would test
/// more than `max_start_pairs` cell pairs (< 0: no limit): the GPU descent prunes those faster.
std::optional<Clearance> clearance_cpu(const PreparedModel& a, const PreparedModel& b,
                                       const glm::dmat4& motion_b = glm::dmat4(1.0),
                                       double upper = std::numeric_limits<double>::infinity(),
                                       long long max_start_pairs = -1);

/// The CLI's automatic choice of clearance_cpu: one query of models whose grids hold at most this
/// many cell pairs (grid_cell_count(a) x grid_cell_count(b)), also its budget of first-round pairs:
/// about 40 ms of box tests on two cores, within the GPU's set-up.
inline constexpr long long kCpuClearanceStartPairs = 1LL << 22;

/// Compiles (or loads from Mesa's shader cache) every program that preparing the models' atlases
/// and a query with `limits` use, ahead of their first use: the CLI does it on the GL thread while
/// prepare_pair's geometry threads work (about 2 ms a program on llvmpipe, 25 ms in all).
/// `search`: the models' search (the descent's programs differ with ClearanceLimits::upper's Auto);
/// `trimmed`: whether a face of either model has trim loops (else no trim mask is filled).
/// `geometry_done` (prepare_pair's): once it is true, the reduction's and the stream reduction's
/// programs are left to compile at their first use when the coarse-to-fine search may not need
/// them (ClearanceLimits::host_pairs prunes its small levels on the CPU), rather than delay the
/// atlases.
void compile_clearance_programs(gpgpu::Gpu& gpu, const ClearanceLimits& limits = {},
                                Search search = Search::CoarseToFine, bool trimmed = true,
                                const std::function<bool()>& geometry_done = {});

/// The box hierarchy of atlas `atlas` of m moved by `motion`, as the descent builds it
/// (glsl/distance/aabb_leaf.frag, then aabb_merge.frag up to one root), read back for tests to hold against
/// twins: per level its size and the lo, hi corners (RGBA floats per node; an empty node lo = +inf,
/// hi = -inf), relative to `origin`.
struct HierarchyLevels {
  std::vector<glm::ivec2> size;
  std::vector<std::vector<float>> lo, hi;
};
HierarchyLevels clearance_hierarchy(gpgpu::Gpu& gpu, const PreparedModel& m, size_t atlas, const glm::dmat4& motion,
                                    const glm::dvec3& origin);

/// glsl/distance/aabb_pairs_minmax.frag (boxes only) on the node pairs (xa, ya, xb, yb) of level `la` of A's
/// hierarchy (atlas 0, unmoved) and level `lb` of B's (atlas 0, moved by motion_b), both relative to
/// A's centre, each pair as given (no descent): per pair the (minimum, maximum) distance of its two
/// boxes (Eqs. 13-20), +inf for an empty one.
std::vector<glm::vec2> clearance_pair_bounds(gpgpu::Gpu& gpu, const PreparedModel& a, const PreparedModel& b,
                                             const glm::dmat4& motion_b, int la, int lb,
                                             const std::vector<glm::ivec4>& pairs);

/// Closest points of two triangles in double (0 distance and a common point when they intersect).
double triangle_distance(const glm::dvec3 a[3], const glm::dvec3 b[3], glm::dvec3& pa, glm::dvec3& pb, glm::dvec3& wa,
                         glm::dvec3& wb);

/// Closest points of segments p1q1 and p2q2 in double: their parameters s, t in [0, 1].
double segment_distance(glm::dvec3 p1, glm::dvec3 q1, glm::dvec3 p2, glm::dvec3 q2, double& s, double& t);

/// Closest points of segment pq and triangle `tri` in double: the segment's parameter s in [0, 1]
/// and the triangle point's barycentric coordinates w (0 distance where the segment crosses it).
double segment_triangle_distance(glm::dvec3 p, glm::dvec3 q, const glm::dvec3 tri[3], double& s, glm::dvec3& w);

}  // namespace queries
