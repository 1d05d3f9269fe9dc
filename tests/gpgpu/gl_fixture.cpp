#include "gl_fixture.h"

#include <doctest/doctest.h>

namespace test {

gpgpu::Gpu& gpu() {
  static gpgpu::Gpu instance(gpgpu::ContextOptions{gpgpu::backend_from_env()});
  static bool printed = false;
  if (!printed) {
    printed = true;
    MESSAGE("backend " << instance.info().backend << ": " << instance.info().detail << " / "
                       << instance.info().renderer);
  }
  return instance;
}

std::vector<float> random_floats(std::mt19937_64& rng, size_t n, float lo, float hi) {
  std::vector<float> v(n);
  for (float& x : v) {
    const double u = double(rng() >> 11) * 0x1.0p-53;  // 53 random bits in [0, 1)
    x = static_cast<float>(lo + (hi - lo) * u);
  }
  return v;
}

}  // namespace test
