// Text formats of query inputs (nurbs/io/query_text.h): a point and rays, their separators, and the
// exact message of each bad line.
#include <doctest/doctest.h>

#include <string>

#include "nurbs/io/query_text.h"
#include "nurbs/io/read_error.h"

namespace {

template <typename Parse>
std::string error_of(Parse parse) {
  try {
    (void)parse();
  } catch (const nurbs::io::ReadError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("query text: a point and rays with spaces, tabs, commas, CRLF and comments") {
  CHECK(nurbs::io::parse_point("4,5\t6", "--point", 1e3) == glm::dvec3(4, 5, 6));
  const auto rays = nurbs::io::parse_rays("# ox oy oz dx dy dz\n0 0 30 0 0 -2\n1,2,3,1e300,0,0\n", "r.txt", 1e3);
  REQUIRE(rays.size() == 2);
  CHECK(rays[0].direction == glm::dvec3(0, 0, -1));
  CHECK(rays[1].direction == glm::dvec3(1, 0, 0));  // scaled before its length: no overflow
}

TEST_CASE("query text: each bad input names the file, the line and the problem") {
  using nurbs::io::parse_rays, nurbs::io::parse_point;
  const std::string beyond = "lies beyond 1e+03, the coordinates double arithmetic carries for this model";
  CHECK(error_of([] { return parse_point("1 2", "--point", 1e3); }) ==
        "--point: '1 2' is not a point X,Y,Z of three finite numbers");
  CHECK(error_of([] { return parse_point("1e50 0 0", "--point", 1e3); }) == "--point: '1e50 0 0' " + beyond);
  CHECK(error_of([] { return parse_point("1 nan 3", "--point", 1e3); }) ==
        "--point: '1 nan 3' is not a point X,Y,Z of three finite numbers");
  CHECK(error_of([] { return parse_point("1,2,\x01", "--point", 1e3); }) ==
        "--point: '1,2,\\x01' is not a point X,Y,Z of three finite numbers");
  CHECK(error_of([] { return parse_rays("0 0 0 0 0\n", "r.txt", 1e3); }) ==
        "r.txt: line 1: 5 numbers, expected 6 (ox oy oz dx dy dz)");
  CHECK(error_of([] { return parse_rays("0 0 0 0 0 1 1\n", "r.txt", 1e3); }) ==
        "r.txt: line 1: more than 6 numbers (ox oy oz dx dy dz)");
  CHECK(error_of([] { return parse_rays("0 0 0 0 0 inf\n", "r.txt", 1e3); }) == "r.txt: line 1: 'inf' is not a finite number");
  CHECK(error_of([] { return parse_rays("0 0 0 0 0 0\n", "r.txt", 1e3); }) ==
        "r.txt: line 1: the direction (0, 0, 0) has no length");
  CHECK(error_of([] { return parse_rays("#\n1e50 0 0 1 0 0\n", "r.txt", 1e3); }) ==
        "r.txt: line 2: the origin (1e+50, 0, 0) " + beyond);
  CHECK(error_of([] { return parse_rays("# only a comment\n", "r.txt", 1e3); }) == "r.txt: no rays in the file");
}
