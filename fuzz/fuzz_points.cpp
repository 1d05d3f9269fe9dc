// libFuzzer target: files of points (nurbs/io/point_cloud.h), PLY, .npy and text alike (the reader
// tells them apart by content), with the coordinate limit of a model of size 1 at the origin (1e15).
// ReadError is the expected answer to bad input; what is read must be finite and within the limit,
// with one normal and one colour per point where there are any.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "nurbs/io/point_cloud.h"
#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  constexpr double limit = 1e15;
  try {
    const nurbs::io::PointCloud cloud = nurbs::io::read_point_cloud(in, "fuzz", limit);
    if (cloud.points.empty()) std::abort();
    if (!cloud.normals.empty() && cloud.normals.size() != cloud.points.size()) std::abort();
    if (!cloud.colors.empty() && cloud.colors.size() != cloud.points.size()) std::abort();
    for (const auto& p : cloud.points)
      if (!nurbs::within_coordinate_limit(p, limit)) std::abort();
  } catch (const nurbs::io::ReadError&) {
  }
  return 0;
}
