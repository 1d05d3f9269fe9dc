// Trims that OpenCASCADE's BRepCheck holds valid (nurbs/trim_loops.h, nurbs/trim_surface_gaps.h):
// a loop that meets itself only where the part between its two passes is one point in space (a
// pole), loops that enclose no area, and a loop missing a short edge, bridged as OCCT's healing
// does; against the same shapes where the meeting or the gap is real.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "models/exact_shapes.h"
#include "nurbs/curve_ends.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "nurbs/trim_loops.h"
#include "nurbs/trim_surface_gaps.h"

namespace {

nurbs::TrimLoop polygon_loop(const std::vector<glm::dvec2>& points, bool close = true) {
  nurbs::TrimLoop loop;
  loop.outer = true;
  for (size_t k = 0; k + (close ? 0 : 1) < points.size(); ++k)
    loop.curves.push_back(nurbs::segment_curve(points[k], points[(k + 1) % points.size()]));
  return loop;
}

// A loop that runs out along the top side v = 1, back along it, and down across its way out: it
// crosses itself 3e-5 below the top side (the DirectFET's pcurve at a pole).
const std::vector<glm::dvec2> kSpike = {{0, 0}, {1, 0}, {1, 0.9999}, {0, 1}, {0.5, 1}, {0, 0.999}};

std::vector<std::string> problems(const nurbs::TrimmedSurface& face, double touch, double* size = nullptr) {
  return nurbs::check_trim_loops(face, 1e-9, nurbs::flatten_trim(face, 1e-9), touch, size);
}

std::string first_problem(const nurbs::TrimmedSurface& face, double touch) {
  const std::vector<std::string> p = problems(face, touch);
  return p.empty() ? std::string() : p.front();
}

}  // namespace

TEST_CASE("trim touch: a loop meeting itself at a pole or in a lobe thinner than the tolerance is valid") {
  nurbs::TrimmedSurface face;
  face.face_id = 7;
  face.loops = {polygon_loop(kSpike)};
  // The top side collapsed to the apex (0.5, 1, 0): the part of the loop between the passes lies
  // within 1e-4 of it in space.
  face.surface = models::bilinear_patch({glm::dvec3(0, 0, 0), {1, 0, 0}, {0.5, 1, 0}, {0.5, 1, 0}});
  CHECK(problems(face, 0.0).front().find("face 7: loop 0 crosses itself") == 0);
  double size = -1.0;
  CHECK(problems(face, 1e-3, &size).empty());
  CHECK(size > 0.0);
  CHECK(size < 2e-4);  // the lobe lies within 5e-5 in v of the top side: about 1e-4 from the apex
  // On the plane the lobe spans half the square, yet runs along the loop's way out within 1e-3 of
  // it (its far end (0, 1) is 1e-3 above the way back at (0, 0.999)): a touch of that width, as
  // fitted curves crossing in a thin lobe; a tolerance below the width leaves it a crossing.
  face.surface = models::bilinear_square(1.0);
  double flat = -1.0;
  CHECK(problems(face, 2e-3, &flat).empty());
  CHECK(flat == doctest::Approx(1e-3).epsilon(0.05));
  CHECK(first_problem(face, 5e-4).find("face 7: loop 0 crosses itself") == 0);
  // A bow tie: both parts between the passes are half the square wide, a crossing at any tolerance
  // below that.
  face.loops = {polygon_loop({{0, 0}, {1, 0}, {0, 1}, {1, 1}})};
  CHECK(first_problem(face, 1e-2).find("face 7: loop 0 crosses itself") == 0);
}

