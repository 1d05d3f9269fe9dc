// Standard reductions against their CPU twins (double accumulation) on sizes that stress the 2x2
// pyramid: 1x1, 1xN, Nx1, primes, 4097x3, random sizes; with +inf, -inf and NaN entries and ties.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "gl_fixture.h"
#include "gpgpu/array_texture.h"
#include "gpgpu/reduce.h"

using gpgpu::Format;
using gpgpu::ReduceOp;

namespace {

struct Size {
  int w, h;
};

std::vector<Size> sizes() {
  std::vector<Size> s{{1, 1},  {1, 2},     {2, 1},    {1, 1000}, {1000, 1},  {2, 2},      {3, 5},
                      {7, 13}, {127, 131}, {4097, 3}, {3, 4097}, {509, 257}, {1024, 1024}};
  std::mt19937_64 rng(2024);
  for (int i = 0; i < 8; ++i) s.push_back({int(1 + rng() % 700), int(1 + rng() % 700)});
  return s;
}

enum class Special { None, Inf, NaN, AllNaN };

std::vector<float> make_data(std::mt19937_64& rng, Size s, int ch, Special special) {
  auto v = test::random_floats(rng, size_t(s.w) * s.h * ch, -100.0f, 100.0f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  if (special == Special::AllNaN) std::fill(v.begin(), v.end(), nan);
  const size_t n = v.size();
  if (special == Special::Inf && n > 2) {
    v[rng() % n] = inf;
    v[rng() % n] = -inf;
  }
  if (special == Special::NaN) {
    for (int k = 0; k < 3; ++k) v[rng() % n] = nan;
  }
  return v;
}

/// Pairwise float summation: |error| <= (passes + 1) * 2^-24 * sum |x| (each level rounds once).
double sum_tolerance(const std::vector<float>& v, int ch, int c, Size s) {
  double abs_sum = 0;
  for (size_t i = size_t(c); i < v.size(); i += size_t(ch)) abs_sum += std::fabs(v[i]);
  const int passes = int(std::ceil(std::log2(std::max(s.w, s.h)))) + 1;
  return (passes + 1) * 0x1.0p-24 * abs_sum;
}

}  // namespace

TEST_CASE("reduce: min, max, sum per channel match the CPU twin") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(11);
  for (Size s : sizes()) {
    for (Special special : {Special::None, Special::Inf, Special::NaN, Special::AllNaN}) {
      CAPTURE(s.w);
      CAPTURE(s.h);
      CAPTURE(int(special));
      const auto data = make_data(rng, s, 4, special);
      gpgpu::Texture t(s.w, s.h, Format::RGBA32F);
      t.upload(data);
      const gpgpu::ReduceOps ops{ReduceOp::Min, ReduceOp::Max, ReduceOp::Sum, ReduceOp::Min};
      const auto g = gpgpu::reduce(gpu, t, ops);
      const auto c = gpgpu::reduce_cpu(data, 4, ops);
      CHECK(double(g[0]) == c[0]);  // min/max are exact: the result is one of the inputs
      CHECK(double(g[1]) == c[1]);
      CHECK(double(g[3]) == c[3]);
      if (std::isnan(c[2]) || std::isinf(c[2]))
        CHECK((std::isnan(g[2]) == std::isnan(c[2]) && (std::isnan(c[2]) || g[2] == c[2])));
      else
        CHECK(std::fabs(double(g[2]) - c[2]) <= sum_tolerance(data, 4, 2, s));
    }
  }
}

