#include "queries/distance/material_distance.h"

#include <glm/geometric.hpp>

#include "queries/distance/clearance.h"

namespace queries {

const TrimEdges* FaceTrimEdges::operator()(int face) {
  if (m_.faces[size_t(face)].loops.empty()) return nullptr;
  auto it = index_.find(face);
  if (it == index_.end())
    it = index_.emplace(face, TrimEdges(m_.trims[size_t(face)], m_.grids[size_t(face)].grid)).first;
  return &it->second;
}

MaterialPair material_pair_distance(const MaterialTriangle& a, const MaterialTriangle& b, double below) {
  MaterialPair r;
  r.distance = below;
  // The pieces on each triangle.
  std::vector<TrimPiece> pa, pb;
  for (const auto& [t, out] : {std::pair{&a, &pa}, std::pair{&b, &pb}})
    if (t->trim && t->pieces)
      for (const TrimPiece& pc : *t->pieces)
        if (pc.triangle == t->triangle) out->push_back(pc);
  auto offer = [&](double d, glm::dvec3 xa, glm::dvec3 xb, glm::dvec2 uva, glm::dvec2 uvb) {
    if (!(d < r.distance)) return;
    r = {true, d, xa, xb, uva, uvb};
  };
  auto on = [](const glm::dvec2* uv, glm::dvec3 w) { return w.x * uv[0] + w.y * uv[1] + w.z * uv[2]; };
  {  // the closest points of the whole triangles, when both are material
    glm::dvec3 xa, xb, wa, wb;
    const double d = triangle_distance(a.p, b.p, xa, xb, wa, wb);
    const glm::dvec2 uva = on(a.uv, wa), uvb = on(b.uv, wb);
    if (d < r.distance && a.material(uva) && b.material(uvb)) offer(d, xa, xb, uva, uvb);
  }
  // A trim piece of one side against the other triangle, whose closest point must be material.
  for (int side = 0; side < 2; ++side) {
    const MaterialTriangle& o = side == 0 ? b : a;
    for (const TrimPiece& pc : side == 0 ? pa : pb) {
      double t;
      glm::dvec3 w;
      const double d = segment_triangle_distance(pc.a, pc.b, o.p, t, w);
      if (!(d < r.distance)) continue;
      const glm::dvec2 uvs = pc.uv_at(t), uvo = on(o.uv, w);
      if (!o.material(uvo)) continue;
      const glm::dvec3 xs = pc.a + t * (pc.b - pc.a), xo = w.x * o.p[0] + w.y * o.p[1] + w.z * o.p[2];
      if (side == 0)
        offer(d, xs, xo, uvs, uvo);
      else
        offer(d, xo, xs, uvo, uvs);
    }
  }
  // A trim piece of each side.
  for (const TrimPiece& x : pa)
    for (const TrimPiece& y : pb) {
      double s, t;
      const double d = segment_distance(x.a, x.b, y.a, y.b, s, t);
      if (!(d < r.distance)) continue;
      offer(d, x.a + s * (x.b - x.a), y.a + t * (y.b - y.a), x.uv_at(s), y.uv_at(t));
    }
  return r;
}

}  // namespace queries
