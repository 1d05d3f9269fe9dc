#pragma once
/// \file mesh_check.h
/// The measured deviation between trimmed faces and a triangle mesh of them (`tessellate --check`):
/// both one-sided distances of the Hausdorff distance, from dense material samples of the faces to the
/// mesh, and from mesh samples (each triangle's corners, edge midpoints and centroid) to the faces. It needs nothing
/// from the tessellation that made the mesh, so it measures OpenCASCADE's meshes the same way.
#include <vector>

#include "nurbs/triangle_mesh.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::tess {

struct DeviationOptions {
  /// Per face, a samples x samples (u, v) grid (material points kept) seeds the mesh samples'
  /// Newton; the surface is measured to the mesh from all of the largest face's (control-box
  /// diagonal) and from a sub-grid as dense in space of a smaller face's (at least 4 x 4).
  int samples = 48;
  double boundary_tolerance = 0.0;  ///< 3D chord accuracy of the face boundary polylines; 0 = 1e-6 x size
  int threads = 0;                  ///< 0 = all hardware threads
};

struct Deviation {
  double surface_to_mesh = 0.0;  ///< max over face samples of the distance to the mesh
  double mesh_to_surface = 0.0;  ///< max over mesh samples of the distance to the faces (an upper bound)
  int worst_face = -1;           ///< face of the worst surface sample
  /// Per face: the largest distance of its samples to the mesh, and of the samples of its triangles
  /// (mesh.triangle_face; none when the mesh does not carry it) to the faces.
  std::vector<double> face_surface_to_mesh, face_mesh_to_surface;
  long long surface_samples = 0, mesh_samples = 0;
  double seconds = 0.0;
  [[nodiscard]] double max() const { return surface_to_mesh > mesh_to_surface ? surface_to_mesh : mesh_to_surface; }
};

/// Measures the deviation of `mesh` from `faces` (world coordinates, as world_faces() gives them).
/// Face samples: the grid's material points and points along every trim curve (exact surface points).
/// Mesh samples go to the nearest face sample, then Newton on that face (nurbs/surface_project.h) and,
/// when the mesh carries (u, v) and faces, on their own face too, kept where the foot is material;
/// the face boundaries as dense 3D polylines cover feet outside the material. Surface samples get
/// their exact distance to the mesh; mesh samples a distance to a true point of the faces (exact
/// where Newton converges, an upper bound elsewhere). The maxima are over the samples, so a peak
/// between samples can be missed by up to the sample spacing times the slope.
[[nodiscard]] Deviation measure_deviation(const std::vector<TrimmedSurface>& faces, const TriangleMesh& mesh,
                                          const DeviationOptions& options = {});

/// Triangles of a face that reach outside its trim, found cheaply (no sampling of the face).
struct OutsideTrim {
  int triangles = 0;      ///< triangles with a sample farther than the given distance outside
  double distance = 0.0;  ///< the farthest such sample's distance to the face's boundary (0: none found)
};

/// Per face (by mesh.triangle_face, triangles with (u, v) of that face at all three corners): the
/// triangles whose centroid or an edge midpoint lies outside its material (the trim loops,
/// flattened within 1e-5 of the domain) and, in space, farther than `distance` from the face's
/// boundary (its trim curves on the surface, within 1e-3 `distance`). Only samples whose (u, v)
/// distance to the loops times the larger first derivative there passes distance / 4 are measured
/// in space, so a mesh within its loops' tolerance costs one point-in-polygon test per sample.
/// `centroids_only`: the centroids alone (a quarter of the work; finds a region the mesh covers
/// wrongly, such as a hole filled, not a triangle that only overhangs its edge).
[[nodiscard]] std::vector<OutsideTrim> triangles_outside_trim(const std::vector<TrimmedSurface>& faces,
                                                              const TriangleMesh& mesh, double distance,
                                                              bool centroids_only = false);

/// Per face (triangles with (u, v) of that face at all three corners): the triangles whose centroid
/// or an edge midpoint lies farther than `distance` from the face's surface, measured from the
/// surface point at the sample's interpolated (u, v) and, where that is over `distance`, from the
/// point Newton reaches from there (project_point: a surface point, so the figure is an upper
/// bound of the sample's distance to the untrimmed surface). Catches triangles that leave the
/// surface (a wrong cell bound, a triangle across a seam or pole) at one evaluation per sample;
/// parts of the face the mesh misses are not seen (measure_deviation's surface samples see them).
/// `extra`, when not empty: per face, what `distance` grows by on that face (a watertight mesh's
/// boundary vertices moved across the file's edge gaps).
[[nodiscard]] std::vector<OutsideTrim> triangles_off_surface(const std::vector<TrimmedSurface>& faces,
                                                             const TriangleMesh& mesh, double distance,
                                                             const std::vector<double>& extra = {});

/// The triangles of face `face` of `mesh` (by triangle_face) as a mesh of their own, vertices
/// renumbered, triangle_face 0: what measure_deviation needs to measure that face alone.
[[nodiscard]] TriangleMesh face_submesh(const TriangleMesh& mesh, int face);

}  // namespace nurbs::tess
