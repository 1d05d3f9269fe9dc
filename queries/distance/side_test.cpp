#include "queries/distance/side_test.h"

#include <algorithm>
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

/// Whether (u, v) lies on the edge of the face's parameter rectangle (where the face may end).
bool on_domain_edge(const nurbs::Surface& s, const glm::dvec2& uv) {
  const double u0 = s.knots_u[size_t(s.degree_u)], u1 = s.knots_u[size_t(s.count_u)];
  const double v0 = s.knots_v[size_t(s.degree_v)], v1 = s.knots_v[size_t(s.count_v)];
  const double eu = 1e-9 * (u1 - u0), ev = 1e-9 * (v1 - v0);
  return uv.x <= u0 + eu || uv.x >= u1 - eu || uv.y <= v0 + ev || uv.y >= v1 - ev;
}

bool in_box(const nurbs::Box& b, const glm::dvec3& p, double grow) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= b.min[a] - grow && p[a] <= b.max[a] + grow)) return false;
  return true;
}

}  // namespace

struct SideTest::Solid {
  std::vector<int> faces;  ///< global face indices
  nurbs::Box box;          ///< of the faces' control points: holds the solid
  std::unique_ptr<RayCaster> caster;
};

SideTest::SideTest(const std::vector<nurbs::TrimmedSurface>& faces, std::vector<int> solid_of_face)
    : faces_(faces), solid_of_face_(std::move(solid_of_face)) {
  if (solid_of_face_.size() != faces_.size()) solid_of_face_.assign(faces_.size(), 0);
  for (size_t f = 0; f < faces_.size(); ++f) {
    const size_t s = size_t(std::max(solid_of_face_[f], 0));
    if (solids_.size() <= s) solids_.resize(s + 1);
    Solid& solid = solids_[s];
    const nurbs::Box b = nurbs::control_box(faces_[f].surface);
    solid.box = solid.faces.empty() ? b : nurbs::Box{glm::min(solid.box.min, b.min), glm::max(solid.box.max, b.max)};
    solid.faces.push_back(int(f));
  }
}
SideTest::~SideTest() = default;

Side SideTest::by_normal(const glm::dvec3& p, const PointDistance& a, const glm::dvec3& n) const {
  if (!a.found || a.on_trim_edge || a.face < 0) return Side::Unsure;
  const nurbs::TrimmedSurface& f = faces_[size_t(a.face)];
  if (on_domain_edge(f.surface, a.uv)) return Side::Unsure;
  const glm::dvec3 v = p - a.point;
  const double d = glm::length(v);
  if (!(d > a.point_bound) || !(d > 0.0)) return Side::Unsure;
  const double c = glm::dot(v / d, n);
  if (!std::isfinite(c) || std::abs(c) < kNormalCone) return Side::Unsure;
  return c > 0.0 ? Side::Outside : Side::Inside;
}

void SideTest::solids_at(const glm::dvec3& p, int except, std::vector<int>& out) const {
  out.clear();
  for (size_t s = 0; s < solids_.size(); ++s)
    if (int(s) != except && !solids_[s].faces.empty() && in_box(solids_[s].box, p, 0.0)) out.push_back(int(s));
}

