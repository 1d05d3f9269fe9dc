#pragma once
/// \file coherent_eval.h
/// §8 "Evaluation" of Balázs, Guthe and Klein (WSCG 2004): surface points and unit normals at the
/// mesh vertices by direct evaluation of Eq. 1,
///   S(a, b) = Σ_i B_u,i(a) Σ_j B_v,j(b) P_ij   (homogeneous P^w_ij for rational surfaces),
/// exploiting the (v, u) lexicographic order of the vertices: when v repeats, its basis functions
/// (and first derivatives) are reused; when in addition the u span repeats, so are the inner sums
/// Σ_j B_v,j(b) P_ij, leaving O(d_u^2) work per vertex (and a repeated u keeps its basis too). When d_u > d_v the roles
/// of u and v are swapped (the paper's reparametrisation u' = v, v' = -u; here the derivatives are mapped back, so the
/// normal keeps the Su x Sv orientation) and the points are visited in (u, v) order.
///
/// Normals at degenerate points (a pole of a sphere, where Su or Sv vanishes): the limit used by
/// nurbs::surface_normal (±Suv x Sv or ±Su x Suv, the Taylor step from inside the domain); if that
/// vanishes too, the normal at a point moved towards the domain centre by 1e-7, 1e-6, ... of the
/// domain size (a finite, continuous stand-in for the limit). A vertex never gets a NaN normal.
#include <cstddef>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "nurbs/surface.h"

namespace nurbs::tess {

/// How much work coherent evaluation saved.
struct CoherentStats {
  std::size_t points = 0;
  std::size_t slow_basis = 0;  ///< basis evaluations in the slow (outer) direction: new v values
  std::size_t inner_sums = 0;  ///< inner-sum rebuilds: a new v or a new u span
  bool swapped = false;        ///< d_u > d_v: u was the slow direction
};

/// S and the unit normal (oriented like Su x Sv) at every uv[k], written to position[k] and
/// normal[k] (resized). Any order is accepted; the saving needs (v, u) lexicographic order (or
/// (u, v) when d_u > d_v); other orders are sorted internally by index. (u, v) are clamped to the
/// domain. Matches nurbs::surface_point / surface_normal up to roundoff.
void evaluate_coherent(const Surface& s, const std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& position,
                       std::vector<glm::dvec3>& normal, CoherentStats* stats = nullptr);

/// The same results by plain per-point evaluation of Eq. 1 (every basis function and inner sum
/// recomputed): the baseline of the §8 comparison.
void evaluate_direct(const Surface& s, const std::vector<glm::dvec2>& uv, std::vector<glm::dvec3>& position,
                     std::vector<glm::dvec3>& normal);

}  // namespace nurbs::tess
