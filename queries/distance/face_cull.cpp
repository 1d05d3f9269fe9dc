#include "queries/distance/face_cull.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <utility>

#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace queries {

namespace {

/// A face's material sample points (world coordinates, before any motion): the centres of an
/// n x n split of its domain that its trim polygons (flattened coarsely, within 1e-3 of the domain)
/// say are material and that lie farther than 4 times that from them, so that the true trim curves
/// agree (a sample near a trim is dropped, never misjudged).
std::vector<glm::dvec3> material_samples(const nurbs::TrimmedSurface& f, int n) {
  const nurbs::Interval du = nurbs::surface_domain_u(f.surface), dv = nurbs::surface_domain_v(f.surface);
  std::vector<glm::dvec3> out;
  nurbs::TrimPolygons trim;
  const double tol = 1e-3 * std::max(du.width(), dv.width());
  if (!f.loops.empty()) trim = nurbs::flatten_trim(f, tol);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 uv(du.min + du.width() * (i + 0.5) / n, dv.min + dv.width() * (j + 0.5) / n);
      if (!f.loops.empty() && (!nurbs::is_material(trim, uv) || nurbs::distance_to_loops(trim, uv) <= 4.0 * tol)) continue;
      out.push_back(nurbs::surface_point(f.surface, uv.x, uv.y));
    }
  return out;
}

struct FaceData {
  nurbs::Box box;
  std::vector<glm::dvec3> samples;
};

std::vector<FaceData> face_data(const std::vector<nurbs::TrimmedSurface>& faces, int n) {
  std::vector<FaceData> out(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) out[f] = {nurbs::control_box(faces[f].surface), material_samples(faces[f], n)};
  return out;
}

}  // namespace

size_t FaceCull::kept_a() const { return size_t(std::count(keep_a.begin(), keep_a.end(), 1)); }
size_t FaceCull::kept_b() const { return size_t(std::count(keep_b.begin(), keep_b.end(), 1)); }

FaceCull cull_faces(const std::vector<nurbs::TrimmedSurface>& a, const std::vector<nurbs::TrimmedSurface>& b,
                    std::span<const glm::dmat4> motions_b, double margin, int samples) {
  FaceCull out;
  out.keep_a.assign(a.size(), 0);
  out.keep_b.assign(b.size(), 0);
  const std::vector<FaceData> da = face_data(a, samples), db = face_data(b, samples);
  for (const glm::dmat4& m : motions_b) {
    // B's faces moved: their control points' box (the box of the moved control points holds the
    // moved face), and their samples.
    std::vector<FaceData> mb(b.size());
    for (size_t g = 0; g < b.size(); ++g) {
      bool first = true;
      for (const glm::dvec3& p : b[g].surface.points) {
        const glm::dvec3 q(m * glm::dvec4(p, 1.0));
        mb[g].box.min = first ? q : glm::min(mb[g].box.min, q);
        mb[g].box.max = first ? q : glm::max(mb[g].box.max, q);
        first = false;
      }
      for (const glm::dvec3& p : db[g].samples) mb[g].samples.emplace_back(m * glm::dvec4(p, 1.0));
    }
    // Face pairs by their boxes' distance, nearest first.
    std::vector<std::pair<double, std::pair<uint32_t, uint32_t>>> pairs;
    pairs.reserve(a.size() * b.size());
    for (size_t f = 0; f < a.size(); ++f)
      for (size_t g = 0; g < b.size(); ++g)
        pairs.push_back({nurbs::box_distance(da[f].box, mb[g].box),
                         {uint32_t(f), uint32_t(g)}});
    std::sort(pairs.begin(), pairs.end());
    double upper = std::numeric_limits<double>::infinity();
    for (const auto& [d, fg] : pairs) {
      if (d >= upper) break;  // no farther pair has samples nearer than U
      for (const glm::dvec3& p : da[fg.first].samples)
        for (const glm::dvec3& q : mb[fg.second].samples) upper = std::min(upper, glm::distance(p, q));
    }
    upper += margin;  // (+inf when no face has a material sample: every pair kept)
    out.upper = upper;
    for (const auto& [d, fg] : pairs) {
      if (d > upper) break;
      out.keep_a[fg.first] = 1, out.keep_b[fg.second] = 1;
      ++out.pairs;
    }
  }
  return out;
}

}  // namespace queries
