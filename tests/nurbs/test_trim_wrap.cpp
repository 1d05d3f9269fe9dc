// Loops of a face on a closed surface that the file places beyond the surface's domain (its seam
// elsewhere than the surface's) are brought inside it (trim_seams.h: wrap_loops_into_domain): the
// material they bound is the same set of surface points, all of it inside the domain.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "nurbs/curve_ends.h"
#include "nurbs/homogeneous.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "nurbs/trim_loops.h"
#include "nurbs/trim_seams.h"

namespace {

// A counter-clockwise rectangle [u0, u1] x [v0, v1] as the face's outer loop.
nurbs::TrimLoop rectangle(double u0, double u1, double v0, double v1) {
  nurbs::TrimLoop loop;
  const glm::dvec2 a(u0, v0), b(u1, v0), c(u1, v1), d(u0, v1);
  loop.curves = {nurbs::segment_curve(a, b), nurbs::segment_curve(b, c), nurbs::segment_curve(c, d),
                 nurbs::segment_curve(d, a)};
  return loop;
}

// The point of the original closed-in-u surface at u taken modulo its period.
glm::dvec3 periodic_point(const nurbs::Surface& s, double u, double v) {
  const nurbs::Interval d = nurbs::surface_domain_u(s);
  const double w = d.min + std::fmod(std::fmod(u - d.min, d.width()) + d.width(), d.width());
  return nurbs::surface_point(s, w, v);
}

/// A cylinder of radius 2 and height 3, and a band on it from a quarter to three quarters of its
/// height (v0 to v1, middle vm) going once round from a third of its period (`start`).
struct Band {
  nurbs::Surface cylinder = models::rational_cylinder(2.0, 3.0);
  nurbs::Interval du = nurbs::surface_domain_u(cylinder), dv = nurbs::surface_domain_v(cylinder);
  double period = du.width(), start = du.min + period / 3;
  double v0 = dv.min + 0.25 * dv.width(), v1 = dv.max - 0.25 * dv.width(), vm = 0.5 * (v0 + v1);
};

}  // namespace

TEST_CASE("trim wrap: a band whose loop runs past the far side of a cylinder's domain keeps all its material") {
  const Band b;
  const nurbs::Surface& cylinder = b.cylinder;
  const double period = b.period, start = b.start, v0 = b.v0, v1 = b.v1, vm = b.vm;
  nurbs::TrimmedSurface face;
  face.surface = cylinder;
  face.loops = {rectangle(start, start + period, v0, v1)};
  CHECK(nurbs::wrap_loops_into_domain(face, 1e-9, 1e-9) == 1);
  const nurbs::Interval wrapped = nurbs::surface_domain_u(face.surface);
  CHECK(wrapped.max >= start + period - 1e-12);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 1e-6);
  // Every angle round the band: material at the loop's parameter, and the same point in space.
  for (int k = 0; k < 36; ++k) {
    const double u = start + period * (k + 0.5) / 36;
    CHECK(nurbs::is_material(trim, glm::dvec2(u, vm)));
    CHECK(glm::length(nurbs::surface_point(face.surface, u, vm) - periodic_point(cylinder, u, vm)) < 1e-12);
  }
}

TEST_CASE("trim wrap: a loop a whole period beyond the domain moves by the period; open surfaces stay") {
  const nurbs::Surface cylinder = models::rational_cylinder(2.0, 3.0);
  const nurbs::Interval du = nurbs::surface_domain_u(cylinder), dv = nurbs::surface_domain_v(cylinder);
  nurbs::TrimmedSurface face;
  face.surface = cylinder;
  const double a = du.max + 0.1 * du.width(), b = du.max + 0.6 * du.width();
  face.loops = {rectangle(a, b, dv.min, dv.max)};
  CHECK(nurbs::wrap_loops_into_domain(face, 1e-9, 1e-9) == 1);
  CHECK(face.surface.count_u == cylinder.count_u);  // moved, the surface unchanged
  const glm::dvec2 first = nurbs::start_point(face.loops[0].curves[0]);
  CHECK(first.x == doctest::Approx(a - du.width()));

  nurbs::TrimmedSurface flat;
  flat.surface = models::bilinear_square(2.0);
  flat.loops = {rectangle(1.0, 3.0, 0.0, 1.0)};  // beyond the square, which does not close
  CHECK(nurbs::wrap_loops_into_domain(flat, 1e-9, 1e-9) == 0);
  CHECK(nurbs::start_point(flat.loops[0].curves[0]).x == 1.0);
}

