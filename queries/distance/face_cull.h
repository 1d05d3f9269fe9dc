#pragma once
/// \file face_cull.h
/// Beyond the paper: the faces of a clearance query that can hold the closest pair, found before
/// any grid is evaluated, so that two models far apart prepare only the faces that face each other.
///  1. An upper bound U on the clearance: the nearest pair of material sample points of the two
///     models (each face's `samples` x `samples` parameter grid, kept where its trim polygons say
///     material, away from them), searched over face pairs in order of their control boxes' distance while that
///     distance is below U, plus a margin for the trim polygons' flattening.
///  2. Every face pair whose control boxes (which hold the faces: convex hull, positive weights)
///     lie farther apart than U is dropped: it cannot hold the closest pair. A face in no kept pair
///     is left out. With several motions of B, a face is kept when some motion keeps it.
/// The clearance over the kept faces equals the clearance over all faces.
#include <cstddef>
#include <glm/mat4x4.hpp>
#include <span>
#include <vector>

#include "nurbs/trimmed_surface.h"

namespace queries {

struct FaceCull {
  std::vector<char> keep_a, keep_b;  ///< one flag per face: 1 = can hold the closest pair
  double upper = 0.0;                ///< U of the last motion (model units), margin included
  size_t pairs = 0;                  ///< face pairs kept, summed over the motions
  [[nodiscard]] size_t kept_a() const;
  [[nodiscard]] size_t kept_b() const;
};

/// The faces of A and of B (moved by each of `motions_b`) that can hold the closest pair.
/// `margin`: added to U (model units): at least the spatial error of classifying a sample by the
/// flattened trim polygons.
[[nodiscard]] FaceCull cull_faces(const std::vector<nurbs::TrimmedSurface>& a,
                                  const std::vector<nurbs::TrimmedSurface>& b, std::span<const glm::dmat4> motions_b,
                                  double margin, int samples = 5);

}  // namespace queries
