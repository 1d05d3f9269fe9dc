// Tests of §6 (half_edge_trim.h) and, through it, §7 (triangulate.h) of Balázs, Guthe, Klein 2004:
// table cases with known answers. Oracle: test_half_edge_trim_oracle.h.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "test_half_edge_trim_oracle.h"
#include "test_suites.h"

using namespace half_edge_trim_test;

TEST_CASE("half-edge trim: no trims, outer loop = R's boundary, kd tiling with T-junctions") {
  std::mt19937_64 rng(7);
  std::vector<Cell> cells;
  kd_split(cell(0.5, 2.0, -1.0, 0.25), 6, rng, cells);
  const auto boundary = loop({{0.5, -1.0}, {2.0, -1.0}, {2.0, 0.25}, {0.5, 0.25}}, true);
  auto r = run_and_check(cells, {boundary}, 1.5 * 1.25);
  CHECK(r.polys.polygons.size() == cells.size());  // one polygon per cell
  auto r2 = run_and_check(cells, {}, 1.5 * 1.25);  // no loop at all: R is the outer loop
  CHECK(r2.polys.polygons.size() == cells.size());
  CHECK(r2.tstats.nonconvex_polygons == 0);
  CHECK(r2.tstats.degenerate_triangles == 0);
}

TEST_CASE("half-edge trim: square hole strictly inside one cell gets the two paper bridges") {
  const auto cells = grid(0, 1, 0, 1, 4, 4);
  const auto hole = loop({{0.3, 0.3}, {0.3, 0.45}, {0.45, 0.45}, {0.45, 0.3}}, false);
  auto r = run_and_check(cells, {hole}, 1.0 - 0.15 * 0.15);
  CHECK(r.polys.stats.paper_bridges == 2);
  CHECK(r.polys.stats.fallback_bridges == 0);
  CHECK(r.polys.polygons.size() == 17);  // the holed cell is cut in two
}

TEST_CASE("half-edge trim: circle hole across many cells, tiny hole, two holes in one cell") {
  const auto cells = grid(0, 1, 0, 1, 8, 8);
  const auto c = circle({0.5, 0.5}, 0.3, 200, false);
  run_and_check(cells, {c}, 1.0 + nurbs::signed_area(c.uv));
  // 1e-6 of R: still two bridges, still exact area.
  const auto tiny = circle({0.06, 0.07}, 1e-6, 8, false);
  auto r = run_and_check(cells, {c, tiny}, 1.0 + nurbs::signed_area(c.uv) + nurbs::signed_area(tiny.uv));
  CHECK(r.polys.stats.paper_bridges == 2);
  // Two holes in one cell: the second is bridged by the fallback after the first traversal.
  const auto h1 = circle({0.03, 0.9}, 0.01, 12, false), h2 = circle({0.09, 0.96}, 0.01, 12, false);
  auto r2 = run_and_check(cells, {h1, h2}, 1.0 + nurbs::signed_area(h1.uv) + nurbs::signed_area(h2.uv));
  CHECK(r2.polys.stats.paper_bridges == 4);  // the second hole's bridges avoid the first's
  // Nested in one cell: hole, island in the hole, hole in the island. The innermost hole cannot see
  // the cell corners (the island is in the way): it is bridged to the island by the fallback.
  const auto outer_hole = circle({0.06, 0.06}, 0.05, 16, false), island = circle({0.06, 0.06}, 0.03, 16, true),
             inner_hole = circle({0.06, 0.06}, 0.01, 16, false);
  // (The island is an outer loop, so R's boundary must be given as one too.)
  const std::vector<LoopPolyline> nested{loop({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, true), outer_hole, island, inner_hole};
  auto r3 = run_and_check(cells, nested, loops_area(nested));
  CHECK(r3.polys.stats.paper_bridges == 2);
  CHECK(r3.polys.stats.fallback_bridges == 2);
  CHECK(r3.polys.stats.traversal_rounds == 2);
}

TEST_CASE("half-edge trim: holes no bridge can reach (corners cut off, holes side by side) get their cells cut") {
  // A plane is one cell. Its outer loop cuts off the corners of the cell (a chamfered connector
  // face), so the §6 corner bridges leave; each hole's far side sees only the other hole.
  const std::vector<Cell> one{cell(-7.75, 7.75, -4.05, 4.05)};
  const auto chamfered =
      loop({{-7.75, -1.55}, {-4.75, -4.05}, {7.75, -4.05}, {7.75, 4.05}, {-4.75, 4.05}, {-7.75, 1.55}}, true);
  const std::vector<LoopPolyline> pair{chamfered, circle({-3.6, 0.0}, 3.0, 64, false),
                                       circle({3.6, 0.0}, 3.0, 64, false)};
  auto r = run_and_check(one, pair, loops_area(pair));
  CHECK(r.polys.stats.cut_cells > 0);
  CHECK(r.polys.stats.unresolved_holes == 0);
  // 60 pin holes of radius 0.5 in a 10 x 6 grid, 0.2 and 0.1 apart, in one cell under the same
  // outer loop (the corner pins 0.02 from its chamfers).
  std::vector<LoopPolyline> pins{chamfered};
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 6; ++j) pins.push_back(circle({-5.5 + 1.2 * i, -2.75 + 1.1 * j}, 0.5, 24, false));
  auto r2 = run_and_check(one, pins, loops_area(pins));
  CHECK(r2.polys.stats.unresolved_holes == 0);
}