TEST_CASE("reduce: 4x4 and 8x8 blocks per pass give the 2x2 result (min, max exactly; sums within rounding)") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(13);
  for (Size s : sizes()) {
    for (int block : {4, 8}) {
      CAPTURE(s.w);
      CAPTURE(s.h);
      CAPTURE(block);
      const auto data = make_data(rng, s, 4, Special::NaN);
      gpgpu::Texture t(s.w, s.h, Format::RGBA32F);
      t.upload(data);
      const gpgpu::ReduceOps ops{ReduceOp::Min, ReduceOp::Max, ReduceOp::Sum, ReduceOp::Min};
      const auto g = gpgpu::reduce(gpu, t, ops, block);
      const auto c = gpgpu::reduce_cpu(data, 4, ops);
      CHECK(double(g[0]) == c[0]);
      CHECK(double(g[1]) == c[1]);
      CHECK(double(g[3]) == c[3]);
      CHECK(std::isnan(g[2]) == std::isnan(c[2]));  // NaN data: the sum is NaN
      CHECK(double(gpgpu::reduce_min(gpu, t, 3, block)) == c[3]);
    }
  }
  gpgpu::Texture one(3, 3, Format::R32F);
  CHECK_THROWS_AS((void)gpgpu::reduce_min(gpu, one, 0, 3), std::invalid_argument);
}

TEST_CASE("reduce: the paper's min/max texture (RG) and R8 masks") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(12);
  const auto data = make_data(rng, {333, 77}, 2, Special::NaN);
  gpgpu::Texture t(333, 77, Format::RG32F);
  t.upload(data);
  const gpgpu::ReduceOps ops{ReduceOp::Min, ReduceOp::Max, ReduceOp::Min, ReduceOp::Min};
  const auto g = gpgpu::reduce(gpu, t, ops);
  const auto c = gpgpu::reduce_cpu(data, 2, ops);
  CHECK(double(g[0]) == c[0]);
  CHECK(double(g[1]) == c[1]);
  gpgpu::Texture mask(301, 5, Format::R8);
  std::vector<uint8_t> bytes(301 * 5, 0);
  for (int i = 0; i < 97; ++i) bytes[size_t(rng() % bytes.size())] = 255;
  mask.upload(bytes);
  double set = 0;
  for (uint8_t b : bytes) set += b ? 1 : 0;
  CHECK(double(gpgpu::reduce_sum(gpu, mask)) == set);  // sums of small integers are exact in float
}

TEST_CASE("argmin: value and index match the CPU twin, ties go to the smallest index") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(13);
  for (Size s : sizes()) {
    for (Special special : {Special::None, Special::Inf, Special::NaN, Special::AllNaN}) {
      CAPTURE(s.w);
      CAPTURE(s.h);
      CAPTURE(int(special));
      auto data = make_data(rng, s, 2, special);
      if (special == Special::None && data.size() > 8) {
        // Plant the same minimum at three places: the earliest must win.
        const size_t n = data.size() / 2;
        for (int k = 0; k < 3; ++k) data[2 * (rng() % n) + 1] = -1000.0f;
      }
      gpgpu::Texture t(s.w, s.h, Format::RG32F);
      t.upload(data);
      const gpgpu::ArgMin g = gpgpu::argmin(gpu, t, 1);
      const gpgpu::ArgMin c = gpgpu::argmin_cpu(data, s.w, 2, 1);
      REQUIRE(g.found == c.found);
      if (!c.found) continue;
      CHECK(g.value == c.value);
      CHECK(g.index == c.index);
      CHECK(g.x == c.x);
      CHECK(g.y == c.y);
    }
  }
}

TEST_CASE("reduce: a long 1D array laid out in 2D, padded with the neutral element") {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(14);
  const size_t n = 1000003;  // prime: the last row is partial
  auto v = test::random_floats(rng, n, 1.0f, 2.0f);
  v[n - 1] = 0.5f;  // the minimum sits in the partial last row
  const float inf = std::numeric_limits<float>::infinity();
  const gpgpu::ArrayTexture a = gpgpu::upload_array(v, Format::R32F, gpu.info().max_texture_size, inf);
  CHECK(a.layout.capacity() >= int64_t(n));
  const gpgpu::ArgMin m = gpgpu::argmin(gpu, a.texture);
  CHECK(m.value == 0.5f);
  CHECK(m.index == int64_t(n - 1));
  // Small-width layout (as on a GPU with a small GL_MAX_TEXTURE_SIZE): 1000003 > 1000^2 throws.
  CHECK_THROWS_AS(gpgpu::upload_array(v, Format::R32F, 1000, inf), std::length_error);
}
