#include "gpgpu/layout.h"

#include <fmt/format.h>

#include <algorithm>
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

Layout2D layout_pow2(int64_t count, int max_size) {
  int w = 1;
  while (w * 2 <= max_size && w < count) w *= 2;
  if (count > int64_t(w) * max_size)
    throw std::length_error(fmt::format("{} elements do not fit a {}^2 texture", count, max_size));
  return {count, w, static_cast<int>(std::max<int64_t>(1, (count + w - 1) / w))};
}

}  // namespace gpgpu
