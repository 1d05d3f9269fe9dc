// Every face of every shared IGES model: rays along the normal onto material points hit exactly.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/random_surfaces.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "nurbs/surface_eval.h"
#include "tests/nurbs/raycast/patch_error.h"
#include "tests/shared_models.h"

using namespace nurbs;
using namespace nurbs::ray;

namespace {

/// Up to `want` material (u, v) of face f from a 7 x 7 interior grid (untrimmed: any grid point).
std::vector<glm::dvec2> material_points(const Scene& scene, int f, int want) {
  const Surface& s = scene.faces[f].surface;
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  std::vector<glm::dvec2> out;
  for (int k = 0; k < 49 && static_cast<int>(out.size()) < want; ++k) {
    const int i = (k * 17) % 7, j = (k * 17 / 7 + k) % 7;  // scattered order over the grid
    const glm::dvec2 uv(du.min + (i + 0.5) / 7 * (du.max - du.min), dv.min + (j + 0.5) / 7 * (dv.max - dv.min));
    if (scene.faces[f].loops.empty() || is_material(scene.trims[f], uv)) out.push_back(uv);
  }
  return out;
}

}  // namespace

TEST_CASE("raycast: rays onto every face of every shared IGES model" * test::needs_shared_models()) {
  for (const auto& file : test::shared_iges_files()) {
    CAPTURE(file.filename().string());
    const Model model = io::read_model(file);
    const auto t0 = std::chrono::steady_clock::now();
    const Scene scene = build_scene(world_faces(model));
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double worst_err = 0.0;
    int max_patches = 0, unconverged = 0;
    for (const auto& st : scene.face_stats) {
      worst_err = std::max(worst_err, st.max_sampled_error);
      max_patches = std::max(max_patches, st.patches);
      unconverged += !st.converged;
    }
    // Offset of the near rays: 1e-4 size; another face closer than that counts as occluded, not wrong.
    const double near = 1e-4 * scene.size;
    int rays = 0, wrong = 0, occluded = 0, far_wrong = 0, coincident = 0;
    double worst_bicubic = 0.0;  // |bicubic hit - exact hit| along the ray
    TraversalStats ts;
    const auto t1 = std::chrono::steady_clock::now();
    for (int f = 0; f < static_cast<int>(scene.faces.size()); ++f)
      for (const glm::dvec2 uv : material_points(scene, f, 2)) {
        const glm::dvec3 p = surface_point(scene.faces[f].surface, uv.x, uv.y);
        const glm::dvec3 n = surface_normal(scene.faces[f].surface, uv.x, uv.y);
        if (glm::length(n) < 0.5) continue;  // degenerate point (a pole): no normal to shoot along
        const Hit h = cast_ray(scene, {p + near * n, -n}, 0.0, Traversal::Stackless, &ts);
        // The required bound: 1e-9 x model size after the exact step (the hit is the same point of f).
        if (h.face >= 0) worst_bicubic = std::max(worst_bicubic, std::abs(h.t_bicubic - h.t));
        // At the face's point itself on another face: a coincident face (solids of an assembly
        // touching), either of which is the nearest hit.
        if (h.face >= 0 && h.t < near - 1e-9 * scene.size)
          ++occluded;
        else if (h.face >= 0 && h.face != f && std::abs(h.t - near) <= 1e-9 * scene.size)
          ++coincident;
        else
          wrong += h.face != f || std::abs(h.t - near) > 1e-9 * scene.size;
        // From outside the model's box along the normal: nothing can lie beyond the face's point.
        const Hit g = cast_ray(scene, {p + scene.size * n, -n}, 0.0, Traversal::Stackless, &ts);
        far_wrong += g.face < 0 || g.t > scene.size + 1e-9 * scene.size;
        rays += 2;
      }
    const double cast_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    // Independent error check: 9 x 9 points per patch, none of them the build's 6 x 6.
    double dense_err = 0.0;
    for (const auto& p : scene.patches)
      dense_err = std::max(dense_err, test::patch_error(scene.faces[p.face].surface, p, 9));
    // §3.4 cubic trims vs the winding-number oracle on 40 random points per trimmed face.
    int trim_points = 0, trim_disagree = 0;
    models::Random rng(17);
    for (int f = 0; f < static_cast<int>(scene.faces.size()); ++f) {
      if (scene.faces[f].loops.empty()) continue;
      const TrimPolygons& oracle = scene.trims[f];
      const double diag =
          std::hypot(oracle.domain_u.max - oracle.domain_u.min, oracle.domain_v.max - oracle.domain_v.min);
      const TrimCubics tc = trim_cubics(scene.faces[f], scene.options.trim_flatten * diag);
      for (int k = 0; k < 40; ++k) {
        const glm::dvec2 p(rng.uniform(oracle.domain_u.min, oracle.domain_u.max),
                           rng.uniform(oracle.domain_v.min, oracle.domain_v.max));
        ++trim_points;
        trim_disagree += inside_trim(tc, p) != is_material(oracle, p);
      }
    }
    CHECK(wrong == 0);
    CHECK(far_wrong == 0);
    CHECK(unconverged == 0);
    CHECK(worst_err <= scene.options.tolerance * scene.size);
    CHECK(dense_err <= scene.options.tolerance * scene.size);  // the bicubic tolerance itself
    // Required: bicubic hits within 1e-5 size of the exact hit (near-normal rays: about the patch error).
    CHECK(worst_bicubic <= 1e-5 * scene.size);
    MESSAGE(file.filename().string() << ": " << scene.faces.size() << " faces, " << scene.patches.size()
                                     << " patches (max " << max_patches << "/face), sampled error "
                                     << worst_err / scene.size << " x size, build " << build_s << " s; " << rays
                                     << " rays, " << occluded << " occluded, " << coincident << " on a coincident face, " << rays / cast_s << " rays/s, "
                                     << double(ts.box_tests) / rays << " box + " << double(ts.patch_tests) / rays
                                     << " patch tests/ray; dense error " << dense_err / scene.size
                                     << " x size; §3.4 trim test disagrees on " << trim_disagree << " of "
                                     << trim_points << " points; bicubic hit off by " << worst_bicubic / scene.size
                                     << " x size");
  }
}
