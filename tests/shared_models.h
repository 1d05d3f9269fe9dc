#pragma once
/// \file shared_models.h
/// Where the tests find the shared CAD models (NURBSGL_SHARED_DIR/models; CMake's cache variable
/// NURBSGL_SHARED_DIR defaults to ../shared), and the decorator of test cases that read them:
///   TEST_CASE("..." * test::needs_shared_models()) { ... test::shared_models_dir() / "iges/x.iges" ... }
/// puts the case in the test suite "shared_models" and skips it when the folder is absent. ctest runs
/// that suite as its own entry (PROGRAM[shared]), which then reports Skipped, not Passed: a program
/// that runs no test case exits with kSkipExitCode (test_main.cpp), ctest's SKIP_RETURN_CODE.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace test {

/// Exit code of a test program that ran no test case (77, as automake's skip code).
inline constexpr int kSkipExitCode = 77;

/// NURBSGL_SHARED_DIR/models.
inline std::filesystem::path shared_models_dir() { return std::filesystem::path(NURBSGL_SHARED_DIR) / "models"; }

/// True when the shared model folder exists.
inline bool shared_models_present() { return std::filesystem::is_directory(shared_models_dir()); }

/// Every IGES file (.igs, .iges) under shared_models_dir(), sorted. A folder without one fails the
/// calling test case (a loop over no files would pass having checked nothing).
inline std::vector<std::filesystem::path> shared_iges_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(shared_models_dir()))
    if (e.path().extension() == ".igs" || e.path().extension() == ".iges") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  REQUIRE_MESSAGE(!files.empty(), "no IGES file under " << shared_models_dir().string());
  return files;
}

/// doctest decorator: suite "shared_models", skipped (decided at registration) when the folder is absent.
struct needs_shared_models {
  void fill(doctest::detail::TestCase& tc) const {
    tc.m_test_suite = "shared_models";
    tc.m_description = "reads " NURBSGL_SHARED_DIR "/models";
    tc.m_skip = !shared_models_present();
  }
};

}  // namespace test
