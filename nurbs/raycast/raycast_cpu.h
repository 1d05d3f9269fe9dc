#pragma once
/// \file raycast_cpu.h
/// The double-precision CPU ray caster of Lemasson et al. (§3.1-3.3, the trim test on the exact
/// flattened loops): the GPU path's twin and test oracle. Faces -> bicubic patches (§3.1) -> Morton
/// BVH (§3.2) -> per candidate patch the two-plane Newton (§3.3), then the final Newton step on the
/// exact NURBS face and the point-in-trim test: the winding number on the face's flattened trim
/// loops (trim_classify.h, the oracle) or the paper's §3.4 test on cubic trims (trim_test.h).
#include <algorithm>
#include <memory>
#include <vector>

#include "nurbs/raycast/bicubic_patches.h"
#include "nurbs/raycast/morton_bvh.h"
#include "nurbs/raycast/ray_patch.h"
#include "nurbs/raycast/trim_test.h"
#include "nurbs/trim_classify.h"

namespace nurbs::ray {

struct SceneOptions {
  /// Bicubic tolerance relative to the model size (box diagonal of the patches' control points):
  /// hits on the bicubics then land within ~1e-5 size of the exact hit before the final step.
  double tolerance = 1e-5;
  double trim_flatten = 1e-7;  ///< trim flattening for the final test, relative to each face's domain diagonal
  /// Patches are also split while their normals turn by more than this (BicubicOptions): the teapot's
  /// 32 exact bicubics kept whole missed 2 % of the nearest hits OpenCASCADE finds (0.05 % split).
  double max_turn_degrees = 30.0;
  /// The exact step is accepted when |R| <= this x size; from a bicubic hit within 1e-5 size two
  /// quadratic steps reach round-off, so 1e-10 rejects only hits that do not exist on the exact face.
  double exact_residual = 1e-10;
  int exact_iterations = 6;
  /// Beyond the paper: each exact hit also looks for the first of a grazing pair before it
  /// (Scene::refine_first, earlier_root); false: the exact step alone, as the GPU pass's twin has it.
  bool grazing_pairs = true;
  /// Point-in-trim test of a hit: flattened loops + winding number, or §3.4 on cubic Bézier trims
  /// (those approximated within trim_flatten x domain diagonal as well).
  enum class Trim { Polygons, Cubics } trim = Trim::Polygons;
  RayPatchOptions patch;
};

/// The material test of a scene's faces: each face's flattened loops with their bands
/// (BandedTrim: is_material's answer, bit for bit, reading only the point's band), shared by the
/// scene's copies (a BandedTrim points into its loops).
struct SceneMaterial {
  std::vector<TrimPolygons> trims;
  std::vector<BandedTrim> banded;
  /// Per face, twice its flattening tolerance in (u, v): the loops' polygons lie within the
  /// tolerance of the trim curves, so a point of the true boundary lies within this of an edge.
  std::vector<double> edge_reach;
};

struct Scene {
  std::vector<TrimmedSurface> faces;
  std::vector<TrimPolygons> trims;    ///< per face; empty loops = untrimmed
  std::shared_ptr<const SceneMaterial> material;  ///< the same loops, banded (build_scene)
  /// Whether (u, v) of face f is material: is_material on its flattened loops (true untrimmed).
  [[nodiscard]] bool is_material(int f, glm::dvec2 uv) const {
    return faces[size_t(f)].loops.empty() || material->banded[size_t(f)].is_material(uv);
  }
  /// is_material with the face closed: a point within the flattening's reach of its loops counts
  /// too (the face's edge is its own, as the edge it shares with its neighbour is). On the polygons
  /// alone a ray through the edge two faces share may miss both, each loop's polygon a rounding off
  /// the other's. For the certified nearest hits (the mesh method).
  [[nodiscard]] bool is_material_closed(int f, glm::dvec2 uv) const {
    if (is_material(f, uv)) return true;
    const double r = material->edge_reach[size_t(f)];
    return material->banded[size_t(f)].meets_box(uv - glm::dvec2(r), uv + glm::dvec2(r));
  }
  /// is_material_closed of face f, as a predicate of (u, v).
  [[nodiscard]] auto material_test_closed(int f) const {
    return [this, f](glm::dvec2 uv) { return is_material_closed(f, uv); };
  }
  /// Per face, its surface in Bézier form for the exact steps (empty where it would be too large),
  /// shared by the scene's copies.
  std::shared_ptr<const std::vector<BezierForm>> forms;
  std::vector<Seams> seams;  ///< per face (build_scene): Newton steps continue across them
  [[nodiscard]] Seams seams_of(int f) const { return f < int(seams.size()) ? seams[size_t(f)] : Seams{}; }
  /// Face f's Bézier form; an empty one (the exact steps then evaluate the surface) without forms.
  [[nodiscard]] const BezierForm& form_of(int f) const {
    static const BezierForm none;
    return forms ? (*forms)[size_t(f)] : none;
  }
  /// is_material of face f, as a predicate of (u, v) (look_back, refine_first).
  [[nodiscard]] auto material_test(int f) const {
    return [this, f](glm::dvec2 uv) { return is_material(f, uv); };
  }
  /// The exact step on face f (refine_on_surface with its Bézier form, the scene's iterations unless
  /// `iterations` is given, and its residual).
  [[nodiscard]] ExactHit refine(int f, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv, int iterations = 0) const {
    const int steps = iterations > 0 ? iterations : options.exact_iterations;
    return refine_on_surface(form_of(f), faces[size_t(f)].surface, ray, planes, uv, steps,
                             options.exact_residual * size, seams_of(f));
  }
  /// From an exact hit `found` on face f, earlier_root while it finds one (a grazing pair; none
  /// without options.grazing_pairs): the earliest root before `found` and after t_min whose (u, v)
  /// `material` accepts; ok false when none.
  template <class Material>
  [[nodiscard]] ExactHit look_back(int f, const Ray& ray, const RayPlanes& planes, const ExactHit& found, double t_min,
                                   const Material& material) const {
    ExactHit first, at = found;
    for (int k = 0; k < (options.grazing_pairs ? 3 : 0); ++k) {
      // Near a grazing pair Newton converges slowly (the ray almost tangent): more steps.
      const ExactHit a = earlier_root(form_of(f), faces[size_t(f)].surface, ray, planes, at,
                                      std::max(40, options.exact_iterations), options.exact_residual * size,
                                      seams_of(f));
      if (!a.ok || !(a.t > t_min)) break;
      if (material(a.uv)) first = a;
      at = a;
    }
    return first;
  }
  /// refine (`iterations` as there), then look_back: the earliest exact hit after t_min whose
  /// (u, v) `material` accepts; ok false when none.
  template <class Material>
  [[nodiscard]] ExactHit refine_first(int f, const Ray& ray, const RayPlanes& planes, glm::dvec2 uv, double t_min,
                                      const Material& material, int iterations = 0) const {
    const ExactHit e = refine(f, ray, planes, uv, iterations);
    if (!e.ok) return e;
    const ExactHit back = look_back(f, ray, planes, e, t_min, material);
    return back.ok ? back : e.t > t_min && material(e.uv) ? e : ExactHit{};
  }
  std::vector<TrimCubics> cubics;     ///< per face, filled when options.trim == Cubics
  std::vector<BicubicPatch> patches;  ///< in BVH leaf order (patches[k] is leaf k)
  std::vector<BicubicStats> face_stats;
  Bvh bvh;
  double size = 0.0;  ///< diagonal of the box of every control point of every patch
  SceneOptions options;
};

/// Scene::size of `faces`: the diagonal of the box of their control points.
[[nodiscard]] double scene_size(const std::vector<TrimmedSurface>& faces);

/// Builds the patches of every face (tolerance x size, size from the faces' control boxes) and the
/// BVH over their boxes (each inflated by twice the tolerance so the exact surface is inside).
[[nodiscard]] Scene build_scene(std::vector<TrimmedSurface> faces, const SceneOptions& options = {});

/// Nearest valid hit; t = -1 and face = -1 for a miss.
struct Hit {
  double t = -1.0;  ///< distance along the unit direction
  int face = -1;
  glm::dvec2 uv{0.0};  ///< on the face's surface
  glm::dvec3 point{0.0};
  double t_bicubic = -1.0;  ///< t of the bicubic hit before the exact step (what a float GPU pass would report)
};

enum class Traversal { Stackless, Stack, BruteForce };

/// Casts one ray (unit direction) for hits with t > t_min through the BVH (or all patches).
[[nodiscard]] Hit cast_ray(const Scene& scene, const Ray& ray, double t_min, Traversal traversal = Traversal::Stackless,
                           TraversalStats* stats = nullptr);

/// Tests the patches [first, last] (leaf order) and improves `best` (used by every traversal and
/// by DACRT): bicubic Newton, exact step, domain and trim test.
void test_patches(const Scene& scene, const Ray& ray, double t_min, int first, int last, Hit& best);

/// Casts many rays.
[[nodiscard]] std::vector<Hit> cast_rays(const Scene& scene, const std::vector<Ray>& rays, double t_min,
                                         Traversal traversal = Traversal::Stackless, TraversalStats* stats = nullptr);

/// Every ray's hits, parallel over `threads` (0: all hardware threads), deterministic.
[[nodiscard]] std::vector<Hit> cast_rays_parallel(const Scene& scene, const std::vector<Ray>& rays, double t_min,
                                                  Traversal traversal, int threads = 0,
                                                  TraversalStats* stats = nullptr);

}  // namespace nurbs::ray
