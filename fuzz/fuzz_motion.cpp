// libFuzzer target: motion lines (DX DY DZ AX AY AZ DEG, as `clearance --motion` reads them) through
// nurbs::parse_numbers and nurbs::rigid_motion. A line either fails to parse, is refused
// (std::invalid_argument), or gives a rigid transform with finite entries (validate_rigid empty).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "nurbs/model_ops.h"
#include "nurbs/rigid_motion.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  for (std::string line; std::getline(in, line);) {
    double v[7];
    if (!nurbs::parse_numbers(line, 7, v)) continue;
    try {
      const glm::dmat4 m = nurbs::rigid_motion({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6]);
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          if (!std::isfinite(m[c][r])) std::abort();
      if (!nurbs::validate_rigid(m).empty()) std::abort();
    } catch (const std::invalid_argument&) {
    }
  }
  return 0;
}