TEST_CASE("half-edge trim: holes whose sides lie on one line to a rounding are not bridged along it") {
  // The plate of a pin socket (KiCad PinSocket_2x15_P2.00mm_Vertical_SMD, face 4, as read): 30 unit
  // square holes in two rows in one cell, their sides on the lines y = 0.5, 1.5, 2.5, 3.5 to a few
  // ulps. A bridge along such a line passes a rounding from the holes' sides: it must not be taken
  // for one that crosses nothing (one joined (-4.5, 2.5) to (-1.5, 2.5) across a hole's side).
  const std::vector<Cell> one{cell(-30.000000000000004, 0, -1.3322676295503e-14, 4)};
  const std::vector<std::pair<bool, std::vector<glm::dvec2>>> given{
      {true,
       {{-30.000000000000004, -1.3322676295503e-14}, {0, -1.3322676295503e-14},
        {0, 4}, {-30.000000000000004, 4}}},
      {false,
       {{-18.5, 0.49999999999999178}, {-19.5, 0.49999999999999134},
        {-19.5, 1.4999999999999913}, {-18.5, 1.4999999999999918}}},
      {false,
       {{-19.5, 2.4999999999999911}, {-19.5, 3.4999999999999911},
        {-18.5, 3.4999999999999916}, {-18.5, 2.4999999999999916}}},
      {false,
       {{-23.5, 2.4999999999999893}, {-23.5, 3.4999999999999893},
        {-22.5, 3.4999999999999898}, {-22.5, 2.4999999999999898}}},
      {false,
       {{-20.5, 2.4999999999999907}, {-21.5, 2.4999999999999902},
        {-21.5, 3.4999999999999902}, {-20.5, 3.4999999999999907}}},
      {false,
       {{-23.5, 0.49999999999998956}, {-23.5, 1.4999999999999896},
        {-22.5, 1.49999999999999}, {-22.5, 0.49999999999999001}}},
      {false,
       {{-20.5, 0.4999999999999909}, {-21.5, 0.49999999999999045},
        {-21.5, 1.4999999999999905}, {-20.5, 1.4999999999999909}}},
      {false,
       {{-17.5, 1.4999999999999922}, {-16.5, 1.4999999999999927},
        {-16.5, 0.49999999999999267}, {-17.5, 0.49999999999999223}}},
      {false,
       {{-16.5, 3.4999999999999925}, {-16.5, 2.4999999999999925},
        {-17.5, 2.499999999999992}, {-17.5, 3.499999999999992}}},
      {false,
       {{-14.5, 0.49999999999999356}, {-15.5, 0.49999999999999312},
        {-15.5, 1.4999999999999931}, {-14.5, 1.4999999999999936}}},
      {false,
       {{-14.500000000000002, 2.4999999999999933}, {-15.500000000000002, 2.4999999999999929},
        {-15.500000000000002, 3.4999999999999929}, {-14.500000000000002, 3.4999999999999933}}},
      {false,
       {{-5.5000000000000009, 2.4999999999999973}, {-5.5000000000000018, 3.4999999999999973},
        {-4.5000000000000018, 3.4999999999999978}, {-4.5000000000000009, 2.4999999999999978}}},
      {false,
       {{-7.5000000000000018, 3.4999999999999964}, {-6.5000000000000018, 3.4999999999999969},
        {-6.5000000000000009, 2.4999999999999969}, {-7.5000000000000009, 2.4999999999999964}}},
      {false,
       {{-4.5, 0.499999999999998}, {-5.5, 0.49999999999999756},
        {-5.5000000000000009, 1.4999999999999976}, {-4.5000000000000009, 1.499999999999998}}},
      {false,
       {{-6.5000000000000009, 1.4999999999999971}, {-6.5, 0.49999999999999711},
        {-7.5, 0.49999999999999667}, {-7.5000000000000009, 1.4999999999999967}}},
      {false,
       {{-12.5, 1.4999999999999944}, {-12.5, 0.49999999999999445},
        {-13.5, 0.499999999999994}, {-13.5, 1.499999999999994}}},
      {false,
       {{-9.5, 0.49999999999999578}, {-9.5, 1.4999999999999958},
        {-8.5, 1.4999999999999962}, {-8.5, 0.49999999999999623}}},
      {false,
       {{-11.5, 1.4999999999999949}, {-10.5, 1.4999999999999953},
        {-10.5, 0.49999999999999534}, {-11.5, 0.49999999999999489}}},
      {false,
       {{-13.500000000000002, 3.4999999999999938}, {-12.500000000000002, 3.4999999999999942},
        {-12.500000000000002, 2.4999999999999942}, {-13.500000000000002, 2.4999999999999938}}},
      {false,
       {{-10.500000000000002, 3.4999999999999951}, {-10.500000000000002, 2.4999999999999951},
        {-11.500000000000002, 2.4999999999999947}, {-11.500000000000002, 3.4999999999999947}}},
      {false,
       {{-9.5000000000000018, 2.4999999999999956}, {-9.5000000000000018, 3.4999999999999956},
        {-8.5000000000000018, 3.499999999999996}, {-8.5000000000000018, 2.499999999999996}}},
      {false,
       {{-26.5, 1.4999999999999882}, {-26.5, 0.49999999999998823},
        {-27.5, 0.49999999999998779}, {-27.5, 1.4999999999999878}}},
      {false,
       {{-25.5, 0.49999999999998868}, {-25.5, 1.4999999999999887},
        {-24.5, 1.4999999999999891}, {-24.5, 0.49999999999998912}}},
      {false,
       {{-25.5, 3.4999999999999885}, {-24.5, 3.4999999999999889},
        {-24.5, 2.4999999999999889}, {-25.5, 2.4999999999999885}}},
      {false,
       {{-27.5, 2.4999999999999876}, {-27.5, 3.4999999999999876},
        {-26.5, 3.499999999999988}, {-26.5, 2.499999999999988}}},
      {false,
       {{-29.5, 3.4999999999999867}, {-28.5, 3.4999999999999871},
        {-28.5, 2.4999999999999871}, {-29.5, 2.4999999999999867}}},
      {false,
       {{-29.5, 1.4999999999999869}, {-28.5, 1.4999999999999873},
        {-28.5, 0.49999999999998734}, {-29.5, 0.4999999999999869}}},
      {false,
       {{-1.5000000000000016, 3.4999999999999991}, {-0.50000000000000155, 3.4999999999999996},
        {-0.50000000000000111, 2.4999999999999996}, {-1.5000000000000011, 2.4999999999999991}}},
      {false,
       {{-0.50000000000000022, 0.49999999999999978}, {-1.5000000000000002, 0.49999999999999933},
        {-1.5000000000000007, 1.4999999999999993}, {-0.50000000000000067, 1.4999999999999998}}},
      {false,
       {{-2.5000000000000018, 3.4999999999999987}, {-2.5000000000000013, 2.4999999999999987},
        {-3.5000000000000013, 2.4999999999999982}, {-3.5000000000000018, 3.4999999999999982}}},
      {false,
       {{-3.5000000000000009, 1.4999999999999984}, {-2.5000000000000009, 1.4999999999999989},
        {-2.5000000000000004, 0.49999999999999889}, {-3.5000000000000004, 0.49999999999999845}}},
  };
  std::vector<LoopPolyline> plate;
  for (const auto& [outer, uv] : given) plate.push_back(loop(uv, outer));
  auto r = run_and_check(one, plate, loops_area(plate));
  CHECK(r.polys.stats.unresolved_holes == 0);
}

