// Output files written safely (nurbs/io/output_file.h): a writer that fails midway leaves the old
// file as it was and no temporary beside it; an unwritable target is refused before any work.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "nurbs/io/output_file.h"

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

size_t entries(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace

TEST_CASE("output files: a failed write keeps the old file and leaves no temporary") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "nurbsgl_output_file_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::filesystem::path target = dir / "mesh.obj";
  nurbs::io::write_file(target, [](std::ostream& out) { out << "good\n"; });
  CHECK(slurp(target) == "good\n");
  // Half a file, then an error: the target keeps its old content.
  CHECK_THROWS_AS(nurbs::io::write_file(target,
                                        [](std::ostream& out) {
                                          out << "partial";
                                          throw std::runtime_error("disk full");
                                        }),
                  nurbs::io::WriteError);
  CHECK(slurp(target) == "good\n");
  CHECK(entries(dir) == 1);
  // A new complete file replaces it.
  nurbs::io::write_file(target, [](std::ostream& out) { out << "better\n"; });
  CHECK(slurp(target) == "better\n");
  CHECK(entries(dir) == 1);
  // Unwritable targets: a missing folder, a folder.
  CHECK_THROWS_WITH_AS(nurbs::io::check_writable(dir / "missing" / "x.obj"),
                       doctest::Contains("cannot create a file in its folder"), nurbs::io::WriteError);
  CHECK_THROWS_WITH_AS(nurbs::io::check_writable(dir), doctest::Contains("is a folder"), nurbs::io::WriteError);
  CHECK_NOTHROW(nurbs::io::check_writable(target));
  CHECK(entries(dir) == 1);
  std::filesystem::remove_all(dir);
}
