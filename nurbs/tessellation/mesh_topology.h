#pragma once
/// \file mesh_topology.h
/// Edge counts of a triangle mesh whose faces were tessellated separately: vertices closer than a
/// weld tolerance are one point, then each undirected edge is counted by its triangles. An open edge
/// (one triangle) is a crack or the border of an open sheet; a closed solid has none.
#include <map>
#include <vector>

#include "nurbs/triangle_mesh.h"

namespace nurbs::tess {

struct EdgeCounts {
  long long edges = 0;        ///< undirected edges after welding
  long long open = 0;         ///< used by one triangle
  long long nonmanifold = 0;  ///< used by three or more
  long long welded_vertices = 0;
  /// Open edges per face (TriangleMesh::triangle_face of the edge's triangle; face -1 when the mesh
  /// has no faces): where a watertight mesh still has cracks.
  std::map<int, long long> open_by_face;
};

/// Weld: for each vertex, the index of the first earlier vertex within `tol` of it (itself when there
/// is none). Grid hashing with cells of `tol` and the 27 neighbour cells, so pairs across a cell
/// border are found too.
[[nodiscard]] std::vector<int> weld_vertices(const std::vector<glm::dvec3>& positions, double tol);

/// Welds vertices within `weld_tolerance` (absolute; grid hashing, so points closer than the
/// tolerance across a cell border are welded too, by a neighbour search) and counts edges.
[[nodiscard]] EdgeCounts count_edges(const TriangleMesh& mesh, double weld_tolerance);

/// Edge counts of the mesh as indexed (as written to a file: no weld).
[[nodiscard]] EdgeCounts count_edges_as_indexed(const TriangleMesh& mesh);

/// The mesh with vertices within `tol` made one (weld_vertices): the first of each group keeps its
/// position, (u, v), face, colour and value; the group's normals are averaged; triangles whose
/// corners merge are dropped (`collapsed` counts them). What a watertight mesh is written as, so
/// that the file itself shares its boundary vertices.
[[nodiscard]] TriangleMesh weld_mesh(const TriangleMesh& mesh, double tol, long long* collapsed = nullptr);

}  // namespace nurbs::tess
