#pragma once
/// \file thickness_view.h
/// Thickness mode: wall thickness by ray casting (Lemasson et al.) through the library's front door
/// queries::thickness_map on the CPU ray caster, as `nurbsgl thickness` computes it, shown as a mesh
/// of the sample grids coloured by thickness (one vertex per sample, two triangles per grid cell of
/// material samples).
#include <string>
#include <vector>

#include "nurbs/model_report.h"
#include "nurbs/triangle_mesh.h"
#include "nurbs/trimmed_surface.h"
#include "viewer/draw_buffers.h"

namespace viewer {

class ThicknessView {
 public:
  /// Casts about `samples` rays over `model` and uploads the coloured mesh.
  void compute(const nurbs::LoadedModel& model, long long samples);
  [[nodiscard]] bool ready() const { return ready_; }
  /// Samples with a hit thinner than `threshold` (model units).
  [[nodiscard]] long long below(double threshold) const;
  /// The q-quantile (0..1) of the hits' thickness (0 without hits).
  [[nodiscard]] double quantile(double q) const;

  MeshBuffers buffers;
  double lo = 0.0, hi = 0.0;  ///< thinnest and thickest hit
  long long rays = 0, hits = 0;
  double seconds = 0.0;
  std::string uncertified;  ///< why the map is not certified (queries::ThicknessMap::failure); empty when it is

 private:
  bool ready_ = false;
  std::vector<float> thickness_;  ///< per hit sample, increasing
};

}  // namespace viewer
