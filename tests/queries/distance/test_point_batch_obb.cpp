// The oriented box pyramid of the batched point projection (point_batch.h, PointBoxes::Oriented):
// every box holds its cell's four samples (so its two triangles), or for a cell a trim edge crosses
// the material part of its triangles, or its children's boxes, in double
// for the stored floats; the descent finds the same nearest triangles as over the axis-aligned
// pyramid, testing far fewer cells.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <map>

#include "tests/gpgpu/gl_fixture.h"
#include "models/paper_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/prepared_model.h"
#include "tests/queries/distance/point_batch_fixtures.h"

namespace {

struct Obb {
  glm::dvec3 c, a[3], e;
  bool empty;
};

/// Atlas 0's oriented levels as uploaded (every texel), expanded once per level.
struct Levels {
  const queries::PointBatch& b;
  std::map<int, std::array<std::vector<float>, 3>> cache;
  const std::array<std::vector<float>, 3>& operator()(int level) {
    auto [it, fresh] = cache.try_emplace(level);
    if (fresh)
      for (int k = 0; k < 3; ++k) it->second[size_t(k)] = b.oriented_level(0, level, k);
    return it->second;
  }
};

Obb node(Levels& levels, int level, size_t texel) {
  const auto& l = levels(level);
  const float *c = &l[0][4 * texel], *t = &l[1][4 * texel], *n = &l[2][4 * texel];
  Obb o;
  o.c = {c[0], c[1], c[2]};
  o.a[0] = {t[0], t[1], t[2]};
  o.a[2] = {n[0], n[1], n[2]};
  o.a[1] = glm::cross(o.a[2], o.a[0]);
  o.e = {c[3], t[3], n[3]};
  o.empty = c[3] < 0.0f;
  return o;
}

/// How far p lies outside box o along its axes (<= 0: inside), relative to the box's size.
double outside(const Obb& o, const glm::dvec3& p) {
  double worst = -HUGE_VAL;
  for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(glm::dot(o.a[i], p - o.c)) - o.e[i]);
  return worst / (glm::length(o.e) + glm::length(o.c));
}

}  // namespace

