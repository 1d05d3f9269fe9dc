#include "viewer/scene_model.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <stdexcept>

#include "nurbs/io/read_model.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace viewer {

void load_scene_model(SceneModel& out, const std::string& path) {
  out.loaded = nurbs::io::load_model(path);
  const nurbs::Model& model = out.loaded.model;
  out.path = path;
  out.faces = nurbs::world_faces(model);
  out.box = nurbs::model_box(model);
  for (const std::string& line : out.loaded.report.lines())
    std::fprintf(stderr, "%s: %s\n", path.c_str(), line.c_str());
  out.size = out.loaded.checked_size();
}

void tessellate_scene_model(SceneModel& m, double eps_relative, nurbs::tess::TessMode mode) {
  const auto t0 = std::chrono::steady_clock::now();
  nurbs::tess::ModelMeshOptions options;
  options.eps = eps_relative;
  options.tess.mode = mode;
  nurbs::tess::ModelMesh mesh = nurbs::tess::mesh_model(m.loaded, options);
  m.tess = std::move(mesh.result);
  m.tess_eps = mesh.eps;
  m.tess_failure = mesh.failure();
  m.tess_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.buffers.upload(m.tess.mesh);
  m.mesh_min = m.box.min;
  m.mesh_max = m.box.max;
  if (!m.tess.mesh.positions.empty()) {
    m.mesh_min = m.mesh_max = m.tess.mesh.positions.front();
    for (const glm::dvec3& p : m.tess.mesh.positions) {
      m.mesh_min = glm::min(m.mesh_min, p);
      m.mesh_max = glm::max(m.mesh_max, p);
    }
  }
}

std::optional<Pick> pick(const nurbs::TriangleMesh& mesh, const glm::dmat4& motion, const Ray& ray) {
  // Into the mesh's own frame: the motion is rigid, so t stays the world distance along the ray.
  const glm::dmat4 inv = glm::inverse(motion);
  const glm::dvec3 o = glm::dvec3(inv * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 d = glm::dvec3(inv * glm::dvec4(ray.direction, 0.0));
  std::optional<Pick> best;
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    const glm::ivec3 tri = mesh.triangles[k];
    const glm::dvec3 a = mesh.positions[tri.x], e1 = mesh.positions[tri.y] - a, e2 = mesh.positions[tri.z] - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-300) continue;
    const glm::dvec3 s = o - a;
    const double u = glm::dot(s, p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double t = glm::dot(e2, q) / det;
    if (t <= 0.0 || (best && t >= best->t)) continue;
    const int face = k < mesh.triangle_face.size() ? mesh.triangle_face[k] : -1;
    best = Pick{face, t, ray.origin + t * ray.direction};
  }
  return best;
}

void add_control_net(const nurbs::TrimmedSurface& face, const glm::vec3& color, LineBatch& batch) {
  const nurbs::Surface& s = face.surface;
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i) {
      if (i + 1 < s.count_u) batch.line(s.point(i, j), s.point(i + 1, j), color);
      if (j + 1 < s.count_v) batch.line(s.point(i, j), s.point(i, j + 1), color);
    }
}

void add_trim_loops(const nurbs::TrimmedSurface& face, const glm::vec3& color, LineBatch& batch) {
  const nurbs::Surface& s = face.surface;
  const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
  std::vector<std::vector<glm::dvec2>> loops;
  if (face.loops.empty()) {
    loops.push_back({{du.min, dv.min}, {du.max, dv.min}, {du.max, dv.max}, {du.min, dv.max}});
  } else {
    // Within 1e-4 of the domain width: below a pixel for a face filling the window.
    loops = nurbs::flatten_trim(face, 1e-4 * std::max(du.width(), dv.width())).loops;
  }
  for (const auto& loop : loops) {
    // Long polygon edges (the domain's sides) are mapped through the surface at several points so
    // that they follow it; flattened curves are already fine.
    const int steps = std::max(1, 256 / static_cast<int>(std::max<size_t>(loop.size(), 1)));
    for (size_t k = 0; k < loop.size(); ++k) {
      const glm::dvec2 a = loop[k], b = loop[(k + 1) % loop.size()];
      glm::dvec3 prev = nurbs::surface_point(s, std::clamp(a.x, du.min, du.max), std::clamp(a.y, dv.min, dv.max));
      for (int i = 1; i <= steps; ++i) {
        const glm::dvec2 uv = a + (b - a) * (double(i) / steps);
        const glm::dvec3 p =
            nurbs::surface_point(s, std::clamp(uv.x, du.min, du.max), std::clamp(uv.y, dv.min, dv.max));
        batch.line(prev, p, color);
        prev = p;
      }
    }
  }
}

}  // namespace viewer
