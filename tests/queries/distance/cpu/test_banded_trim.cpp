// The band index of the trim polygons (queries/distance/point_batch_trim.h: BandedTrim), shared by the
// batched projection and the coarse-to-fine refinement, against plain references on random trimmed
// faces: the winding-number classification of nurbs::is_material and an edge-by-edge box test.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/point_batch_trim.h"

namespace {

/// The trim polygons of the banded-trim tests: 12 random trimmed faces and the trimmed 100 x 105 surface.
std::vector<nurbs::TrimPolygons> banded_test_trims() {
  std::vector<nurbs::TrimmedSurface> faces;
  for (uint64_t seed = 0; seed < 12; ++seed) faces.push_back(models::random_trimmed_surface(seed));
  faces.push_back(models::trimmed_wavy_surface_100x105());
  std::vector<nurbs::TrimPolygons> out;
  for (const auto& f : faces)
    if (!f.loops.empty()) out.push_back(nurbs::flatten_trim(f, 1e-6 * nurbs::surface_domain_u(f.surface).width()));
  return out;
}

}  // namespace

TEST_CASE("banded trim: classification equals nurbs::is_material") {
  // Random trimmed faces, the trimmed 100 x 105 surface; random (u, v) and every polygon vertex and
  // edge midpoint (the ties of the half-open rule).
  models::Random rng(17);
  long long checked = 0, material = 0, differ = 0;
  for (const nurbs::TrimPolygons& t : banded_test_trims()) {
    const queries::BandedTrim banded(t);
    std::vector<glm::dvec2> uvs;
    for (int k = 0; k < 2000; ++k)
      uvs.emplace_back(rng.uniform(t.domain_u.min, t.domain_u.max), rng.uniform(t.domain_v.min, t.domain_v.max));
    for (const auto& loop : t.loops)
      for (size_t e = 0; e < loop.size(); ++e)
        uvs.insert(uvs.end(), {loop[e], 0.5 * (loop[e] + loop[(e + 1) % loop.size()])});
    for (const glm::dvec2& uv : uvs) {
      const bool want = nurbs::is_material(t, uv);
      differ += banded.is_material(uv) != want;
      material += want;
      ++checked;
    }
  }
  CHECK(differ == 0);
  CHECK(material > checked / 10);
  MESSAGE(checked << " (u, v) classified, " << material << " material, " << differ << " differ");
}

namespace {

/// Orientation of c against the line ab (> 0: left).
double orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Whether segment ab meets the box [lo, hi], by another route than the clipping under test: an end
/// inside, or a proper crossing of one of the box's four sides.
bool segment_meets_box_reference(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi) {
  auto inside = [&](glm::dvec2 p) { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; };
  if (inside(a) || inside(b)) return true;
  const glm::dvec2 c[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  for (int k = 0; k < 4; ++k) {
    const glm::dvec2 p = c[k], q = c[(k + 1) % 4];
    if (orient(a, b, p) * orient(a, b, q) < 0 && orient(p, q, a) * orient(p, q, b) < 0) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("banded trim: the edge-box query equals a test of every edge") {
  // Boxes from a thousandth of the domain to a half a side, some thin as a refined cell; the answer of
  // BandedTrim::meets_box against every edge of every loop tested with the reference.
  models::Random rng(23);
  long long checked = 0, met = 0, differ = 0;
  for (const nurbs::TrimPolygons& t : banded_test_trims()) {
    const queries::BandedTrim banded(t);
    const double wu = t.domain_u.width(), wv = t.domain_v.width();
    for (int k = 0; k < 3000; ++k) {
      const double su = wu * std::pow(10.0, rng.uniform(-3.0, -0.3)), sv = wv * std::pow(10.0, rng.uniform(-3.0, -0.3));
      const glm::dvec2 lo(rng.uniform(t.domain_u.min - su, t.domain_u.max),
                          rng.uniform(t.domain_v.min - sv, t.domain_v.max));
      const glm::dvec2 hi = lo + glm::dvec2(su, sv);
      bool want = false;
      for (const auto& loop : t.loops)
        for (size_t e = 0; e < loop.size() && !want; ++e)
          want = segment_meets_box_reference(loop[e], loop[(e + 1) % loop.size()], lo, hi);
      differ += banded.meets_box(lo, hi) != want;
      met += want;
      ++checked;
    }
  }
  CHECK(differ == 0);
  CHECK(met > checked / 10);
  CHECK(met < checked * 9 / 10);
  MESSAGE(checked << " boxes, " << met << " met by a trim edge, " << differ << " differ");
}
