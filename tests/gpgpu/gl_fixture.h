#pragma once
// One headless context per test program: created on first use from NURBSGL_GL, so ctest
// runs this program once per backend (egl, osmesa, glfw under xvfb).
#include <random>
#include <vector>

#include "gpgpu/gpu.h"

namespace test {

gpgpu::Gpu& gpu();

/// Uniform floats in [lo, hi) from a fixed-seed generator, reproducible across compilers.
std::vector<float> random_floats(std::mt19937_64& rng, size_t n, float lo, float hi);

}  // namespace test
