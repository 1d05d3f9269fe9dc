#include "gpgpu/layout.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace gpgpu {

Layout2D layout_for(int64_t count, int max_size) {
  if (count < 0 || count > int64_t(max_size) * max_size)
    throw std::length_error(fmt::format("{} elements do not fit a {}^2 texture", count, max_size));
  Layout2D l;
  l.count = count;
  if (count <= 1) return l;
  int64_t w = static_cast<int64_t>(std::ceil(std::sqrt(static_cast<double>(count))));
  while (w * w < count) ++w;  // guard sqrt rounding
  if (w > max_size) w = max_size;
  l.width = static_cast<int>(w);
  l.height = static_cast<int>((count + w - 1) / w);
  return l;
}

}  // namespace gpgpu