TEST_CASE("half-edge trim: large case (64 x 64 cells, 20000-point outer circle, 100 holes)" * test::sweep()) {
  const auto cells = grid(0, 1, 0, 1, 64, 64);
  std::vector<LoopPolyline> loops{circle({0.5, 0.5}, 0.49, 20000, true)};
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) loops.push_back(circle({0.23 + 0.06 * i, 0.23 + 0.06 * j}, 0.02, 40, false));
  auto r = run_and_check(cells, loops, loops_area(loops));
  MESSAGE("large case: " << r.polys.polygons.size() << " polygons, " << r.tris.size() << " triangles, "
                         << r.polys.stats.graph_vertices << " graph vertices, " << r.seconds << " s");
  CHECK(r.polys.stats.fallback_bridges == 0);
}

TEST_CASE("half-edge trim: outer loop along one edge of R, vertices on cell corners, collinear edges") {
  const auto cells = grid(0, 1, 0, 1, 4, 4);
  const auto touching = loop({{0, 0}, {1, 0}, {1, 0.6}, {0.5, 0.8}, {0, 0.6}}, true);
  run_and_check(cells, {touching}, loops_area({touching}));
  // Diamond through cell corners (its edges pass through the corners (0.75, 0.25) etc.).
  const auto diamond = loop({{0.5, 0}, {1, 0.5}, {0.5, 1}, {0, 0.5}}, true);
  run_and_check(cells, {diamond}, 0.5);
  // L-shape along cell lines with a hole whose edges are cell edges.
  const auto ell = loop({{0, 0}, {0.75, 0}, {0.75, 0.5}, {0.5, 0.5}, {0.5, 1}, {0, 1}}, true);
  const auto square = loop({{0.25, 0.25}, {0.25, 0.5}, {0.5, 0.5}, {0.5, 0.25}}, false);
  run_and_check(cells, {ell, square}, loops_area({ell, square}));
  // A hole sharing a corner with the outer loop (touching at one vertex).
  const auto outer = loop({{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}}, true);
  const auto corner_hole = loop({{0.1, 0.1}, {0.2, 0.3}, {0.3, 0.2}}, false);
  run_and_check(cells, {outer, corner_hole}, loops_area({outer, corner_hole}));
  // A hole touching a cell edge at one vertex (pinch in the traversal, then fallback bridges).
  const auto edge_hole = loop({{0.25, 0.375}, {0.4, 0.45}, {0.45, 0.3}}, false);
  auto r = run_and_check(cells, {edge_hole}, 1.0 + loops_area({edge_hole}));
  CHECK(r.polys.stats.paper_bridges == 0);
  CHECK(r.polys.stats.fallback_bridges == 2);
  // Vertices 1e-14 off cell lines and corners (below the 1e-12 snapping tolerance): snapped.
  const double d = 1e-14;
  const auto near = loop({{0.5 + d, 0.25 - d}, {0.75 - d, 0.5}, {0.5, 0.75 + d}, {0.25, 0.5 - d}}, true);
  auto r2 = run_and_check(cells, {near}, 0.125);   // the snapped diamond: 1e-14 changes the area by ~1e-14
  CHECK(r2.polys.stats.snapped_coordinates == 5);  // the five coordinates written with d
}

