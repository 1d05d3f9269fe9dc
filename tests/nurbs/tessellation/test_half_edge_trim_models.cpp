// §6 + §7 (Balázs, Guthe, Klein 2004) on every face of every shared IGES model: the cells and loops
// come from the pipeline's §4-§5 stages (as tessellate.cpp builds them), the checks from
// test_half_edge_trim_oracle.h (area of the loops clipped to R, centroids material, crack-free).
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <glm/common.hpp>

#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/tessellation/surface_cells.h"
#include "nurbs/tessellation/trim_polyline.h"
#include "test_half_edge_trim_oracle.h"
#include "tests/shared_models.h"

using namespace half_edge_trim_test;

namespace {

/// Sutherland–Hodgman of one loop against the rectangle [lo, hi] (written for this test): the
/// material area of loops reaching outside R is the shoelace area of the clipped loops.
std::vector<glm::dvec2> clip_to(std::vector<glm::dvec2> p, glm::dvec2 lo, glm::dvec2 hi) {
  for (int side = 0; side < 4; ++side) {
    const int axis = side / 2;
    const double c = side % 2 ? hi[axis] : lo[axis], s = side % 2 ? 1.0 : -1.0;
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const glm::dvec2 a = p[i], b = p[(i + 1) % p.size()];
      const double da = s * (a[axis] - c), db = s * (b[axis] - c);
      if (da <= 0.0) out.push_back(a);
      if (da * db < 0.0) out.push_back(a + (b - a) * (da / (da - db)));
    }
    p = std::move(out);
  }
  return p;
}

}  // namespace

TEST_CASE("half-edge trim: every face of the shared IGES models (oracle checks)" * test::needs_shared_models()) {
  int faces = 0, polygons = 0, triangles = 0, paper = 0, fallback = 0, clipped = 0;
  double seconds = 0.0;
  for (const auto& path : test::shared_iges_files()) {
    const nurbs::Model model = nurbs::io::read_model(path);
    const double eps = 2e-3 * nurbs::model_size(model);
    for (const nurbs::TrimmedSurface& face : nurbs::world_faces(model)) {
      nurbs::tess::TrimApproxOptions to;
      to.eps = eps;
      const auto loops = nurbs::tess::approximate_trim_loops(face, to);
      glm::dvec2 lo(1e300), hi(-1e300);
      for (const auto& l : loops)
        for (glm::dvec2 p : l.uv) lo = glm::min(lo, p), hi = glm::max(hi, p);
      const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
      lo = glm::max(lo, glm::dvec2(du.min, dv.min));
      hi = glm::min(hi, glm::dvec2(du.max, dv.max));
      if (!(lo.x < hi.x && lo.y < hi.y)) continue;
      nurbs::tess::CellOptions co;
      co.eps_surface = eps;
      co.domain_u = nurbs::Interval{lo.x, hi.x};
      co.domain_v = nurbs::Interval{lo.y, hi.y};
      const auto cells = nurbs::tess::subdivide_surface(face.surface, co);
      const Bounds b = bounds(cells);
      double expected = 0.0, abs_terms = 0.0, perimeter = 0.0;
      bool any_outer = false;
      for (const auto& l : loops) {
        any_outer = any_outer || l.outer;
        const auto c = clip_to(l.uv, b.lo, b.hi);
        clipped += c != l.uv;
        expected += nurbs::signed_area(c);
        for (std::size_t i = 0; i < c.size(); ++i) {
          const glm::dvec2 p = c[i] - b.lo, q = c[(i + 1) % c.size()] - b.lo;
          abs_terms += std::abs(p.x * q.y) + std::abs(p.y * q.x);
          perimeter += glm::length(q - p);
        }
      }
      if (!any_outer) expected += (b.hi.x - b.lo.x) * (b.hi.y - b.lo.y);
      CAPTURE(path.filename().string());
      CAPTURE(faces);
      // Rounding of the shoelace sums (~1e-14 of the sum of |terms| for thousands of vertices) and the
      // library's snapping (coordinates move <= 1e-12 * size: area change <= perimeter * that).
      const double size = std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
      const double tol = 1e-12 + (1e-14 * abs_terms + 1e-12 * size * perimeter) / std::abs(expected);
      const Result r = run_and_check(cells, loops, expected, tol);
      ++faces;
      polygons += static_cast<int>(r.polys.polygons.size());
      triangles += static_cast<int>(r.tris.size());
      paper += r.polys.stats.paper_bridges;
      fallback += r.polys.stats.fallback_bridges;
      seconds += r.seconds;
    }
  }
  MESSAGE(faces << " faces (" << clipped << " loops clipped to R): " << polygons << " polygons, " << triangles
                << " triangles, " << paper << " paper bridges, " << fallback << " fallback bridges, " << seconds
                << " s in trim_cells + triangulate_polygons");
  CHECK(faces > 0);
}
