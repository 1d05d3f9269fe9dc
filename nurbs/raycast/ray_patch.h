#pragma once
/// \file ray_patch.h
/// Lemasson et al. §3.3: ray / bicubic Bézier patch intersection by Newton iteration on two planes
/// through the ray (after Geimer and Abert 2005), and the final Newton step on the exact NURBS face
/// (beyond the paper) that brings the hit to the true surface.
#include <array>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "nurbs/bezier_eval.h"
#include "nurbs/raycast/bicubic_patches.h"
#include "nurbs/surface.h"

namespace nurbs::ray {

/// A ray: origin and unit direction; hits are at origin + t direction with t > t_min.
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
};

/// Two orthogonal planes P1 = (N1, d1), P2 = (N2, d2) whose intersection is the ray (§3.3):
/// N1, N2 unit, orthogonal to each other and to the direction; d = -N . origin.
struct RayPlanes {
  glm::dvec3 n1{0.0}, n2{0.0};
  double d1 = 0.0, d2 = 0.0;
};
[[nodiscard]] RayPlanes ray_planes(const Ray& ray);

/// The three outcomes of §3.3.
enum class PatchOutcome { NoConvergence, Outside, Converged };

struct PatchHit {
  PatchOutcome outcome = PatchOutcome::NoConvergence;
  glm::dvec2 st{0.0};  ///< local patch parameters in [0, 1]^2 when Converged
  double t = 0.0;      ///< distance along the ray of the patch point
  glm::dvec3 point{0.0};
};

struct RayPatchOptions {
  int iterations = 7;  ///< §3.3: the same count on every thread; 7 suffice
  /// §3.3's 10^4 parametric scale: Newton runs on (U, V) = scale (s, t). It adds float digits on the
  /// GPU; in double it changes nothing but is kept so the twin runs the same arithmetic.
  double param_scale = 1e4;
  /// ε of §3.3 relative to the patch box diagonal: |R(u, v)| > ε = no convergence. After 7 steps
  /// from the control-polyhedron start, double residuals are ~1e-15 of the patch; 1e-7 only rejects
  /// true non-convergence.
  double residual = 1e-7;
  /// Hits with (s, t) up to this far outside [0, 1]^2 still count (neighbours share edges exactly,
  /// so this only guards round-off at shared edges; the exact step and the trim test decide).
  double edge_margin = 1e-7;
};

/// Starting parameters (§3.3): the ray against the control polyhedron (each 3 x 3 cell of the net
/// as two triangles); a crossing in cell (i, j) at local (a, b) starts at ((i + a)/3, (j + b)/3).
/// Writes up to max_out distinct starts (nearest first), or the patch centre when the ray crosses
/// no cell; returns the count.
int initial_guesses(const BicubicPatch& patch, const Ray& ray, glm::dvec2* out, int max_out);

/// Newton (Eq. 3) on R(s, t) = (N1 . S + d1, N2 . S + d2) (Eq. 2) with the Jacobian of Eq. 4, a
/// fixed number of iterations from `start`, classified as no-convergence / outside / converged.
[[nodiscard]] PatchHit newton_patch(const BicubicPatch& patch, const Ray& ray, const RayPlanes& planes,
                                    glm::dvec2 start, const RayPatchOptions& options);

/// Every converged hit of the ray with the patch in front of t_min (one Newton run per start of
/// initial_guesses, up to 4), nearest first, duplicates merged. Returns the count written.
int intersect_patch(const BicubicPatch& patch, const Ray& ray, const RayPatchOptions& options, double t_min,
                    std::array<PatchHit, 4>& out);

/// Whether a surface closes on itself along u (S(u_min, v) = S(u_max, v)) and along v: a Newton
/// step past such an edge of the domain continues on the other side instead of stopping there.
struct Seams {
  bool u = false, v = false;
};
/// The seams of `s`: its two opposite edges of the domain within `tolerance` of each other at nine
/// points along them.
[[nodiscard]] Seams surface_seams(const Surface& s, double tolerance);

/// Result of the final Newton step on the exact face.
struct ExactHit {
  bool ok = false;     ///< residual below tolerance with (u, v) inside the surface domain
  glm::dvec2 uv{0.0};  ///< parameters on the face's surface
  glm::dvec3 point{0.0};
  double t = 0.0;
};

/// Beyond the paper: the same two-plane Newton (Eqs. 2-4) on the exact (rational, any degree)
/// surface, from the face parameters of a bicubic hit, up to `iterations` steps clamped to the
/// domain, stopping when |R| <= 1e-16 size or, with |R| within the tolerance, when a step no
/// longer halves it (the rounding floor; the better of the two points is kept). ok when |R| <= tolerance at the end.
[[nodiscard]] ExactHit refine_on_surface(const Surface& surface, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv,
                                         int iterations, double tolerance, Seams seams = {});
/// The same with the surface's Bézier form (bezier_eval.h: S, Su, Sv in fewer steps, equal up to
/// rounding); an empty form falls back to the surface.
[[nodiscard]] ExactHit refine_on_surface(const BezierForm& form, const Surface& surface, const Ray& ray,
                                         const RayPlanes& planes, glm::dvec2 uv, int iterations, double tolerance,
                                         Seams seams = {});

/// The (u, v) per unit of t of a ray's motion along a surface whose tangents at a point are su,
/// sv: [Su Sv] w = direction in least squares. NaN where the tangents are parallel.
[[nodiscard]] glm::dvec2 uv_rate(const glm::dvec3& su, const glm::dvec3& sv, const glm::dvec3& direction);

/// Beyond the paper: Newton finds one root, and a ray that grazes a face meets it twice close
/// together, where a step from near either may land on the second. At an exact hit `found`: the
/// ray's height over the tangent plane (c s, c = d . N) against the surface's (q s^2 / 2, q its
/// second form along the ray's motion on it) predicts the pair's other root at s = 2 c / q; when
/// that lies before the hit, Newton from there (and from half and 1.5 times as far): the earliest
/// exact root it finds before `found`, ok false when none.
[[nodiscard]] ExactHit earlier_root(const BezierForm& form, const Surface& surface, const Ray& ray,
                                    const RayPlanes& planes, const ExactHit& found, int iterations, double tolerance,
                                    Seams seams = {});

}  // namespace nurbs::ray