std::vector<Side> SideTest::ask(const std::vector<Ask>& asks, bool both_ways, const std::vector<double>& near) {
  std::vector<Side> out(asks.size(), Side::Unsure);
  const size_t per = both_ways ? 6 : 3;
  std::vector<std::vector<size_t>> by_solid(solids_.size());
  for (size_t i = 0; i < asks.size(); ++i) by_solid[size_t(asks[i].solid)].push_back(i);
  for (size_t s = 0; s < solids_.size(); ++s) {
    const std::vector<size_t>& mine = by_solid[s];
    if (mine.empty()) continue;
    Solid& solid = solids_[s];
    if (!solid.caster) {
      std::vector<nurbs::TrimmedSurface> faces;
      faces.reserve(solid.faces.size());
      for (const int f : solid.faces) faces.push_back(faces_[size_t(f)]);
      solid.caster = std::make_unique<RayCaster>(std::move(faces), RayCasterOptions{});
    }
    std::vector<nurbs::ray::Ray> rays;
    rays.reserve(per * mine.size());
    for (const size_t i : mine)
      for (size_t r = 0; r < per; ++r) rays.push_back({asks[i].origin, r < 3 ? kRayDirections[r] : -kRayDirections[r - 3]});
    const std::vector<nurbs::ray::Hit> hits = solid.caster->cast(rays, 0.0);
    for (size_t m = 0; m < mine.size(); ++m) {
      const Ask& a = asks[mine[m]];
      int inside = 0, outside = 0;
      bool close = false;
      for (size_t r = 0; r < per; ++r) {
        const nurbs::ray::Hit& h = hits[per * m + r];
        if (h.face < 0) {
          ++outside;  // nothing met: the ray leaves the solid
          continue;
        }
        if (both_ways && !(h.t > near[a.k])) close = true;
        const glm::dvec3 dir = rays[per * m + r].direction;
        const double c = glm::dot(dir, nurbs::outward_normal(faces_[size_t(solid.faces[size_t(h.face)])], h.uv));
        if (!std::isfinite(c) || std::abs(c) < kGrazing) continue;
        (c > 0.0 ? inside : outside) += 1;  // leaving the solid through its face: the ray started inside
      }
      Side side = Side::Unsure;
      if (inside >= 2 && outside == 0) side = Side::Inside;
      if (outside >= int(per) - 1 && inside == 0) side = Side::Outside;
      out[mine[m]] = close ? Side::Unsure : side;
    }
  }
  return out;
}

std::vector<SideAnswer> SideTest::sides(std::span<const glm::dvec3> points, const std::vector<PointDistance>& answers,
                                        std::span<const glm::dvec3> normals) {
  std::vector<SideAnswer> out(points.size());
  std::vector<Side> normal(points.size(), Side::Unsure);
  nurbs::for_shares(points.size(), nurbs::share_count(points.size(), 256), [&](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) normal[i] = by_normal(points[i], answers[i], normals[i]);
  });
  // The solids each point still needs rays for: every solid whose box holds it, but the closest
  // face's where the normal put the point outside that one.
  std::vector<Ask> asks;
  std::vector<int> at;
  std::vector<char> by_rays(points.size(), 0);
  for (size_t k = 0; k < points.size(); ++k) {
    if (!answers[k].found) continue;
    if (normal[k] == Side::Inside) {
      out[k].side = Side::Inside;
      continue;
    }
    const int except = normal[k] == Side::Outside ? solid_of_face_[size_t(answers[k].face)] : -1;
    solids_at(points[k], except, at);
    out[k].side = Side::Outside;  // unless a solid below holds it, or cannot be shown not to
    by_rays[k] = normal[k] == Side::Unsure || !at.empty();
    for (const int s : at) asks.push_back({k, s, points[k]});
  }
  if (!asks.empty()) {
    const std::vector<Side> found = ask(asks, false, {});
    // Inside any solid is inside; else unsure where one solid's rays did not decide.
    for (size_t i = 0; i < asks.size(); ++i) {
      SideAnswer& a = out[asks[i].k];
      if (found[i] == Side::Inside) a.side = Side::Inside;
      else if (found[i] == Side::Unsure && a.side == Side::Outside) a.side = Side::Unsure;
    }
  }
  for (size_t k = 0; k < points.size(); ++k) {
    if (!answers[k].found) continue;
    if (out[k].side == Side::Unsure) ++figures_.unsure;
    else ++(by_rays[k] ? figures_.by_rays : figures_.by_normal);
  }
  if (solids_.size() < 2) return out;
  // The union's distance: a closest point inside or on another solid is not on its boundary.
  std::vector<Ask> hidden;
  std::vector<double> near(points.size(), 0.0);
  for (size_t k = 0; k < points.size(); ++k) {
    const PointDistance& a = answers[k];
    if (!a.found || out[k].side == Side::Outside) continue;
    near[k] = a.bound + a.point_bound;
    const int own = solid_of_face_[size_t(a.face)];
    for (size_t s = 0; s < solids_.size(); ++s)
      if (int(s) != own && !solids_[s].faces.empty() && in_box(solids_[s].box, a.point, near[k]))
        hidden.push_back({k, int(s), a.point});
  }
  if (hidden.empty()) return out;
  const std::vector<Side> found = ask(hidden, true, near);
  for (size_t i = 0; i < hidden.size(); ++i) {
    SideAnswer& a = out[hidden[i].k];
    if (found[i] != Side::Outside && a.hidden_by < 0) {
      a.hidden_by = hidden[i].solid;
      ++figures_.hidden;
    }
  }
  return out;
}

}  // namespace queries
