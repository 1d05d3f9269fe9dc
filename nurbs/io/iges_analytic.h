#pragma once
/// \file iges_analytic.h
/// IGES 5.3 analytic surfaces as exact rational NURBS: 190 plane, 192 right circular cylinder,
/// 194 right circular cone, 196 sphere, 198 torus (IGES 5.3, the analytic surfaces of the B-rep
/// entities: "Plane Surface Entity (Type 190)" to "Toroidal Surface Entity (Type 198)"), 120 surface
/// of revolution (§4.18) and 122 tabulated cylinder (§4.19), with the exact map from the entity's
/// IGES (u, v) to the NURBS (s, t), which the face's parameter-space trim curves need. Internal to
/// the reader.
///
/// Parametrisations, as OpenCASCADE 7.6 reads and writes them (IGESToBRep_BasicSurface and
/// IGESToBRep_TopoSurface::ParamSurface; GeomToIGES): X = the reference direction made
/// orthogonal to the axis A (form 1; form 0: OpenCASCADE's gp_Ax3(L, A) choice), Y = A x X, angles of
/// 192-198 in degrees, of 120 in radians:
///   190  S(u, v) = L + u X + v Y                                   (X, Y from N and REFDIR)
///   192  S(u, v) = L + R (cos u X + sin u Y) + v A
///   194  S(u, v) = L + (R + v sin a)(cos u X + sin u Y) + v cos a A (a = SANGLE, v along the ruling)
///   196  S(u, v) = C + R cos v (cos u X + sin u Y) + R sin v A
///   198  S(u, v) = C + (R + r cos u)(cos v X - sin v Y) + r sin u A (u minor angle, v major angle)
///   120  S(u, v) = the generatrix point C(u) turned by v about the axis line (right-handed about
///        its start -> end direction), v in [SA, TA]
///   122  S(u, v) = C(t0 + u (t1 - t0)) + v (G - C(t0)), (u, v) in [0, 1]^2, G the generatrix end.
#include <functional>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "nurbs/io/analytic_nurbs.h"
#include "nurbs/io/iges_geometry.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::io {

/// True for the surface types this file converts (120, 122, 190, 192, 194, 196, 198).
bool is_analytic_surface_type(int type);

/// The analytic surface `de` mapped by parent * (its own transform chain), covering the IGES
/// parameter box [box_min, box_max] (192-198, 190: the face's trims; 120: the angles; 122 and the
/// generatrix of 120 always span their whole range). Throws ReadError on malformed data.
AnalyticSurface analytic_surface(IgesGeometry& g, int de, const glm::dmat4& parent, glm::dvec2 box_min,
                                 glm::dvec2 box_max);

/// The whole IGES parameter box of a bounded analytic surface: 120 the generatrix's parameter range
/// x [SA, TA], 122 [0, 1]^2; nullopt for 190-198, whose parameters are unbounded.
std::optional<std::pair<glm::dvec2, glm::dvec2>> analytic_range(IgesGeometry& g, int de);

/// Face hook of the readers of 510 and 144 faces on an analytic surface: `f.loops` hold the
/// parameter curves in IGES (u, v); builds f.surface over their box, grown to `range` when given
/// (a 144 without outer boundary is bounded by its surface's range), and maps every loop into
/// (s, t). Each
/// curve is flattened in (u, v) within 1e-7 of the loops' extent (flatten_curve) and every vertex
/// mapped exactly, so the trims become degree-1 polylines within that flattening tolerance of the
/// exact trims (segments parallel to a parameter axis map exactly); when both directions are
/// linear the control points are mapped instead, which is exact.
void set_analytic_surface(IgesGeometry& g, int de, const glm::dmat4& parent, TrimmedSurface& f,
                          const std::optional<std::pair<glm::dvec2, glm::dvec2>>& range = std::nullopt);

/// One edge use of a 508 loop (IGES 5.3 §4.147): TYPE (0: an edge of a 504 list, 1: a vertex of a
/// 502 list), the list's entry and the index NDX in it, the orientation flag OF (1: the use runs
/// along the edge's model-space curve), and the entries of its K parameter-space curves.
struct LoopEdgeUse {
  int type = 0, list = 0, ndx = 1, of = 1;
  std::vector<int> pcurves;
};

/// The edge uses of the 508 `de`, every field checked as it is read: TYPE 0 or 1, a 504 (edge) or
/// 502 (vertex) list, NDX within the list's count N (`list_size` of the list's entry), OF 0 or 1, K
/// within the parameters left, the parameter-space curves of the curve types (ISOP flags read,
/// not used), nothing after the last use. The first problem throws ReadError naming `de`.
std::vector<LoopEdgeUse> loop_edge_uses(IgesGeometry& g, int de, const std::function<int(int)>& list_size);

/// A 508 loop of a face on a 190 plane `plane_de` (mapped by `parent` as the face), in the plane's
/// IGES (u, v): each edge's model-space curve (504) projected onto the plane, reversed where the
/// edge's orientation flag OF is 0 (disagrees with the curve). Exact (the projection is affine,
/// rational curves keep their weights) and independent of any parameter-space curves, which
/// OpenCASCADE does not write on planes. Vertex-type entries (a loop of one vertex) add nothing.
/// `off_plane`, when given, is raised to the largest distance of the edges' control points from
/// the plane: a bound on how far the edges lie from the loop (curves lie in their control points'
/// hull), model units.
TrimLoop plane_loop(IgesGeometry& g, int plane_de, const glm::dmat4& parent, int loop_de, bool outer,
                    double* off_plane = nullptr);

/// A 108 plane of form 1 (bounded, IGES 5.3 §4.8: A x + B y + C z = D, PTR a closed curve in it) as
/// a face: a bilinear patch over the box of the boundary in an orthonormal frame (e1, e2) of the
/// plane with e1 x e2 along (A, B, C), whose parameters are the frame coordinates, and one outer
/// loop: the boundary curves mapped into the frame (affine: exact, rational curves keep their
/// weights). Mapped by parent * (its transform chain). Throws ReadError for a zero normal, a
/// boundary off the plane (beyond 1e-6 of its size) or a form other than 1.
TrimmedSurface bounded_plane_face(IgesGeometry& g, int de, const glm::dmat4& parent);

}  // namespace nurbs::io
