// The cells of a face's grid that its trim edges cross (queries/distance/point_batch_trim.h), on grids with
// a knot span a trillionth of the domain wide (a double knot written with rounding, as on the
// Bottom model's faces 318 and 319): every cell an edge passes through is indexed, and the index
// costs the cells crossed, not the edge's length in steps of the narrowest cell.
#include <doctest/doctest.h>

#include <vector>

#include "nurbs/distance/certified_grid.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/point_batch_trim.h"

TEST_CASE("trim edges: every cell an edge crosses is indexed, beside a span 1e-12 of the domain wide") {
  nurbs::ParamGrid grid;
  grid.u = {0.0, 0.25, 0.5, 0.5 + 1e-12, 0.75, 1.0};
  grid.v = {0.0, 0.25, 0.5, 0.75, 1.0};
  nurbs::TrimPolygons trim;
  trim.loops = {{{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}}};
  trim.outer = {true};
  trim.domain_u = {0.0, 1.0}, trim.domain_v = {0.0, 1.0};
  const queries::TrimEdges edges(trim, grid);
  // The loop runs along rows 0 and 3 and columns 0 and 4: every cell of that ring, the thin
  // column 2 included, and none inside.
  for (int i = 0; i < grid.cells_u(); ++i)
    for (int j = 0; j < grid.cells_v(); ++j) {
      CAPTURE(i);
      CAPTURE(j);
      const bool ring = i == 0 || i == grid.cells_u() - 1 || j == 0 || j == grid.cells_v() - 1;
      CHECK(edges.crossed(i, j) == ring);
    }
  CHECK(edges.cells().size() == 14);
}