TEST_CASE("point batch: oriented boxes hold their cells' samples and their children's boxes") {
  gpgpu::Gpu& gpu = test::gpu();
  const auto faces = test::spread_faces(5);
  const queries::PreparedModel m = queries::prepare_model(gpu, faces, 5e-3);
  REQUIRE(m.atlases.size() == 1);
  const queries::PointBatch batch(gpu, m, queries::PointBoxes::Oriented);
  const std::vector<float> samples = m.atlases[0].points.read();
  const int w = m.atlases[0].plan.width;
  const glm::vec3 origin(m.centre);
  int leaves = 0, thin = 0, trimmed_cells = 0, smaller = 0;
  double worst = -HUGE_VAL, worst_material = -HUGE_VAL;
  const int width0 = batch.level_width(0, 0);
  Levels levels{batch, {}};
  for (size_t t = 0; t < levels(0)[0].size() / 4; ++t) {
    const Obb o = node(levels, 0, t);
    if (o.empty) continue;
    ++leaves;
    const int x = int(t % size_t(width0)), y = int(t / size_t(width0));
    REQUIRE(x + 1 < w);
    glm::dvec3 corner[4];
    for (int k = 0; k < 4; ++k) {
      const float* s = &samples[4 * (size_t(y + (k >> 1)) * size_t(w) + size_t(x + (k & 1)))];
      corner[k] = glm::dvec3(glm::vec3(s[0], s[1], s[2]) - origin);
    }
    const auto cell = m.cell_at(0, x, y);
    REQUIRE(cell.has_value());
    const nurbs::TrimPolygons& trim = m.trims[size_t(cell->face)];
    bool crossed = false;
    if (!trim.loops.empty()) {
      const nurbs::ParamGrid& g = m.grids[size_t(cell->face)].grid;
      crossed = queries::BandedTrim(trim).meets_box({g.u[size_t(cell->i)], g.v[size_t(cell->j)]},
                                                   {g.u[size_t(cell->i) + 1], g.v[size_t(cell->j) + 1]});
    }
    if (!crossed) {  // the whole cell: its four samples, exactly
      for (const glm::dvec3& c : corner) worst = std::max(worst, outside(o, c));
    } else {
      // A cell a trim edge crosses holds only its material part: every material point of a 12 x 12
      // barycentric grid on each triangle (nurbs::is_material, independent of the pass's trim data)
      // lies in the box, up to the float rounding of the stored trim pieces (1e-6 of the box).
      ++trimmed_cells;
      const nurbs::ParamGrid& g = m.grids[size_t(cell->face)].grid;
      const double u0 = g.u[size_t(cell->i)], du = g.u[size_t(cell->i) + 1] - u0;
      const double v0 = g.v[size_t(cell->j)], dv = g.v[size_t(cell->j) + 1] - v0;
      bool outside_some = false;
      for (int a = 0; a <= 12; ++a)
        for (int b = 0; a + b <= 12; ++b)
          for (int tri = 0; tri < 2; ++tri) {
            const double wa = a / 12.0, wb = b / 12.0, wc = 1.0 - wa - wb;
            // triangle 0: corners 0, 1, 3 at (0, 0), (1, 0), (1, 1); triangle 1: 0, 3, 2 at (0, 0), (1, 1), (0, 1)
            const glm::dvec2 st = tri == 0 ? glm::dvec2(wb + wc, wc) : glm::dvec2(wb, wb + wc);
            const glm::dvec3 pt = tri == 0 ? wa * corner[0] + wb * corner[1] + wc * corner[3]
                                           : wa * corner[0] + wb * corner[3] + wc * corner[2];
            const double out = outside(o, pt);
            if (nurbs::is_material(trim, {u0 + st.x * du, v0 + st.y * dv}))
              worst_material = std::max(worst_material, out);
            else
              outside_some = outside_some || out > 1e-6;
          }
      smaller += outside_some;
    }
    thin += o.e.z < 0.1 * std::min(o.e.x, o.e.y);  // as thick as the cell is curved, not as it is wide
  }
  CHECK(worst <= 1e-15);
  CHECK(worst_material <= 1e-6);
  CHECK(trimmed_cells > 20);
  CHECK(smaller > 0);  // some crossed cells' boxes leave trimmed-away parts out
  CHECK(leaves > 100);
  CHECK(thin * 10 >= leaves * 9);
  // Children inside their parents: every corner of every child box.
  double worst_child = -HUGE_VAL;
  for (int l = 1; l < batch.levels(0); ++l) {
    const int pw = batch.level_width(0, l), cw = batch.level_width(0, l - 1);
    const size_t ct = levels(l - 1)[0].size() / 4;
    for (size_t t = 0; t < ct; ++t) {
      const Obb c = node(levels, l - 1, t);
      if (c.empty) continue;
      const int x = int(t % size_t(cw)) / 2, y = int(t / size_t(cw)) / 2;
      const Obb p = node(levels, l, size_t(y) * size_t(pw) + size_t(x));
      REQUIRE(!p.empty);
      for (int k = 0; k < 8; ++k)
        worst_child = std::max(
            worst_child, outside(p, c.c + ((k & 1) ? c.e.x : -c.e.x) * c.a[0] + ((k & 2) ? c.e.y : -c.e.y) * c.a[1] +
                                        ((k & 4) ? c.e.z : -c.e.z) * c.a[2]));
    }
  }
  CHECK(worst_child <= 1e-15);
  MESSAGE(leaves << " cells: samples outside their boxes by at most " << worst << ", material points of "
                 << trimmed_cells << " crossed cells by " << worst_material << " (" << smaller
                 << " boxes leave trimmed parts out), children by " << worst_child
                 << " (relative); " << thin << " boxes thinner than a tenth of their width");
}

TEST_CASE("point batch: oriented and axis-aligned pyramids find the same nearest triangles") {
  // The paper's 100 x 105 surface and points in its wave band: the axis-aligned boxes of the tilted
  // cells make every point test many cells; the oriented ones few. Both descents end at the least
  // triangle distance (within the pass's float slack twice).
  gpgpu::Gpu& gpu = test::gpu();
  std::vector<nurbs::TrimmedSurface> faces(1);
  faces[0].surface = models::wavy_surface_100x105();
  const double size = nurbs::control_box(faces[0].surface).diagonal();
  const queries::PreparedModel m = queries::prepare_model(gpu, faces, 1e-4 * size);
  queries::PointBatch aabb(gpu, m, queries::PointBoxes::Aabb), obb(gpu, m, queries::PointBoxes::Oriented);
  models::Random rng(3);
  std::vector<glm::dvec3> points;
  for (int k = 0; k < 400; ++k) points.emplace_back(rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(11, 29));
  const auto a = aabb.descend_gpu(points), o = obb.descend_gpu(points);
  long long tested_a = 0, tested_o = 0;
  double worst = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    CAPTURE(i);
    REQUIRE(!a[0][i].cut);
    REQUIRE(!o[0][i].cut);
    const double eps = obb.slack(points[i]);
    CHECK(std::abs(a[0][i].distance - o[0][i].distance) <= 2 * eps);
    worst = std::max(worst, std::abs(a[0][i].distance - o[0][i].distance) / eps);
    // The twin of the oriented pass.
    CHECK(std::abs(obb.descend_cpu(0, points[i]).distance - o[0][i].distance) <= 2 * eps);
    tested_a += a[0][i].tested, tested_o += o[0][i].tested;
  }
  MESSAGE(points.size() << " wave-band points: cells tested per point " << double(tested_a) / double(points.size())
                        << " (axis-aligned) against " << double(tested_o) / double(points.size())
                        << " (oriented); distances differ by at most " << worst << " eps");
  CHECK(tested_o * 4 <= tested_a);
}