TEST_CASE("half-edge trim: R = bounding box of the outer loop (the paper's domain restriction, §5)") {
  // The loop touches R's boundary at four single vertices; kd tiling with T-junctions.
  const auto c = circle({0.3, -0.2}, 0.7, 96, true);
  std::vector<Cell> cells;
  std::mt19937_64 rng(5);
  kd_split(cell(0.3 - 0.7, 0.3 + 0.7, -0.2 - 0.7, -0.2 + 0.7), 7, rng, cells);
  auto r = run_and_check(cells, {c}, nurbs::signed_area(c.uv));
  CHECK(r.polys.stats.clipped_loops == 0);
}

TEST_CASE("half-edge trim: loops slightly outside R are clipped") {
  const auto cells = grid(0, 1, 0, 1, 3, 5);
  const auto out = loop({{-1e-3, -1e-3}, {0.5, -1e-3}, {0.5, 0.5}, {-1e-3, 0.5}}, true);
  auto r = run_and_check(cells, {out}, 0.25);  // [0, 0.5]^2 after clipping
  CHECK(r.polys.stats.clipped_loops == 1);
  // Loops leaving and re-entering R: a diamond |u - .5| + |v - .5| <= .7 (R minus four corner
  // triangles with legs .3: 1 - 4 * .045) and a plus sign with arms .4 wide (2 * .4 - .16).
  const auto diamond = loop({{0.5, -0.2}, {1.2, 0.5}, {0.5, 1.2}, {-0.2, 0.5}}, true);
  run_and_check(cells, {diamond}, 1.0 - 4 * 0.045);
  const auto plus = loop({{0.3, -0.5},
                          {0.7, -0.5},
                          {0.7, 0.3},
                          {1.5, 0.3},
                          {1.5, 0.7},
                          {0.7, 0.7},
                          {0.7, 1.5},
                          {0.3, 1.5},
                          {0.3, 0.7},
                          {-0.5, 0.7},
                          {-0.5, 0.3},
                          {0.3, 0.3}},
                         true);
  run_and_check(cells, {plus}, 2 * 0.4 - 0.16);
  // Outside by 1e-14 (< the 1e-12 snapping tolerance): snapped onto R's boundary, area of R.
  const auto almost = loop({{-1e-14, -1e-14}, {1 + 1e-14, -1e-14}, {1 + 1e-14, 1}, {-1e-14, 1}}, true);
  auto r2 = run_and_check(cells, {almost}, 1.0);
  CHECK(r2.polys.stats.snapped_coordinates > 0);
}
