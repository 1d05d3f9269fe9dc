#include "nurbs/model_ops.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "nurbs/surface_eval.h"

namespace nurbs {

std::vector<std::string> validate_rigid(const glm::dmat4& m) {
  std::vector<std::string> problems;
  const glm::dmat3 r(m);
  const glm::dmat3 rtr = glm::transpose(r) * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::fabs(rtr[i][j] - (i == j ? 1.0 : 0.0)) > 1e-9) {
        problems.push_back(fmt::format("rotation part is not orthonormal (R^T R [{}][{}] = {})", i, j, rtr[i][j]));
        i = j = 3;
      }
  if (std::fabs(glm::determinant(r) - 1.0) > 1e-9)
    problems.push_back(fmt::format("det R = {} (not 1)", glm::determinant(r)));
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
    problems.push_back("last row is not (0, 0, 0, 1): a projective map");
  return problems;
}

TrimmedSurface transformed(const TrimmedSurface& face, const glm::dmat4& m) {
  TrimmedSurface out = face;
  for (glm::dvec3& p : out.surface.points) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  return out;
}

double largest_edge_gap(const std::vector<TrimmedSurface>& faces) {
  double gap = 0.0;
  for (const TrimmedSurface& f : faces) gap = std::max(gap, f.edge_gap);
  return gap;
}

std::vector<TrimmedSurface> world_faces(const Model& model) {
  std::vector<TrimmedSurface> faces;
  for (const Body& b : model.bodies)
    for (const TrimmedSurface& f : b.faces)
      faces.push_back(b.transform == glm::dmat4(1.0) ? f : transformed(f, b.transform));
  return faces;
}

double Box::diagonal() const { return glm::length(max - min); }

Box sampled_box(const Surface& s, const glm::dmat4& m) {
  constexpr int kSamples = 16;  // 17 x 17 points
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  const bool identity = m == glm::dmat4(1.0);
  Box box;
  for (int j = 0; j <= kSamples; ++j)
    for (int i = 0; i <= kSamples; ++i) {
      glm::dvec3 p = surface_point(s, du.min + du.width() * i / kSamples, dv.min + dv.width() * j / kSamples);
      if (!identity) p = glm::dvec3(m * glm::dvec4(p, 1.0));
      box.min = i == 0 && j == 0 ? p : glm::min(box.min, p);
      box.max = i == 0 && j == 0 ? p : glm::max(box.max, p);
    }
  return box;
}

Box model_box(const Model& model) {
  Box box;
  bool first = true;
  for (const Body& b : model.bodies)
    for (const TrimmedSurface& f : b.faces) {
      const Box fb = sampled_box(f.surface, b.transform);
      box.min = first ? fb.min : glm::min(box.min, fb.min);
      box.max = first ? fb.max : glm::max(box.max, fb.max);
      first = false;
    }
  return box;
}

double model_size(const Model& model) { return model_box(model).diagonal(); }

double coordinate_limit(const Box& box) {
  const glm::dvec3 far = glm::max(glm::abs(box.min), glm::abs(box.max));
  return std::max({far.x, far.y, far.z}) + kCoordinateReach * box.diagonal();
}

Box control_box(const Surface& s) {
  Box box{s.points.front(), s.points.front()};
  for (const glm::dvec3& p : s.points) {
    box.min = glm::min(box.min, p);
    box.max = glm::max(box.max, p);
  }
  return box;
}

double box_distance(const Box& a, const Box& b) {
  return glm::length(glm::max(glm::max(a.min - b.max, b.min - a.max), glm::dvec3(0.0)));
}

double box_distance(const Box& b, const glm::dvec3& p) {
  return glm::length(glm::max(glm::max(b.min - p, p - b.max), glm::dvec3(0.0)));
}

std::vector<std::string> validate_model_size(double size) {
  if (!std::isfinite(size)) return {fmt::format("model size is {} (coordinates too large for double precision)", size)};
  if (size < kMinModelSize)
    return {fmt::format("model size is {:g}, less than {:g}: the surfaces collapse to a point (coordinates too small?)",
                        size, kMinModelSize)};
  if (size > kMaxModelSize)
    return {fmt::format("model size is {:g}, more than {:g}: coordinates too large", size, kMaxModelSize)};
  return {};
}

std::string unit_name(const nurbs::Model& model) {
  const double k = model.unit_scale_to_mm;
  const std::pair<double, const char*> known[] = {{1.0, "mm"},    {25.4, "in"}, {304.8, "ft"}, {1000.0, "m"},
                                                  {10.0, "cm"},   {0.001, "um"}, {1e6, "km"},  {0.0254, "mil"},
                                                  {1609344.0, "mi"}};
  for (const auto& [scale, name] : known)
    if (std::abs(k - scale) <= 1e-9 * scale) return name;
  return fmt::format("x {:g} mm", k);
}

glm::dvec3 outward_normal(const TrimmedSurface& f, const glm::dvec2& uv) {
  const glm::dvec3 n = surface_normal(f.surface, uv.x, uv.y);
  return f.reversed ? -n : n;
}

}  // namespace nurbs