TEST_CASE("trim touch: a sliver face whose long sides, as fitted, cross near its tip is valid") {
  // A sliver 0.002 wide at its right end (a KiCad diode bridge's face between two arcs of nearly
  // one circle): the top side dips 3e-4 below the bottom one before it reaches the tip, crossing it
  // twice. The lobes beyond the crossings are thinner than 5e-4 in space.
  nurbs::TrimmedSurface face;
  face.face_id = 9;
  face.surface = models::bilinear_patch({glm::dvec3(0, 0, 0), {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  face.loops = {polygon_loop({{0, 0.01}, {1, 0.01}, {1, 0.012}, {0.1, 0.0105}, {0.02, 0.0097}, {0, 0.0102}})};
  CHECK(first_problem(face, 0.0).find("face 9: loop 0 crosses itself") == 0);
  double size = -1.0;
  CHECK(problems(face, 1e-3, &size).empty());
  CHECK(size > 1e-4);
  CHECK(size < 5e-4);
  CHECK(first_problem(face, 1e-4).find("face 9: loop 0 crosses itself") == 0);
}

TEST_CASE("trim touch: loops that enclose no area meet anything without crossing it") {
  // A degenerate face (SOD-323): two loops, each a segment out and back, over each other.
  nurbs::TrimmedSurface face;
  face.face_id = 1859;
  face.surface = models::bilinear_square(1.0);
  face.loops = {polygon_loop({{0.2, 0.1}, {0.2, 0.9}}), polygon_loop({{0.2, 0.9}, {0.2, 0.1}})};
  CHECK(problems(face, 0.0).front().find("face 1859: loops 0 and 1 cross") == 0);
  CHECK(problems(face, 1e-3).empty());
  // A loop with area crossing one that has none: still a touch (the latter bounds nothing).
  face.loops = {polygon_loop({{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}}), polygon_loop({{0.05, 0.5}, {0.5, 0.5}})};
  CHECK(problems(face, 1e-3).empty());
  // Two loops with area crossing each other stay a crossing.
  face.loops = {polygon_loop({{0.1, 0.1}, {0.6, 0.1}, {0.6, 0.6}, {0.1, 0.6}}),
                polygon_loop({{0.4, 0.4}, {0.9, 0.4}, {0.9, 0.9}, {0.4, 0.9}})};
  CHECK(problems(face, 1e-3).front().find("loops 0 and 1 cross") != std::string::npos);
}

TEST_CASE("trim bridge: a loop missing a short edge is closed, its length returned for the edge gap") {
  // Three sides of the unit square of a plane 10 wide: the fourth, 1 long, is missing.
  nurbs::TrimmedSurface face;
  face.surface = models::bilinear_square(10.0);
  face.loops = {polygon_loop({{2, 2}, {3, 2}, {3, 3}, {2, 3}}, false)};
  int added = 0;
  CHECK(nurbs::bridge_open_joints(face, 0.5, 1e-9, added) == 0.0);  // over the cap: left open
  CHECK(added == 0);
  CHECK(face.loops[0].curves.size() == 3);
  CHECK(nurbs::bridge_open_joints(face, 1.5, 1e-9, added) == doctest::Approx(1.0));
  CHECK(added == 1);
  REQUIRE(face.loops[0].curves.size() == 4);
  CHECK(nurbs::check_trim_loops(face, 1e-9, 1e-9).empty());

  // Round three sides of the whole domain, the side u = 10 missing (10 long, over the cap): the
  // missing edge is the surface's own side, closed exactly along it, the boundary moved by nothing.
  // The same gap 1 inside the side (u = 9): no side of the domain, over the cap, left open.
  for (const double u : {10.0, 9.0}) {
    face.loops = {polygon_loop({{u, 10}, {0, 10}, {0, 0}, {u, 0}}, false)};
    int side = 0;
    CHECK(nurbs::bridge_open_joints(face, 0.5, 1e-9, side) == 0.0);
    CHECK(side == (u == 10.0 ? 1 : 0));
    CHECK(nurbs::check_trim_loops(face, 1e-9, 1e-9).empty() == (u == 10.0));
  }

  // Across a cylinder's seam the straight (u, v) segment turns round the surface: its image is
  // far longer than the gap's chord, so it is no bridge.
  nurbs::TrimmedSurface tube;
  tube.surface = models::rational_cylinder(1.0, 4.0);
  const nurbs::Interval du = nurbs::surface_domain_u(tube.surface);
  const nurbs::Interval dv = nurbs::surface_domain_v(tube.surface);  // along the axis, 4 high
  const double a = du.min + 0.01 * du.width(), b = du.max - 0.01 * du.width();
  const double v1 = dv.min + 0.25 * dv.width(), v3 = dv.min + 0.75 * dv.width();
  // Round the tube at heights 1 and 3 (v1, v3), the side back down along the axis missing: bridged,
  // 2 long.
  tube.loops = {polygon_loop({{a, v1}, {b, v1}, {b, v3}, {a, v3}}, false)};
  added = 0;
  CHECK(nurbs::bridge_open_joints(tube, 10.0, 1e-9, added) == doctest::Approx(2.0));
  CHECK(added == 1);
  // Two sides along the axis at u = b and u = a: the (u, v) segments joining them cross the domain,
  // round the tube the long way (0.98 of a turn for a chord of 0.13): left open.
  tube.loops = {polygon_loop({{b, v1}, {b, v3}}, false), polygon_loop({{a, v3}, {a, v1}}, false)};
  tube.loops[0].curves.push_back(tube.loops[1].curves.front());
  tube.loops.pop_back();
  added = 0;
  CHECK(nurbs::bridge_open_joints(tube, 10.0, 1e-9, added) == 0.0);
  CHECK(added == 0);
  CHECK(!nurbs::check_trim_loops(tube, 1e-9, 1e-9).empty());  // the seam jump stays open
}

TEST_CASE("trim bridge: two faces that both skip one edge get one edge number for their two bridges") {
  // Two squares of the plane z = 0 side by side, [0, 1] and [1, 2] in x: each loop skips the
  // shared side x = 1 (as a file's loops that both leave out an edge), bridged by the repair (-1).
  auto square = [](double x0, int first_edge, bool skip_right) {
    nurbs::TrimmedSurface f;
    f.surface = models::bilinear_patch({glm::dvec3(x0, 0, 0), {x0 + 1, 0, 0}, {x0, 1, 0}, {x0 + 1, 1, 0}});
    f.loops = {polygon_loop({{0, 0}, {1, 0}, {1, 1}, {0, 1}})};
    for (size_t k = 0; k < 4; ++k) f.loops[0].curves[k].edge = first_edge + int(k);
    f.loops[0].curves[skip_right ? 1 : 3].edge = -1;
    return f;
  };
  // Another body's face bridging the same two points, its edges up to 29: no partner across
  // bodies, and the new number lies above every edge of the model.
  const glm::dmat4 at(1.0);
  std::vector<nurbs::Body> model{{"pair", {square(0, 0, true), square(1, 10, false)}, at, {}},
                                 {"other", {square(1, 27, false)}, at, {}}};
  CHECK(nurbs::pair_added_edges(model, 1e-6) == 1);
  CHECK(model[0].faces[0].loops[0].curves[1].edge == 30);
  CHECK(model[0].faces[1].loops[0].curves[3].edge == 30);
  CHECK(model[0].faces[0].loops[0].curves[0].edge == 0);  // the file's own edges keep their numbers
  CHECK(model[1].faces[0].loops[0].curves[3].edge == -1);
  // A third face of the body bridging the same two points: no pair is certain, none is numbered.
  std::vector<nurbs::Body> three{{"three", {square(0, 0, true), square(1, 10, false), square(1, 20, false)}, at, {}}};
  CHECK(nurbs::pair_added_edges(three, 1e-6) == 0);
  CHECK(three[0].faces[0].loops[0].curves[1].edge == -1);
}

TEST_CASE("trim touch: loops meeting at a vertex they share are valid, crossing there by a stretch is not") {
  nurbs::TrimmedSurface face;
  face.face_id = 624;
  face.surface = models::bilinear_square(1.0);
  // A hole whose corner is a vertex of the outline's right side (the outline split there), as a
  // 5 mm LED's flange writes its hole against the flat.
  const nurbs::TrimLoop outline = polygon_loop({{0.1, 0.1}, {0.8, 0.1}, {0.8, 0.5}, {0.8, 0.9}, {0.1, 0.9}});
  face.loops = {outline, polygon_loop({{0.8, 0.5}, {0.6, 0.65}, {0.4, 0.5}, {0.6, 0.35}})};
  face.loops[1].outer = false;
  CHECK(first_problem(face, 0.0).find("face 624: loops 0 and 1 cross") == 0);
  CHECK(problems(face, 1e-3).empty());
  // One loop through that vertex twice: along the bottom to its middle, round the hole the other
  // way, on along the bottom.
  face.loops = {polygon_loop({{0.1, 0.1}, {0.5, 0.1}, {0.3, 0.3}, {0.5, 0.5}, {0.7, 0.3}, {0.5, 0.1}, {0.8, 0.1},
                              {0.8, 0.9}, {0.1, 0.9}})};
  CHECK(first_problem(face, 0.0).find("face 624: loop 0 crosses itself") == 0);
  CHECK(problems(face, 1e-3).empty());
  // The hole moved 0.1 to the right runs out of the outline between vertices: a crossing.
  face.loops = {outline, polygon_loop({{0.9, 0.5}, {0.7, 0.65}, {0.5, 0.5}, {0.7, 0.35}})};
  face.loops[1].outer = false;
  CHECK(first_problem(face, 1e-3).find("face 624: loops 0 and 1 cross near (u, v) = (0.8, 0.575)") == 0);
}

TEST_CASE("trim touch: a hole tangent to the outline, fitted a hair beyond it, touches; one a stretch beyond crosses") {
  // The hole a 48-gon of radius 0.25 tangent to the outline's right side x = 0.8 at (0.8, 0.5),
  // pushed `out` beyond it: its points past the side lie at most `out` from it.
  nurbs::TrimmedSurface face;
  face.face_id = 78;
  face.surface = models::bilinear_square(1.0);
  const auto hole = [](double out) {
    std::vector<glm::dvec2> points;
    for (int k = 0; k < 48; ++k) {
      const double a = -2.0 * M_PI * k / 48;  // clockwise: a hole
      points.emplace_back(0.55 + out + 0.25 * std::cos(a), 0.5 + 0.25 * std::sin(a));
    }
    nurbs::TrimLoop loop = polygon_loop(points);
    loop.outer = false;
    return loop;
  };
  face.loops = {polygon_loop({{0.1, 0.1}, {0.8, 0.1}, {0.8, 0.9}, {0.1, 0.9}}), hole(1e-4)};
  CHECK(first_problem(face, 0.0).find("face 78: loops 0 and 1 cross") == 0);
  double size = -1.0;
  CHECK(problems(face, 1e-3, &size).empty());
  CHECK(size == doctest::Approx(1e-4).epsilon(1e-6));
  face.loops[1] = hole(0.02);
  CHECK(first_problem(face, 1e-3).find("face 78: loops 0 and 1 cross") == 0);
  CHECK(problems(face, 0.03).empty());  // within a touch tolerance beyond its 0.02
}
