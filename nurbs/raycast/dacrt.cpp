#include "nurbs/raycast/dacrt.h"

#include <algorithm>
#include <glm/common.hpp>
#include <limits>

namespace nurbs::ray {
namespace {

struct Context {
  const Scene& scene;
  const std::vector<Ray>& rays;
  std::vector<Hit>& hits;
  double t_min;
  double pad;  ///< patch boxes grow by this, as build_scene does for the BVH
  DacrtOptions options;
  DacrtStats stats;
};

void box_of(const Context& cx, const std::vector<int>& patches, int b, int e, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(std::numeric_limits<double>::max());
  hi = -lo;
  for (int i = b; i < e; ++i) {
    lo = glm::min(lo, cx.scene.patches[patches[i]].box_min - cx.pad);
    hi = glm::max(hi, cx.scene.patches[patches[i]].box_max + cx.pad);
  }
}

void divide(Context& cx, std::vector<int>& patches, int pb, int pe, std::vector<int>& rays, int rb, int re) {
  if (pe - pb <= cx.options.patch_leaf || re - rb <= cx.options.ray_leaf) {
    for (int r = rb; r < re; ++r)
      for (int p = pb; p < pe; ++p) {
        ++cx.stats.patch_tests;
        test_patches(cx.scene, cx.rays[rays[r]], cx.t_min, patches[p], patches[p], cx.hits[rays[r]]);
      }
    return;
  }
  // Split the patch set at the centroid median along the largest axis of its centroid box.
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  auto centre = [&](int i) { return cx.scene.patches[i].box_min + cx.scene.patches[i].box_max; };
  for (int i = pb; i < pe; ++i) {
    lo = glm::min(lo, centre(patches[i]));
    hi = glm::max(hi, centre(patches[i]));
  }
  const glm::dvec3 ext = hi - lo;
  const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  const int mid = pb + (pe - pb) / 2;
  std::nth_element(patches.begin() + pb, patches.begin() + mid, patches.begin() + pe,
                   [&](int a, int b) { return centre(a)[axis] < centre(b)[axis]; });
  for (const auto& [b, e] : {std::pair{pb, mid}, std::pair{mid, pe}}) {
    glm::dvec3 blo, bhi;
    box_of(cx, patches, b, e, blo, bhi);
    // In-place partition: the rays crossing this half's box (before their current nearest hit) first.
    const auto split = std::partition(rays.begin() + rb, rays.begin() + re, [&](int r) {
      ++cx.stats.box_tests;
      const Ray& ray = cx.rays[r];
      const Hit& h = cx.hits[r];
      const double t_max = h.face >= 0 ? h.t + 2.0 * cx.pad : std::numeric_limits<double>::infinity();
      return ray_box(ray, 1.0 / ray.direction, blo, bhi, cx.t_min, t_max);
    });
    divide(cx, patches, b, e, rays, rb, static_cast<int>(split - rays.begin()));
  }
}

}  // namespace

std::vector<Hit> cast_rays_dacrt(const Scene& scene, const std::vector<Ray>& rays, double t_min,
                                 const DacrtOptions& options, DacrtStats* stats) {
  std::vector<Hit> hits(rays.size());
  Context cx{scene, rays, hits, t_min, 2.0 * scene.options.tolerance * scene.size, options, {}};
  std::vector<int> patch_ids(scene.patches.size()), ray_ids(rays.size());
  for (size_t i = 0; i < patch_ids.size(); ++i) patch_ids[i] = static_cast<int>(i);
  for (size_t i = 0; i < ray_ids.size(); ++i) ray_ids[i] = static_cast<int>(i);
  divide(cx, patch_ids, 0, static_cast<int>(patch_ids.size()), ray_ids, 0, static_cast<int>(ray_ids.size()));
  if (stats) *stats = cx.stats;
  return hits;
}

}  // namespace nurbs::ray
