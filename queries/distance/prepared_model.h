#pragma once
/// \file prepared_model.h
/// A model prepared for distance queries (Krishnamurthy et al. §3-5): every face on its certified
/// grid (K_e <= tolerance on every cell), all faces evaluated in atlases with their trim masks
/// (face_atlas.h), and per atlas slot the growth of its cell boxes: K_e plus the float budget of
/// the GPU samples. Evaluated once; queries reuse it.
#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/trim_classify.h"
#include "nurbs/trimmed_surface.h"
#include "queries/distance/face_atlas.h"

namespace queries {

/// A grid cell of one face: cell (i, j) of faces[face].
struct FaceCell {
  int face = -1, i = 0, j = 0;
};

/// A face whose grid cannot meet the tolerance within the sample limit (prepare_geometry), or too
/// large for an atlas (prepare_atlases): what() names the face. A request to change, not a fault.
class GridLimitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The most grid samples of one face unless a caller says otherwise: a face that needs more for its
/// tolerance is refused (GridLimitError), not evaluated.
inline constexpr long long kDefaultMaxSamples = 1LL << 22;
/// The side of the atlases faces are packed into, texels, where the GL does not say its memory
/// (atlas_side).
inline constexpr int kAtlasSide = 4096;
/// The side of the atlases on this GPU: the largest power of two within GL_MAX_TEXTURE_SIZE whose
/// atlas (about 64 bytes a texel: samples, normals, masks and indices, the pyramid's boxes) takes
/// at most an eighth of the GPU's memory (ContextInfo::memory_bytes), at least 1024; kAtlasSide,
/// within the texture size, where the memory is not known (a software renderer: host memory, which
/// the preparation's own estimate checks).
[[nodiscard]] int atlas_side(const gpgpu::ContextInfo& info);

/// How a query reaches its tolerance T.
///  - Faithful (the paper): every face on a grid with K_e <= T everywhere; the GPU search ends at
///    cells that already meet T.
///  - CoarseToFine (beyond the paper): every face on a coarse grid (K_e <= the coarse
///    tolerance); the GPU search over it returns the candidate cells (lower bound <= the least upper
///    bound) and only those are subdivided, in double on the CPU (queries/distance/refine.h), pruned again
///    against the improving upper bound, until every surviving cell meets T. Same guarantee.
enum class Search { Faithful, CoarseToFine };

struct PreparedModel {
  double tolerance = 0.0;       ///< T: K_e of the cells the answers come from (model units)
  double grid_tolerance = 0.0;  ///< K_e of the evaluated grids: T (Faithful) or the coarse tolerance
  Search search = Search::Faithful;
  std::vector<nurbs::TrimmedSurface> faces;
  std::vector<nurbs::FilipBound> bounds;
  std::vector<nurbs::CertifiedGrid> grids;
  std::vector<FaceAtlas> atlases;
  std::vector<gpgpu::Texture> grow;  ///< per atlas: RG32F per slot, (K_e + float budget, float budget)
  /// Per atlas: R8, 1 where an edge of the face's trim polygons crosses the cell with lower-left
  /// sample (x, y). Such a cell is not culled even when its four samples are trimmed away: the
  /// paper's §5.3 corner test alone loses material between samples (a thin strip along a trim).
  std::vector<gpgpu::Texture> crossed;
  /// Per face: its trim loops flattened within nurbs::query_flatten_tolerance, for classifying the
  /// closest points the queries find (empty for untrimmed faces).
  std::vector<nurbs::TrimPolygons> trims;
  glm::dvec3 centre{0.0};  ///< centre of the control-point box of all faces
  /// Preparation time: Filip bounds (Bézier extraction and bounds), certified grids and trim
  /// polygons, GPU atlases (evaluation and trim masks).
  double bounds_seconds = 0.0, grids_seconds = 0.0, atlas_seconds = 0.0;

  /// The cell whose lower-left sample is texel (x, y) of atlas `a`, if that texel starts a cell.
  [[nodiscard]] std::optional<FaceCell> cell_at(size_t a, int x, int y) const;
};

/// Prepares `faces` for queries at K_e <= `tolerance` (model units). Throws GridLimitError naming a
/// face that cannot meet it within `max_samples`, or whose grid
/// is larger than an atlas of the GPU's size.
/// The CPU part of prepare_model: bounds, certified grids, trim polygons and centre, no atlases
/// (what the refinement of refine.h and the CPU twins need).
/// `coarse` > 0: the coarse grid tolerance of Search::CoarseToFine (at least `tolerance`) instead of
/// coarse_tolerance(faces, tolerance), e.g. that of the whole model when `faces` are some of it.
PreparedModel prepare_geometry(std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                               long long max_samples = kDefaultMaxSamples, Search search = Search::Faithful,
                               double coarse = 0.0);

/// With Search::CoarseToFine the grids are evaluated at `coarse_tolerance(faces, tolerance)`.
/// Faces go into atlases of at most `atlas_side`^2 texels (and the GPU's texture size), as many
/// as they need; the tests lower it to get several atlases from small models.
PreparedModel prepare_model(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                            long long max_samples = kDefaultMaxSamples, Search search = Search::Faithful, int atlas_side = kAtlasSide);

/// The GPU part of prepare_model for a model from prepare_geometry: the atlases (evaluation,
/// trim masks, growth, crossed cells). Lets a caller prepare two models' geometry on two threads
/// (the GL context stays on one).
void prepare_atlases(gpgpu::Gpu& gpu, PreparedModel& m, int atlas_side = kAtlasSide);

/// The two models of a clearance query: their geometry on two threads, then their atlases on this
/// thread (the GL context's). `meanwhile`, when given, runs on this thread while the geometry
/// threads work (compile_clearance_programs: GL work that needs no model); its argument tells
/// whether both have finished (work that can wait may stop then).
struct PreparedPair {
  PreparedModel a, b;
};
PreparedPair prepare_pair(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> a, std::vector<nurbs::TrimmedSurface> b,
                          double tolerance, Search search, long long max_samples = kDefaultMaxSamples,
                          const std::function<void(const std::function<bool()>& geometry_done)>& meanwhile = {},
                          double coarse_a = 0.0, double coarse_b = 0.0);

/// The grid tolerance of the coarse-to-fine search: the larger of T and 5e-4 of the faces' control
/// box diagonal (grids of a few thousand cells per face on the models at hand).
[[nodiscard]] double coarse_tolerance(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance);

/// The cells of grid g (row-major, cells_u x cells_v, 1 = crossed) that an edge of `trim` meets;
/// edges outside the grid count for the nearest cells.
[[nodiscard]] std::vector<uint8_t> crossed_cells(const nurbs::TrimPolygons& trim, const nurbs::ParamGrid& g);

/// Float budget of one face's GPU samples: the tabulated evaluation's measured error (1.0e-7 of the
/// control box, surface_grid.h) with a factor 10, plus 4 ulp of the largest coordinate (the atlas
/// adds each face's origin back in float).
[[nodiscard]] double float_budget(const nurbs::Surface& s);

}  // namespace queries
