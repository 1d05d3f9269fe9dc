#pragma once
/// \file mesh_distance.h
/// Point distances from a certified mesh (beyond the papers): the faces tessellated in the
/// guaranteed mode of Balázs, Guthe and Klein at eps, on the knot-aligned grids of Krishnamurthy et
/// al. §2.2 (nurbs::tess::Subdivision::Grid), the triangles put in Embree's BVH, and every point's
/// closest triangle found by Embree's point query with the distances taken in double.
///
/// Bound. The guaranteed mesh lies within eps of the faces and the faces within eps of the mesh
/// (the cells' Filip bound K_e for any triangle inside a cell, the trim loops within their share of
/// eps: tessellate.h), so the distance d from a point to the mesh brackets its distance d* to the
/// faces: |d - d*| <= eps. An answer is d with bound eps, its closest point on the mesh, the face of
/// that triangle and the (u, v) of the point by the triangle's barycentric weights; point_bound is
/// Krishnamurthy et al.'s sqrt(4 K d + K^2) with K = eps, as for the grids' triangles; on_trim_edge
/// where the point lies on its face's mesh boundary.
///
/// Rays: the faces lie within eps of the mesh, so within the slab between two shells, the mesh
/// moved 1.5 eps to either side along the vertex normals (inside a face; beside its edges, within
/// tubes around the mesh's face boundaries). A ray meets a face only inside the slab: first_hit
/// gives the first shell triangle it crosses (Embree's rtcIntersect1), with the face and the
/// (u, v) of the crossing by the triangle's barycentric weights, where a ray caster starts its
/// Newton step on the exact face (queries/raycast/ray_caster.h, RayMethod::Mesh); a ray that
/// crosses no shell and no tube meets no face.
///
/// Floats. Embree keeps its boxes and triangles in float (relative to the mesh's centre); a box it
/// prunes is beyond the best distance so far grown by the float rounding of the triangles and the
/// point (2^-18 (R + |p - centre|), R the mesh's radius, 64 times the rounding of the coordinates),
/// so no triangle nearer than the best in double is pruned: the answer is the mesh's closest
/// triangle in double, with no float term in its bound.
#include <array>
#include <cstdint>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <vector>

#include "nurbs/tessellation/tessellate.h"
#include "nurbs/trimmed_surface.h"
#include "queries/distance/point_distance.h"

struct RTCSceneTy;  // Embree's scene (embree3/rtcore.h)

namespace queries {

/// The first mesh triangle a ray meets (MeshDistance::first_hit).
struct MeshRayHit {
  int triangle = -1;  ///< -1: none (or a boundary)
  /// Built for rays: the ray meets a tube or ball around a face's mesh boundary first, at t.
  bool boundary = false;
  double t = -1.0;    ///< along the unit direction (Embree's, in float)
  int face = -1;
  glm::dvec2 uv{0.0};
  /// Built for rays, a shell triangle: the shell (0 inside the faces, 1 outside), and whether the
  /// ray enters the slab there (crosses the shell towards the mesh) or leaves it.
  int shell = -1;
  bool entering = false;
  /// A tube: its mesh boundary edge (vertex indices of tessellation().mesh; a ball: its vertex
  /// twice), with `face` that edge's face.
  glm::ivec2 edge{-1, -1};
};

/// The faces whose slab or tube may hold a point (MeshDistance::slabs_at).
struct SlabsAt {
  int count = 0;
  /// Per face: `face`, `uv` the point on its mesh of the first triangle, edge or ball found within
  /// reach nearest the point, `t` that distance; `triangle` that triangle, or -1 (with `boundary`)
  /// for an edge or ball.
  std::array<MeshRayHit, 8> faces;
  bool more = false;  ///< more faces than room for them
};

class MeshDistance {
 public:
  /// Tessellates `faces` within `eps` (absolute; guaranteed mode, Subdivision::Grid) on `threads`
  /// (0: every hardware thread) and builds the BVH. Throws nurbs::tess::WorkLimitError when the
  /// mesh would exceed `max_cells` (tessellate.h). Faces that could not be meshed within eps are
  /// listed by failures(): answers are then not certified (query() leaves them as it finds them;
  /// the caller decides). `rays`: for first_hit instead of query: the BVH then
  /// holds two shells, the mesh's vertices moved 1.5 eps along their normals to either side, and
  /// tubes of radius 2 eps around every face's mesh boundary.
  MeshDistance(const std::vector<nurbs::TrimmedSurface>& faces, double eps, int threads = 0,
               long long max_cells = nurbs::tess::TessellateOptions{}.max_cells, bool rays = false);
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;

