// OBJ export of sampled grids: counts of vertices and faces, index order, bad sizes.
#include <doctest/doctest.h>

#include <sstream>
#include <stdexcept>

#include "nurbs/io/obj_writer.h"

namespace {
int count_prefix(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0 ? 1 : 0;
  return n;
}
}  // namespace

TEST_CASE("OBJ: quads and triangles of a 3 x 2 grid and a 2 x 5 grid") {
  nurbs::io::SampledGrid a{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}}, 3, 2, "a"};
  nurbs::io::SampledGrid b{std::vector<glm::dvec3>(10, glm::dvec3(0.5)), 2, 5, ""};
  struct Row {
    bool triangles;
    int faces;  // (3-1)(2-1) + (2-1)(5-1) cells, twice for triangles
  };
  for (const Row r : {Row{false, 6}, Row{true, 12}}) {
    std::ostringstream out;
    nurbs::io::write_obj(out, {a, b}, r.triangles);
    CHECK(count_prefix(out.str(), "v ") == 16);
    CHECK(count_prefix(out.str(), "f ") == r.faces);
    CHECK(count_prefix(out.str(), "g a") == 1);
    // First cell counter-clockwise in (u, v): 1 2 5 4; second grid starts at vertex 7.
    CHECK(out.str().find(r.triangles ? "f 1 2 5\nf 1 5 4\n" : "f 1 2 5 4\n") != std::string::npos);
    CHECK(out.str().find(r.triangles ? "f 7 8 10\n" : "f 7 8 10 9\n") != std::string::npos);
  }
}

TEST_CASE("OBJ: inconsistent grids are rejected") {
  std::ostringstream out;
  CHECK_THROWS_AS(nurbs::io::write_obj(out, {{{{0, 0, 0}, {1, 0, 0}}, 2, 2, "x"}}), std::invalid_argument);
  CHECK_THROWS_AS(nurbs::io::write_obj(out, {{{{0, 0, 0}, {1, 0, 0}}, 2, 1, "x"}}), std::invalid_argument);
}
