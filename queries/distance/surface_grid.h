#pragma once
/// \file surface_grid.h
/// A NURBS surface evaluated on a tensor grid of parameters (Krishnamurthy et al. §2.2): on the GPU
/// into float textures (glsl/surface_eval*.frag), and its CPU twin in double precision. The grid is
/// any nurbs::ParamGrid: uniform, or the knot-aligned piecewise-uniform grid of a tolerance
/// (nurbs/distance/certified_grid.h), whose Filip bound K_e holds on every cell.
///
/// Tiles. A grid larger than the GPU allows (GL_MAX_TEXTURE_SIZE, or a memory budget per tile) is
/// evaluated as tiles of at most TileLimits' side; neighbouring tiles share their boundary samples,
/// so every grid cell lies in exactly one tile. Results are identical to one big texture.
///
/// Float budget of the GPU path (tabulated): basis functions computed in double and rounded to
/// float (relative error 2^-24), control points sent relative to the centre of their box, the
/// (p+1)(q+1)-term sums in float: measured on degrees 1-7 up to about 1.6e-6 of the control box
/// (tests/queries/distance/test_surface_grid.cpp allows 4e-6). The per-fragment method also rounds knots and
/// parameters to float, which adds |S_u| 2^-24 per unit of normalised parameter: large on thin spans.
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/distance/certified_grid.h"
#include "nurbs/surface.h"

namespace queries {

/// A surface uploaded once: knots (R32F, normalised to [0, 1]) and homogeneous control points
/// relative to `origin` (RGBA32F, point (i, j) at index j count_u + i), both laid out row-major in
/// near-square 2D textures (gpgpu/layout.h) so no dimension limits their length.
struct GpuSurface {
  gpgpu::Texture knots_u, knots_v, control;
  int count_u = 0, count_v = 0, degree_u = 0, degree_v = 0;
  nurbs::Interval domain_u, domain_v;
  glm::dvec3 origin{0.0};
  std::vector<double> host_knots_u, host_knots_v;  ///< the knots in double (tabulated basis, CPU side)
};

/// Uploads a valid surface.
GpuSurface upload_surface(const nurbs::Surface& surface, int max_texture_size);

/// How large one tile may be: at most max_side samples per direction (0: GL_MAX_TEXTURE_SIZE) and
/// at most max_bytes for its point and normal textures (32 bytes per sample).
struct TileLimits {
  int max_side = 0;
  long long max_bytes = 256LL << 20;
};

/// The side of the square tiles for these limits on this GPU (at least 2).
[[nodiscard]] int tile_side(const gpgpu::ContextInfo& info, const TileLimits& limits);

/// Pass 1 of EvalMethod::Tabulated for one direction, in double on the CPU: (degree + 1) rows of
/// `samples` texels (N_r(t_i), dN_r/dt(t_i), span, 0), row r first, for the parameters
/// t[first .. first + samples), t normalised to [0, 1] for the derivative (it only orients normals).
/// In double because float knots and parameters cannot resolve thin spans: a knot span 1e-4 of the
/// domain wide has its width known to 6e-4 in float, and the surface crosses it fast (GPU-CPU
/// errors up to 3.7e-4 x size on the C0 random family with float basis functions; the tabulated
/// values are <= 1 and lose nothing).
[[nodiscard]] std::vector<float> tabulate_basis(const std::vector<double>& knots, int degree, int count,
                                                const std::vector<double>& t, int first, int samples,
                                                nurbs::Interval domain);

/// First samples of the tiles along one direction: tiles of `side` samples sharing their boundary
/// sample (0, side - 1, 2 side - 2, ...), the last one shorter.
[[nodiscard]] std::vector<int> tile_starts(int samples, int side);

/// One tile: samples [i0, i0 + width) x [j0, j0 + height) of the grid.
struct GridTile {
  int i0 = 0, j0 = 0;
  gpgpu::Texture points;   ///< RGBA32F (x, y, z, w): w = rational denominator
  gpgpu::Texture normals;  ///< RGBA32F (nx, ny, nz, 0), zero where undefined
};

/// The evaluated grid: sample (i, j) is S(params.u[i], params.v[j]).
struct SurfaceGrid {
  nurbs::ParamGrid params;
  std::vector<GridTile> tiles;  ///< row-major, tiles_u per row
  int tiles_u = 0, tiles_v = 0;
  [[nodiscard]] int n() const { return params.cells_u(); }
  [[nodiscard]] int m() const { return params.cells_v(); }
  /// The whole grid read back, 4 floats per sample, row-major with i fastest.
  [[nodiscard]] std::vector<float> read_points() const;
  [[nodiscard]] std::vector<float> read_normals() const;
};

/// How the GPU evaluates the grid.
enum class EvalMethod {
  /// One pass, all in float on the GPU: every fragment finds its knot spans and runs Cox-de Boor in
  /// u and v (the paper's way). Float knots limit it on thin knot spans (see basis_table in the .cpp).
  PerFragment,
  /// Basis functions tabulated once per grid column and row, in double on the CPU ((n + m)(p + 1)
  /// values, uploaded as two small textures), then each fragment only combines (p+1)(q+1) control
  /// points (surface_eval_tabulated.frag). Faster, and as accurate on every knot vector.
  Tabulated,
};

/// Evaluates on the GPU tile by tile (two render targets each), handing each tile to `visit` and then
/// releasing it: a grid of any size holds one tile of GPU memory at a time. The parameters must lie
/// in the domain.
void evaluate_surface_tiles(gpgpu::Gpu& gpu, const GpuSurface& surface, const nurbs::ParamGrid& params,
                            EvalMethod method, const TileLimits& limits, const std::function<void(GridTile&&)>& visit);

/// Evaluates on the GPU and keeps every tile.
SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& surface, const nurbs::ParamGrid& params,
                             EvalMethod method = EvalMethod::Tabulated, const TileLimits& limits = {});
/// The uniform n x m cell grid over the whole domain.
SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& surface, int n, int m,
                             EvalMethod method = EvalMethod::Tabulated, const TileLimits& limits = {});

/// CPU twin in double: points and unit normals, row-major (i fastest), one per sample.
struct SurfaceGridCpu {
  nurbs::ParamGrid params;
  std::vector<glm::dvec3> points;
  std::vector<glm::dvec3> normals;
};
SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& surface, const nurbs::ParamGrid& params);
SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& surface, int n, int m);

}  // namespace queries