  /// The closest mesh point of every point (input order), on every hardware thread; found false
  /// only for a mesh without triangles. Of equally near triangles the lowest index, so the answers
  /// do not depend on the threads or on the other points. `progress` (optional): points done,
  /// points in all.
  [[nodiscard]] std::vector<PointDistance> query(std::span<const glm::dvec3> points,
                                                 const std::function<void(size_t, size_t)>& progress = {}) const;
  /// The first triangle the ray (origin, unit direction) meets at t in (t_min, t_max): of the mesh
  /// (built for points) or of its shells (built for rays), or, built for rays, the first tube or
  /// ball around a face's mesh boundary when the ray meets one first: where a face's true edge may
  /// lie up to eps outside its mesh, so that the ray may meet the face and miss its shells.
  [[nodiscard]] MeshRayHit first_hit(const glm::dvec3& origin, const glm::dvec3& direction, double t_min,
                                     double t_max) const;
  /// Built for rays: the faces whose slab (between the shells) or tube may hold p: those with a
  /// mesh triangle within 1.5 eps of p, or a mesh boundary edge or ball within 2 eps, by Embree's
  /// point query with the float rounding allowance added. A ray that starts there may meet such a
  /// face before it crosses any shell or tube.
  [[nodiscard]] SlabsAt slabs_at(const glm::dvec3& p) const;
  /// Where a ray (origin, unit direction) leaves the mesh's box grown by the tubes' radius and the
  /// float allowance, beyond which it meets no slab, no tube and no face (0 if it never meets it).
  [[nodiscard]] double box_exit(const glm::dvec3& origin, const glm::dvec3& direction) const;
  /// The float rounding allowance at a point p (a query point, a ray's origin): 2^-18 (R +
  /// |p - centre|), the radius a point query is grown by; a step past a ray's hit by more than it
  /// leaves the hit's triangle behind.
  [[nodiscard]] double float_slack(const glm::dvec3& p) const;
  /// The same for one point, by testing every triangle (the reference the tests hold the BVH to).
  [[nodiscard]] PointDistance brute_force(const glm::dvec3& p) const;

  [[nodiscard]] double eps() const { return eps_; }
  [[nodiscard]] const nurbs::tess::TessellateResult& tessellation() const { return tess_; }
  [[nodiscard]] long long triangles() const { return (long long)tess_.mesh.triangles.size(); }
  [[nodiscard]] double tessellate_seconds() const { return tess_seconds_; }
  [[nodiscard]] double build_seconds() const { return build_seconds_; }

 private:
  struct Scene;
  void add_triangles(::RTCSceneTy* scene, const std::vector<glm::dvec3>& positions, double offset);
  PointDistance answer(int triangle, double distance, const glm::dvec3& point, const glm::dvec3& weights,
                       long long tested) const;
  double eps_ = 0.0;
  int threads_ = 0;
  bool rays_ = false;
  nurbs::tess::TessellateResult tess_;
  double tess_seconds_ = 0.0, build_seconds_ = 0.0;
  glm::dvec3 centre_{0.0};
  double radius_ = 0.0;
  glm::dvec3 lo_{0.0}, hi_{0.0};  ///< the mesh's bounding box
  std::unique_ptr<Scene> scene_;
  std::vector<uint8_t> boundary_;  ///< points: per triangle, its edges on the face's mesh boundary
  int tube_geometry_ = -1;                     ///< rays: Embree's geometry of the tubes
  std::vector<glm::ivec2> boundary_vertices_;  ///< rays: per tube, its edge
  std::vector<int> ball_vertices_;             ///< rays: per ball, its vertex
};

}  // namespace queries
