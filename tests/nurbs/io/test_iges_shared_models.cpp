// Every IGES file in the shared model folder reads, with the face counts of OpenCASCADE 7.6.3
// (../shared/models/occt_reference.txt). Skipped (reported as such) when the folder is absent.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <glm/geometric.hpp>
#include <map>
#include <string>

#include "nurbs/io/iges_reader.h"
#include "nurbs/io/model_summary.h"
#include "shared_models.h"

namespace fs = std::filesystem;

namespace {

struct SharedModel {
  const char* path;    // relative to test::shared_models_dir()
  int occt_faces;      // "faces=" in occt_reference.txt
  int occt_rational;   // "rational=": faces whose weights are not all equal
  int occt_poles;      // "totalpoles="
  int max_du, max_dv;  // "maxdeg="
  glm::dvec3 lo, hi;   // OCCT "bbox=" in mm (printed to 4 significant digits)
  double unit_mm;      // from the file's global section (G14/G15)
};

// From occt_reference.txt (OCCT 7.6.3); units from each file's G14 (2 = MM, 1 = IN).
const SharedModel kModels[] = {
    {"iges/occt_bearing.iges", 213, 0, 3000, 8, 3, {-0.04849, -0.06849, -3.254e-07}, {0.05249, 0.05349, 0.03135}, 1.0},
    {"iges/occt_hammer.iges",
     45,
     27,
     850,
     3,
     2,
     {-1.094e+04, 1.705e+04, -1.371e+04},
     {2240, 2.134e+04, 2.472e+04},
     1.0},
    {"iges/pythonocc_example_45_faces.iges", 45, 0, 862, 5, 5, {-150, -38, -0.6}, {150, 74, 35.4}, 1.0},
    {"iges/pythonocc_sunglasses_lens.igs", 9, 0, 2304, 3, 3, {-355.9, -69.67, 37.05}, {-293, -36.22, 57.03}, 25.4},
    {"generated/teapot_bezier32.igs", 32, 0, 512, 3, 3, {-3, -2, -1e-07}, {3.434, 2, 3.15}, 1.0},
    // OCCT counts 1854 poles: it turns the closed surfaces into periodic form (48 poles fewer);
    // the file's 128 entities hold 1902 (27+1)(3+1) + 7*2 + 4*3 + 42*42.
    {"generated/vase_shell_t2.igs", 6, 1, 1902, 14, 11, {-40.3, -41.37, -1e-07}, {40.3, 41.37, 100}, 1.0},
};

size_t trimmed_count(const nurbs::Model& m) {
  size_t n = 0;
  for (const auto& b : m.bodies)
    for (const auto& f : b.faces) n += f.loops.empty() ? 0 : 1;
  return n;
}

size_t face_count(const nurbs::Model& m) {
  size_t n = 0;
  for (const auto& b : m.bodies) n += b.faces.size();
  return n;
}

}  // namespace

TEST_CASE("shared IGES models read with OCCT's face counts" * test::needs_shared_models()) {
  for (const SharedModel& sm : kModels) {
    CAPTURE(std::string(sm.path));
    const fs::path path = test::shared_models_dir() / sm.path;
    nurbs::io::IgesReadLog log;
    const auto t0 = std::chrono::steady_clock::now();
    nurbs::Model model = nurbs::io::read_iges(path, {}, &log);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::string skipped;
    for (auto [type, count] : model.skipped_entities)
      skipped += " " + std::to_string(type) + "x" + std::to_string(count);
    MESSAGE(std::string(sm.path) << ": " << face_count(model) << " faces (OCCT " << sm.occt_faces << "), "
                                 << trimmed_count(model) << " with loops, read " << ms << " ms, loops reoriented "
                                 << log.reoriented_loops << ", skipped:" << (skipped.empty() ? " none" : skipped));
    CHECK(face_count(model) == static_cast<size_t>(sm.occt_faces));
    CHECK(log.warnings.empty());
    CHECK(model.unit_scale_to_mm == sm.unit_mm);  // exact: table constants
    const nurbs::io::ModelSummary s = nurbs::io::summarize(model);
    CHECK(s.rational_faces == sm.occt_rational);
    CHECK(s.control_points == sm.occt_poles);
    CHECK(std::max(s.max_degree_u, s.max_degree_v) == std::max(sm.max_du, sm.max_dv));  // OCCT may swap u and v
    // The control-point box in mm contains OCCT's surface box, up to its 4 printed digits
    // (5e-4 relative of the model size).
    const glm::dvec3 lo = s.bbox_min * sm.unit_mm, hi = s.bbox_max * sm.unit_mm;
    const double tol = 5e-4 * glm::length(sm.hi - sm.lo);
    for (int k = 0; k < 3; ++k) {
      CHECK(lo[k] <= sm.lo[k] + tol);
      CHECK(hi[k] >= sm.hi[k] - tol);
    }
  }
}
