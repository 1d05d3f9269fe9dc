// The teapot's Bézier patch format: the shared teapot and a table of malformed files.
#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "nurbs/io/bpt_reader.h"
#include "nurbs/io/read_error.h"
#include "shared_models.h"

namespace fs = std::filesystem;

TEST_CASE("bpt: Newell teapot has 32 bicubic patches" * test::needs_shared_models()) {
  const fs::path path = test::shared_models_dir() / "teapot/newell_teapot.bpt";
  const auto t0 = std::chrono::steady_clock::now();
  const nurbs::Model m = nurbs::io::read_bpt(path);
  MESSAGE("newell_teapot.bpt: read "
          << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() << " ms");
  REQUIRE(m.bodies.size() == 1);
  REQUIRE(m.bodies[0].faces.size() == 32);
  for (const auto& f : m.bodies[0].faces) {
    CHECK(f.surface.degree_u == 3);
    CHECK(f.surface.degree_v == 3);
    CHECK(f.surface.points.size() == 16);
    CHECK(f.surface.knots_u == std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1});
    CHECK_FALSE(f.surface.rational());
    CHECK(f.loops.empty());
  }
  // File rows 1 and 2 of patch 1 are (1.4, 0, 2.4) and (1.4, -0.784, 2.4): row k = i * 4 + j.
  const auto& s = m.bodies[0].faces[0].surface;
  CHECK(s.point(0, 0) == glm::dvec3(1.4, 0.0, 2.4));     // exact: parsed decimal literals
  CHECK(s.point(0, 1) == glm::dvec3(1.4, -0.784, 2.4));  // row 2 = u index 0, v index 1
}

TEST_CASE("bpt: malformed files give their specific error") {
  struct Case {
    const char* text;
    const char* expect;
  };
  const std::string patch = "3 3\n" + [] {
    std::string rows;
    for (int i = 0; i < 16; ++i) rows += std::to_string(i) + " 0 1\n";
    return rows;
  }();
  const std::string one = "1\n" + patch;
  const Case cases[] = {
      {"", "t.bpt: line 1: patch count: unexpected end of file"},
      {"abc\n", "t.bpt: line 1: patch count: 'abc' is not a number"},
      {"0\n", "t.bpt: line 1: patch count is 0, expected an integer in [1, 10000000]"},
      {"1.5\n", "t.bpt: line 1: patch count is 1.5"},
      {"1\n3\n", "t.bpt: line 2: patch 1 degrees: expected 2 numbers, found 1"},
      {"1\n0 3\n", "t.bpt: line 2: patch 1 degree u is 0"},
      {"1\n3 99\n", "t.bpt: line 2: patch 1 degree v is 99"},
      {"1\n3 3\n1 2\n", "t.bpt: line 3: patch 1 point (0, 0): expected 3 numbers, found 2"},
      {"1\n3 3\n1 2 nan\n", "t.bpt: line 3: patch 1 point (0, 0): 'nan' is not a finite number"},
      {"1\n3 3\n1 2 3 4\n", "t.bpt: line 3: patch 1 point (0, 0): expected 3 numbers, found 4"},
      {"1\n3 3\n1 2 3\n", "t.bpt: line 4: patch 1 point (0, 1): unexpected end of file"},
  };
  for (const Case& c : cases) {
    CAPTURE(std::string(c.text));
    std::string message;
    try {
      nurbs::io::read_bpt_text(c.text, "t.bpt");
    } catch (const nurbs::io::ReadError& e) {
      message = e.what();
    }
    CHECK_MESSAGE(message.find(c.expect) == 0, message);
  }
  CHECK(nurbs::io::read_bpt_text(one, "t.bpt").bodies[0].faces.size() == 1);
  CHECK_THROWS_WITH(nurbs::io::read_bpt_text(one + "\n7\n", "t.bpt"),
                    "t.bpt: line 20: data after the 1 patches announced on line 1");
  CHECK_THROWS_WITH(nurbs::io::read_bpt_text("2\n" + patch, "t.bpt"),
                    "t.bpt: line 19: patch 2 degrees: unexpected end of file");
  CHECK_THROWS_WITH(nurbs::io::read_bpt("/nonexistent/t.bpt"), "/nonexistent/t.bpt: no such file");
}
