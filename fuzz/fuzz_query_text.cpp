// libFuzzer target: the text formats of query inputs (nurbs/io/query_text.h), the same bytes read as
// a --point and as a ray file, with the coordinate limit of a model of size 1 at the origin (1e15).
// ReadError is the expected answer to bad input; what is read must be finite, within the limit, and
// every ray direction of unit length. Files of points: fuzz_points.cpp.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <string>

#include "nurbs/io/query_text.h"
#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  constexpr double limit = 1e15;
  try {
    if (!nurbs::within_coordinate_limit(nurbs::io::parse_point(text, "fuzz", limit), limit)) std::abort();
  } catch (const nurbs::io::ReadError&) {
  }
  try {
    for (const nurbs::io::TextRay& r : nurbs::io::parse_rays(text, "fuzz", limit))
      if (!nurbs::within_coordinate_limit(r.origin, limit) || !(std::abs(glm::length(r.direction) - 1.0) < 1e-12))
        std::abort();
  } catch (const nurbs::io::ReadError&) {
  }
  return 0;
}
