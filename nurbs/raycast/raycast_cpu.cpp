#include "nurbs/raycast/raycast_cpu.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"

namespace nurbs::ray {

double scene_size(const std::vector<TrimmedSurface>& faces) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& f : faces) {
    const Box b = control_box(f.surface);
    lo = glm::min(lo, b.min);
    hi = glm::max(hi, b.max);
  }
  return faces.empty() ? 0.0 : glm::length(hi - lo);
}

Scene build_scene(std::vector<TrimmedSurface> faces, const SceneOptions& options) {
  Scene scene;
  scene.options = options;
  scene.faces = std::move(faces);
  scene.size = scene_size(scene.faces);
  BicubicOptions bo;
  bo.tolerance = options.tolerance * scene.size;
  bo.max_turn_degrees = options.max_turn_degrees;
  // Faces in parallel (each its own slot), then joined in face order: the same scene on any thread count.
  const size_t n = scene.faces.size();
  scene.trims.resize(n);
  if (options.trim == SceneOptions::Trim::Cubics) scene.cubics.resize(n);
  scene.face_stats.resize(n);
  std::vector<std::vector<BicubicPatch>> patches(n);
  auto forms = std::make_shared<std::vector<BezierForm>>(n);
  scene.seams.resize(n);
  std::vector<double> edge_reach(n);
  parallel_for(n, 0, [&](size_t f, int) {
    const TrimmedSurface& face = scene.faces[f];
    const Interval du = surface_domain_u(face.surface), dv = surface_domain_v(face.surface);
    const double diag = std::hypot(du.max - du.min, dv.max - dv.min);
    edge_reach[f] = 2.0 * options.trim_flatten * diag;
    if (!face.loops.empty()) scene.trims[f] = flatten_trim(face, options.trim_flatten * diag);
    if (options.trim == SceneOptions::Trim::Cubics && !face.loops.empty())
      scene.cubics[f] = trim_cubics(face, options.trim_flatten * diag);
    patches[f] = bicubic_patches(face, static_cast<int>(f), bo, &scene.face_stats[f]);
    (*forms)[f] = BezierForm(face.surface);
    scene.seams[f] = surface_seams(face.surface, options.exact_residual * scene.size);
  });
  scene.forms = std::move(forms);
  std::vector<BicubicPatch> all;
  for (auto& p : patches) all.insert(all.end(), p.begin(), p.end());
  auto material = std::make_shared<SceneMaterial>();
  material->trims = scene.trims;
  material->banded.reserve(material->trims.size());
  for (const TrimPolygons& t : material->trims) material->banded.emplace_back(t);
  material->edge_reach = std::move(edge_reach);
  scene.material = std::move(material);
  std::vector<glm::dvec3> bmin(all.size()), bmax(all.size());
  const glm::dvec3 pad(2.0 * bo.tolerance);  // the exact surface lies within the tolerance of its patch
  for (size_t i = 0; i < all.size(); ++i) {
    bmin[i] = all[i].box_min - pad;
    bmax[i] = all[i].box_max + pad;
  }
  scene.bvh = build_bvh(bmin, bmax);
  scene.patches.reserve(all.size());
  for (int k : scene.bvh.order) scene.patches.push_back(all[k]);
  return scene;
}

void test_patches(const Scene& scene, const Ray& ray, double t_min, int first, int last, Hit& best) {
  const RayPlanes planes = ray_planes(ray);
  for (int k = first; k <= last; ++k) {
    const BicubicPatch& patch = scene.patches[k];
    std::array<PatchHit, 4> hits;
    const int n = intersect_patch(patch, ray, scene.options.patch, t_min, hits);
    for (int h = 0; h < n; ++h) {
      const glm::dvec2 uv(patch.range_u.min + hits[h].st.x * (patch.range_u.max - patch.range_u.min),
                          patch.range_v.min + hits[h].st.y * (patch.range_v.max - patch.range_v.min));
      const TrimmedSurface& face = scene.faces[patch.face];
      const auto material = [&](glm::dvec2 uv) {
        return face.loops.empty() || (scene.options.trim == SceneOptions::Trim::Cubics
                                          ? inside_trim(scene.cubics[patch.face], uv)
                                          : scene.is_material(patch.face, uv));
      };
      const ExactHit e = scene.refine_first(patch.face, ray, planes, uv, t_min, material);
      if (!e.ok || (best.face >= 0 && e.t >= best.t)) continue;
      best = {e.t, patch.face, e.uv, e.point, hits[h].t};
    }
  }
}

Hit cast_ray(const Scene& scene, const Ray& ray, double t_min, Traversal traversal, TraversalStats* stats) {
  Hit best;
  const double inf = std::numeric_limits<double>::infinity();
  auto visit = [&](int first, int last) {
    test_patches(scene, ray, t_min, first, last, best);
    // Boxes are padded by the tolerance; a farther box may still hold an exact hit a hair nearer.
    return best.face >= 0 ? best.t + 4.0 * scene.options.tolerance * scene.size : inf;
  };
  switch (traversal) {
    case Traversal::Stackless:
      traverse_stackless(scene.bvh, ray, t_min, inf, visit, stats);
      break;
    case Traversal::Stack:
      traverse_stack(scene.bvh, ray, t_min, inf, visit, stats);
      break;
    case Traversal::BruteForce:
      if (stats) stats->patch_tests += static_cast<long>(scene.patches.size());
      if (!scene.patches.empty()) test_patches(scene, ray, t_min, 0, static_cast<int>(scene.patches.size()) - 1, best);
      break;
  }
  return best;
}

std::vector<Hit> cast_rays(const Scene& scene, const std::vector<Ray>& rays, double t_min, Traversal traversal,
                           TraversalStats* stats) {
  std::vector<Hit> out;
  out.reserve(rays.size());
  for (const auto& r : rays) out.push_back(cast_ray(scene, r, t_min, traversal, stats));
  return out;
}

std::vector<Hit> cast_rays_parallel(const Scene& scene, const std::vector<Ray>& rays, double t_min, Traversal traversal,
                                    int threads, TraversalStats* stats) {
  std::vector<Hit> out(rays.size());
  std::vector<TraversalStats> per(static_cast<size_t>(thread_count(threads)));
  parallel_for(
      rays.size(), threads,
      [&](size_t i, int t) { out[i] = cast_ray(scene, rays[i], t_min, traversal, &per[size_t(t)]); }, 256);
  if (stats)
    for (const auto& s : per) {
      stats->box_tests += s.box_tests;
      stats->patch_tests += s.patch_tests;
    }
  return out;
}

}  // namespace nurbs::ray
