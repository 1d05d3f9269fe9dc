#include "queries/distance/side_test.h"

#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/parallel.h"
#include "nurbs/surface_eval.h"
#include "queries/raycast/ray_caster.h"

namespace queries {
namespace {

/// cos 25 degrees: p - closest this near the normal line decides by the normal.
constexpr double kNormalCone = 0.906;
/// A ray this close to tangent at its hit abstains (an edge grazed, a silhouette).
constexpr double kGrazing = 1e-3;

/// Three directions in general position (no axis, no diagonal of a box: fewer grazing hits on the
/// planes and edges CAD models are made of), unit length.
const glm::dvec3 kRayDirections[3] = {glm::normalize(glm::dvec3(0.5381, 0.3128, 0.7826)),
                                      glm::normalize(glm::dvec3(-0.7713, 0.5894, 0.2404)),
                                      glm::normalize(glm::dvec3(0.1667, -0.8911, 0.4219))};

glm::dvec3 outward_normal(const nurbs::TrimmedSurface& f, const glm::dvec2& uv) {
  const glm::dvec3 n = nurbs::surface_normal(f.surface, uv.x, uv.y);
  return f.reversed ? -n : n;
}

/// Whether (u, v) lies on the edge of the face's parameter rectangle (where the face may end).
bool on_domain_edge(const nurbs::Surface& s, const glm::dvec2& uv) {
  const double u0 = s.knots_u[size_t(s.degree_u)], u1 = s.knots_u[size_t(s.count_u)];
  const double v0 = s.knots_v[size_t(s.degree_v)], v1 = s.knots_v[size_t(s.count_v)];
  const double eu = 1e-9 * (u1 - u0), ev = 1e-9 * (v1 - v0);
  return uv.x <= u0 + eu || uv.x >= u1 - eu || uv.y <= v0 + ev || uv.y >= v1 - ev;
}

}  // namespace

SideTest::SideTest(const std::vector<nurbs::TrimmedSurface>& faces) : faces_(faces) {}
SideTest::~SideTest() = default;

Side SideTest::by_normal(const glm::dvec3& p, const PointDistance& a) const {
  if (!a.found || a.on_trim_edge || a.face < 0) return Side::Unsure;
  const nurbs::TrimmedSurface& f = faces_[size_t(a.face)];
  if (on_domain_edge(f.surface, a.uv)) return Side::Unsure;
  const glm::dvec3 v = p - a.point;
  const double d = glm::length(v);
  if (!(d > a.point_bound) || !(d > 0.0)) return Side::Unsure;
  const glm::dvec3 n = outward_normal(f, a.uv);
  const double c = glm::dot(v / d, n);
  if (!std::isfinite(c) || std::abs(c) < kNormalCone) return Side::Unsure;
  return c > 0.0 ? Side::Outside : Side::Inside;
}

std::vector<Side> SideTest::sides(std::span<const glm::dvec3> points, const std::vector<PointDistance>& answers) {
  std::vector<Side> out(points.size(), Side::Unsure);
  nurbs::for_shares(points.size(), nurbs::share_count(points.size(), 256), [&](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) out[i] = by_normal(points[i], answers[i]);
  });
  std::vector<size_t> rest;
  for (size_t i = 0; i < points.size(); ++i)
    if (out[i] == Side::Unsure && answers[i].found) rest.push_back(i);
    else if (out[i] != Side::Unsure) ++figures_.by_normal;
  if (rest.empty()) return out;
  if (!caster_) caster_ = std::make_unique<RayCaster>(faces_, RayCasterOptions{});
  std::vector<nurbs::ray::Ray> rays;
  rays.reserve(3 * rest.size());
  for (const size_t i : rest)
    for (const glm::dvec3& d : kRayDirections) rays.push_back({points[i], d});
  const std::vector<nurbs::ray::Hit> hits = caster_->cast(rays, 0.0);
  for (size_t k = 0; k < rest.size(); ++k) {
    int inside = 0, outside = 0;
    for (size_t r = 0; r < 3; ++r) {
      const nurbs::ray::Hit& h = hits[3 * k + r];
      if (h.face < 0) {
        ++outside;  // nothing met: the ray leaves every solid
        continue;
      }
      const double c = glm::dot(kRayDirections[r], outward_normal(faces_[size_t(h.face)], h.uv));
      if (!std::isfinite(c) || std::abs(c) < kGrazing) continue;
      (c > 0.0 ? inside : outside) += 1;  // leaving a solid through its face: the ray started inside
    }
    Side s = Side::Unsure;
    if (inside >= 2 && outside == 0) s = Side::Inside;
    if (outside >= 2 && inside == 0) s = Side::Outside;
    out[rest[k]] = s;
    ++(s == Side::Unsure ? figures_.unsure : figures_.by_rays);
  }
  return out;
}

}  // namespace queries
