#pragma once
/// \file surface_grid.h
/// A NURBS surface evaluated on a uniform (n+1) x (m+1) parameter grid (Krishnamurthy et al. §2.2):
/// on the GPU into float textures (glsl/surface_eval.frag), and its CPU twin in double precision.
/// The grid step follows from a tolerance through the Filip bound (nurbs/filip_bound.h, choose_grid).
///
/// Float budget of the GPU path: knots are normalised to [0, 1] in double before rounding to float
/// (relative error 2^-24), control points are sent relative to the centre of their box, and the
/// basis functions of degree p carry about p rounding errors each. For degrees <= 7 the position
/// error stays below about 20 * 2^-24 ~ 1.2e-6 of the control box; tests allow 1e-5 x model size.
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/surface.h"

namespace queries {

/// A surface uploaded once: knots (R32F rows, normalised to [0, 1]), homogeneous control points
/// relative to `origin` (RGBA32F, count_u x count_v).
struct GpuSurface {
  gpgpu::Texture knots_u, knots_v, control;
  int count_u = 0, count_v = 0, degree_u = 0, degree_v = 0;
  glm::dvec3 origin{0.0};
};

/// Uploads a valid surface. Throws std::invalid_argument when a dimension exceeds GL limits.
GpuSurface upload_surface(const nurbs::Surface& surface, int max_texture_size);

/// The evaluated grid: texel (i, j) is S(u_i, v_j) with u_i = u0 + (u1 - u0) i / n.
struct SurfaceGrid {
  int n = 0, m = 0;        ///< intervals; the textures are (n+1) x (m+1)
  gpgpu::Texture points;   ///< RGBA32F (x, y, z, w): w = rational denominator
  gpgpu::Texture normals;  ///< RGBA32F (nx, ny, nz, 0), zero where undefined
};

/// How the GPU evaluates the grid.
enum class EvalMethod {
  /// One pass; every fragment finds its knot spans and runs Cox-de Boor in u and v.
  PerFragment,
  /// Two passes: basis functions tabulated once per grid column and row (surface_basis.frag),
  /// then each fragment only combines (p+1)(q+1) control points (surface_eval_tabulated.frag).
  Tabulated,
};

/// Evaluates on the GPU (two render targets). n, m >= 1, n + 1 and m + 1 <= max size.
SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& surface, int n, int m,
                             EvalMethod method = EvalMethod::Tabulated);

/// CPU twin in double: points and unit normals, row-major (i fastest), (n+1)(m+1) each.
struct SurfaceGridCpu {
  int n = 0, m = 0;
  std::vector<glm::dvec3> points;
  std::vector<glm::dvec3> normals;
};
SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& surface, int n, int m);

}  // namespace queries
