#pragma once
/// \file point_batch_fixtures.h
/// Inputs shared by the batched point projection's tests (test_point_batch*.cpp).
#include <glm/common.hpp>
#include <vector>

#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trimmed_surface.h"

namespace test {

/// A few random faces side by side (trimmed and not), and random points around them (fixed seed):
/// a quarter of them on the surfaces, the rest in the box grown by half its size.
inline std::vector<nurbs::TrimmedSurface> spread_faces(int count) {
  std::vector<nurbs::TrimmedSurface> faces;
  for (uint64_t seed = 0; seed < uint64_t(count); ++seed) {
    faces.push_back(models::random_trimmed_surface(seed + 7));
    for (auto& p : faces.back().surface.points) p += glm::dvec3(3.0 * double(seed % 3), 3.0 * double(seed / 3), 0.0);
  }
  return faces;
}

inline std::vector<glm::dvec3> random_points(const std::vector<nurbs::TrimmedSurface>& faces, int count,
                                             uint64_t seed) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& f : faces) {
    const nurbs::Box b = nurbs::control_box(f.surface);
    lo = glm::min(lo, b.min), hi = glm::max(hi, b.max);
  }
  const glm::dvec3 pad = 0.5 * (hi - lo);
  models::Random rng(seed);
  std::vector<glm::dvec3> out;
  for (int k = 0; k < count; ++k) {
    if (k % 4 == 0) {  // on a surface
      const nurbs::Surface& s = faces[size_t(k / 4) % faces.size()].surface;
      const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
      out.push_back(nurbs::surface_point(s, rng.uniform(du.min, du.max), rng.uniform(dv.min, dv.max)));
    } else {
      out.emplace_back(rng.uniform(lo.x - pad.x, hi.x + pad.x), rng.uniform(lo.y - pad.y, hi.y + pad.y),
                       rng.uniform(lo.z - pad.z, hi.z + pad.z));
    }
  }
  return out;
}

}  // namespace test
