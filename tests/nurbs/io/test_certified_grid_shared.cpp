// Certified grids on real CAD faces: every face of every IGES file in the shared model
// folder, at tolerances 1e-4 and 1e-5 of the model size, gets a knot-aligned grid with a finite
// K_e within the tolerance, and dense samples (double) of its cells never deviate from the grid
// triangles by more than the cell's K_e. Skipped (reported as such) without ../shared.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "nurbs/distance/grid_report.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "shared_models.h"
#include "tests/nurbs/distance/grid_check.h"

namespace fs = std::filesystem;

TEST_CASE("certified grids on every face of the shared IGES models" * test::needs_shared_models()) {
  const std::vector<fs::path> files = test::shared_iges_files();
  REQUIRE(files.size() >= 8);
  int faces_checked = 0, cells_checked = 0;
  for (const fs::path& file : files) {
    const nurbs::Model model = nurbs::io::read_model(file);
    const double size = nurbs::model_size(model);
    const std::string name = file.filename().string();
    CAPTURE(name);
    std::vector<double> ratios;
    long long samples[2] = {0, 0};
    for (const nurbs::TrimmedSurface& f : nurbs::world_faces(model)) {
      const nurbs::FilipBound b = nurbs::filip_bound(f.surface);
      for (int t = 0; t < 2; ++t) {
        const double tol = (t == 0 ? 1e-4 : 1e-5) * size;
        const nurbs::CertifiedGrid cg = nurbs::certified_grid(b, tol);
        CAPTURE(f.face_id);
        CAPTURE(tol);
        CAPTURE(cg.reason);
        CHECK(cg.meets_tolerance);
        CHECK(std::isfinite(cg.k_e));
        CHECK(cg.k_e <= tol);
        samples[t] += cg.grid.samples();
        // Dense check: the cell with the largest K_e and a spread of others, 7 x 7 points each.
        const int nu = cg.grid.cells_u(), nv = cg.grid.cells_v();
        const long long total = static_cast<long long>(nu) * nv;
        std::vector<std::pair<int, int>> cells;
        if (total <= 20'000) {
          double worst = -1;
          std::pair<int, int> at{0, 0};
          for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i)
              if (const double k = nurbs::grid_cell_k(b, cg.grid, i, j, nurbs::KNorm::Euclidean); k > worst)
                worst = k, at = {i, j};
          cells.push_back(at);
        }
        for (int c = 0; c < 12 && c < total; ++c) {
          const long long idx = (c * 104729LL + 17) % total;
          cells.emplace_back(int(idx % nu), int(idx / nu));
        }
        for (const auto& [i, j] : cells) {
          const grid_check::Deviation d = grid_check::cell_deviation(f.surface, cg.grid, i, j, 6);
          const double ke = nurbs::grid_cell_k(b, cg.grid, i, j, nurbs::KNorm::Euclidean);
          // Rounding of points of magnitude ~ size in double: 1e-12 x size.
          CHECK(d.norm <= ke * (1 + 1e-9) + 1e-12 * size);
          ++cells_checked;
        }
      }
      ++faces_checked;
    }
    MESSAGE(name << ": samples at 1e-4 " << samples[0] << ", at 1e-5 " << samples[1]);
  }
  MESSAGE(faces_checked << " faces in " << files.size() << " files, " << cells_checked << " cells checked densely");
}
