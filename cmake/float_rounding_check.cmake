# The CPU twins of the GPU kernels round doubles to float and back (glm::dvec3(glm::vec3(p)), the
# GPU's float point in double) to compute what the GPU computes. GCC 12.2 (Debian 12) at -O2 drops
# such round trips in the lanes its SLP vectorizer packs together: in
#   dvec3 h(dvec3 m) { return dvec3(float(m.x), float(m.y), float(m.z)); }
# only z is converted, x and y are copied unrounded (found by the oriented pyramid's containment
# test, point_batch_obb.cpp). This check builds that function with the project's flags and runs it;
# where the round trip is lost, SLP vectorization is turned off for the whole project.
include(CheckCXXSourceRuns)
set(CMAKE_REQUIRED_FLAGS "-O2 -std=c++20")
check_cxx_source_runs([=[
#include <glm/vec3.hpp>
__attribute__((noinline)) glm::dvec3 h(glm::dvec3 m) { return glm::dvec3(float(m.x), float(m.y), float(m.z)); }
int main(int argc, char**) {
  const glm::dvec3 r = h(glm::dvec3(0.1 * argc, 0.2 * argc, 0.3 * argc));
  return r.x == double(float(0.1)) && r.y == double(float(0.2)) && r.z == double(float(0.3)) ? 0 : 1;
}
]=] NURBSGL_FLOAT_ROUND_TRIP_KEPT)
unset(CMAKE_REQUIRED_FLAGS)
if(NOT NURBSGL_FLOAT_ROUND_TRIP_KEPT)
  message(STATUS "double -> float -> double lost by the SLP vectorizer: building with -fno-tree-slp-vectorize")
  add_compile_options(-fno-tree-slp-vectorize)
endif()