TEST_CASE("trim wrap: the two circles of a band that start off the seam are cut there and closed into one loop") {
  // The band's lower circle runs once round from a third of the period, the upper one back: each
  // goes past the domain's far side, and neither closes in (u, v) without its seam segments.
  const Band b;
  const nurbs::Surface& cylinder = b.cylinder;
  const double period = b.period, start = b.start, v0 = b.v0, v1 = b.v1, vm = b.vm;
  nurbs::TrimmedSurface face;
  face.surface = cylinder;
  face.loops = {{{nurbs::segment_curve({start, v0}, {start + period, v0})}, true},
                {{nurbs::segment_curve({start + period, v1}, {start, v1})}, false}};
  CHECK(nurbs::wrap_loops_into_domain(face, 1e-9, 1e-9) == 1);
  CHECK(face.surface.count_u == cylinder.count_u);  // cut, not lengthened
  CHECK(nurbs::close_loops_round_seam(face, 1e-9, 1e-9) == 1);
  REQUIRE(face.loops.size() == 1);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 1e-6);
  for (int k = 0; k < 36; ++k) {
    const double u = b.du.min + period * (k + 0.5) / 36;
    CHECK(nurbs::is_material(trim, glm::dvec2(u, vm)));
    CHECK(!nurbs::is_material(trim, glm::dvec2(u, b.dv.min + 0.1 * b.dv.width())));
  }
}

TEST_CASE("trim wrap: a band whose upper loop dips back across the seam (a thread's run-out) keeps its dips") {
  // The lower circle runs once round at v0. The upper loop rises round the band from h1 to h3, then
  // crosses the seam at h3, dips back across it down to h2 (a tongue of material on the domain's
  // left side), runs down to h1 beside the right side (a notch cut out of the band) and crosses
  // the seam again at h1: three seam jumps. Both ways round either loop, as files give them.
  const Band b;
  const double u0 = b.du.min, u1 = b.du.max, P = b.period, v0 = b.v0;
  const double h1 = b.dv.min + 0.4 * b.dv.width(), h2 = b.dv.min + 0.55 * b.dv.width(),
               h3 = b.dv.min + 0.7 * b.dv.width();
  const std::vector<nurbs::Curve2> upper = {
      nurbs::segment_curve({u0 + 0.1 * P, h1}, {u1 - 0.1 * P, h3}), nurbs::segment_curve({u1 - 0.1 * P, h3}, {u1, h3}),
      nurbs::segment_curve({u0, h3}, {u0 + 0.05 * P, h3}), nurbs::segment_curve({u0 + 0.05 * P, h3}, {u0, h2}),
      nurbs::segment_curve({u1, h2}, {u1 - 0.05 * P, h1}), nurbs::segment_curve({u1 - 0.05 * P, h1}, {u1, h1}),
      nurbs::segment_curve({u0, h1}, {u0 + 0.1 * P, h1})};
  for (const int way : {0, 1, 2, 3}) {
    CAPTURE(way);
    const bool top_turned = way & 1, bottom_turned = way & 2;
    nurbs::TrimLoop top{upper, false};
    if (top_turned) {
      std::reverse(top.curves.begin(), top.curves.end());
      for (nurbs::Curve2& c : top.curves) c = nurbs::reversed(c);
    }
    nurbs::TrimmedSurface face;
    face.surface = b.cylinder;
    face.loops = {{{bottom_turned ? nurbs::segment_curve({u1, v0}, {u0, v0}) : nurbs::segment_curve({u0, v0}, {u1, v0})},
                   true},
                  top};
    CHECK(nurbs::close_loops_round_seam(face, 1e-9, 1e-9) == 3);  // the band and two dips
    // The notch is part of the band's loop, the tongue a loop of its own: no loops sharing a side.
    CHECK(face.loops.size() == 2);
    const std::vector<std::string> problems = nurbs::check_trim_loops(face, 1e-9, 1e-7);
    CHECK_MESSAGE(problems.empty(), problems.front());
    const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 1e-7);
    const auto material = [&](double u, double v) { return nurbs::is_material(trim, glm::dvec2(u, v)); };
    for (int k = 0; k < 36; ++k) {  // between the circle and h1 all round; nothing below the circle
      const double u = u0 + P * (k + 0.5) / 36;
      CHECK(material(u, 0.5 * (v0 + h1)));
      CHECK(!material(u, 0.5 * (b.dv.min + v0)));
    }
    CHECK(material(u0 + 0.5 * P, 0.5 * (h1 + h2)));    // under the rising edge
    CHECK(!material(u0 + 0.5 * P, h3 - 0.01 * P));     // above it
    CHECK(material(u1 - 0.02 * P, h3 - 0.1 * (h3 - h2)));  // under the top, beside the right side
    CHECK(!material(u1 - 0.01 * P, 0.5 * (h1 + h2)));  // the notch
    CHECK(material(u0 + 0.01 * P, h3 - 0.1 * (h3 - h2)));  // the tongue across the seam
    CHECK(!material(u0 + 0.01 * P, 0.5 * (h1 + h2)));  // beside it, above h1 on the left side
    CHECK(!material(u0 + 0.01 * P, h3 + 0.01));        // above the tongue
  }
}
