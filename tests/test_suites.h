#pragma once
/// \file test_suites.h
/// The test suite "sweep": property sweeps over hundreds of random inputs and printout benchmarks.
///   TEST_CASE("..." * test::sweep()) { ... }
/// They run in the normal build. The sanitizer build (NURBSGL_SANITIZE) leaves them out: it checks
/// memory and undefined behaviour, which the other cases reach through the same code, and the
/// sweeps cost minutes there (CI time). tests/CMakeLists.txt adds the exclusion.
#include <doctest/doctest.h>

namespace test {

/// doctest decorator: suite "sweep".
struct sweep {
  void fill(doctest::detail::TestCase& tc) const { tc.m_test_suite = "sweep"; }
};

}  // namespace test
