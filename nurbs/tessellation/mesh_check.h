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
  int samples = 48;                 ///< per face, a samples x samples (u, v) grid (material points kept)
  double boundary_tolerance = 0.0;  ///< 3D chord accuracy of the face boundary polylines; 0 = 1e-6 x size
  int threads = 0;                  ///< 0 = all hardware threads
};

struct Deviation {
  double surface_to_mesh = 0.0;  ///< max over face samples of the distance to the mesh
  double mesh_to_surface = 0.0;  ///< max over mesh samples of the distance to the faces (an upper bound)
  int worst_face = -1;           ///< face of the worst surface sample
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

}  // namespace nurbs::tess
