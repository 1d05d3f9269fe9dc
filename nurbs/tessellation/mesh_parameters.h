#pragma once
/// \file mesh_parameters.h
/// Face and (u, v) for a mesh that carries none (read from a file: OpenCASCADE's, a CAD exporter's),
/// so that the deviation check (mesh_check.h) can start Newton where our own meshes let it.
#include <vector>

#include "nurbs/triangle_mesh.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

/// Gives a foreign mesh what our own meshes carry for the check: per triangle its face and per corner
/// a (u, v) on the same side of any seam. The centroid's foot comes from Newton (nurbs/surface_project.h)
/// started at the nearest of `grid` x `grid` cell centres per face that are material (never on a seam
/// or a pole, where (u, v) is ambiguous or Newton cannot turn; never in a trimmed-away part, which may
/// lie nearer than the face the point belongs to) and, when it stops on a domain
/// edge, at the opposite edge too (a closed surface's seam); each corner's foot from Newton started at
/// the centroid's, so the corners agree in (u, v) and their midpoints interpolate sensibly. Triangles
/// get their own three vertices (the check needs no topology). Without this, mesh samples start Newton
/// only from the check's coarse grid, and across a seam or on a wavy surface that start lies on the
/// wrong side: mesh_to_surface came out near the grid spacing. The feet only give measure_deviation
/// more starting points, so its bound can only get tighter. A triangle for which no sample is within
/// reach (coordinates near the double range) keeps its corners with face -1 and no (u, v).
[[nodiscard]] TriangleMesh with_face_parameters(const std::vector<TrimmedSurface>& faces, const TriangleMesh& in,
                                                int grid = 64, int threads = 0);

}  // namespace nurbs::tess
