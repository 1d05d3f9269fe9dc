#include "nurbs/tessellation/mesh_parameters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "nurbs/tessellation/triangle_bvh.h"
#include "nurbs/trim_classify.h"

namespace nurbs::tess {

TriangleMesh with_face_parameters(const std::vector<TrimmedSurface>& faces, const TriangleMesh& in, int grid,
                                  int threads) {
  std::vector<std::array<glm::dvec3, 3>> points;
  std::vector<std::pair<int, glm::dvec2>> where;
  std::vector<TrimPolygons> trims(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    const Interval du = surface_domain_u(faces[f].surface), dv = surface_domain_v(faces[f].surface);
    trims[f] = flatten_trim(faces[f], mesh_flatten_tolerance(faces[f].surface));
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const glm::dvec2 uv(du.min + du.width() * (i + 0.5) / grid, dv.min + dv.width() * (j + 0.5) / grid);
        if (!faces[f].loops.empty() && !is_material(trims[f], uv)) continue;  // another face's may be nearer
        const glm::dvec3 p = surface_point(faces[f].surface, uv.x, uv.y);
        points.push_back({p, p, p});
        where.emplace_back(int(f), uv);
      }
  }
  if (points.empty()) return in;  // no material samples to start from: measure the mesh as it is
  const TriangleBvh bvh(std::move(points));
  const size_t nt = in.triangles.size();
  TriangleMesh out;
  out.positions.resize(3 * nt);
  out.uv.resize(3 * nt);
  out.vertex_face.resize(3 * nt);
  out.triangles.resize(nt);
  out.triangle_face.resize(nt);
  auto foot = [](const Surface& s, glm::dvec3 q, glm::dvec2 from, double& d) {
    const glm::dvec2 uv = project_point(s, q, from, 20);
    d = glm::length(surface_point(s, uv.x, uv.y) - q);
    return uv;
  };
  parallel_for(nt, threads, [&](size_t k, int) {
    const glm::ivec3 t = in.triangles[k];
    const glm::dvec3 corner[3] = {in.positions[size_t(t.x)], in.positions[size_t(t.y)], in.positions[size_t(t.z)]};
    const glm::dvec3 c = (corner[0] + corner[1] + corner[2]) / 3.0;
    // Candidate faces: those of the samples nearest the centroid and each corner (a triangle by an
    // edge between faces has samples of both nearby); the centroid's closest material foot wins.
    int face = -1;
    glm::dvec2 best(0.0);
    double best_score = INFINITY, d = 0;
    for (const glm::dvec3& q : {c, corner[0], corner[1], corner[2]}) {
      const int nearest = bvh.closest(q).triangle;
      if (nearest < 0) continue;  // no sample within the search's reach (a point beyond 1e300)
      const auto& [f, start] = where[size_t(nearest)];
      const Surface& s = faces[size_t(f)].surface;
      const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
      glm::dvec2 uv = foot(s, c, start, d);
      glm::dvec2 twin = uv;  // the same point of a closed surface on the opposite domain edge
      twin.x = uv.x <= du.min ? du.max : uv.x >= du.max ? du.min : uv.x;
      twin.y = uv.y <= dv.min ? dv.max : uv.y >= dv.max ? dv.min : uv.y;
      if (twin != uv) {
        double d2 = 0;
        const glm::dvec2 other = foot(s, c, twin, d2);
        if (d2 < d) uv = other, d = d2;
      }
      const bool material = faces[size_t(f)].loops.empty() || is_material(trims[size_t(f)], uv);
      const double score = material ? d : d + 1e300;  // material feet first
      if (score < best_score) best_score = score, face = f, best = uv;
    }
    out.triangles[k] = glm::ivec3(int(3 * k), int(3 * k + 1), int(3 * k + 2));
    out.triangle_face[k] = face;
    if (face < 0) {  // no foot found: the corners as they are, without a face (measured from the grid)
      for (int i = 0; i < 3; ++i) out.positions[3 * k + size_t(i)] = corner[i], out.vertex_face[3 * k + size_t(i)] = -1;
      return;
    }
    const Surface& s = faces[size_t(face)].surface;
    for (int i = 0; i < 3; ++i) {
      const size_t v = 3 * k + size_t(i);
      out.positions[v] = corner[i], out.uv[v] = foot(s, corner[i], best, d), out.vertex_face[v] = face;
    }
    // A corner on a pole (S_u or S_v vanishes there) has any u (or v): Newton leaves it where it
    // starts, and midpoints interpolated towards it start far from their foot. It takes the mean
    // of the other corners' coordinate, as the triangle's own edges to the pole run.
    glm::dvec2* uv = &out.uv[3 * k];
    for (int i = 0; i < 3; ++i) {
      const SurfaceDerivatives dd = surface_derivatives(s, uv[i].x, uv[i].y);
      const double lu = glm::length(dd.su), lv = glm::length(dd.sv);
      const glm::dvec2 a = uv[(i + 1) % 3], b = uv[(i + 2) % 3];
      if (lu <= 1e-9 * lv) uv[i].x = 0.5 * (a.x + b.x);
      if (lv <= 1e-9 * lu) uv[i].y = 0.5 * (a.y + b.y);
    }
  });
  return out;
}

}  // namespace nurbs::tess
