// Stream compaction against std::copy_if at densities 0, 1e-4, 0.5 and 1, sizes up to 4096^2,
// pyramid fan-outs 4 and 16: same count, same records, same order.
#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>

#include "gl_fixture.h"
#include "gpgpu/compact.h"

using gpgpu::Format;

namespace {

void check_compaction(int w, int h, double density, uint64_t seed, int fanout) {
  gpgpu::Gpu& gpu = test::gpu();
  std::mt19937_64 rng(seed);
  const size_t n = size_t(w) * h;
  std::vector<uint8_t> keep(n);
  const uint64_t threshold = static_cast<uint64_t>(density * 0x1.0p64 >= 0x1.0p64 ? ~0ull : density * 0x1.0p64);
  for (uint8_t& k : keep) k = (density >= 1.0 || rng() < threshold) ? 255 : 0;
  std::vector<float> records(n * 2);
  for (size_t i = 0; i < n; ++i) {
    records[2 * i] = float(i % 16777216);  // exact in float
    records[2 * i + 1] = float(i / 16777216) - 0.5f;
  }
  gpgpu::Texture pred(w, h, Format::R8), rec(w, h, Format::RG32F);
  pred.upload(keep);
  rec.upload(records);
  const gpgpu::Compacted c = gpgpu::compact(gpu, pred, rec, fanout);

  std::vector<uint32_t> expected_index(n);
  std::iota(expected_index.begin(), expected_index.end(), 0u);
  auto end = std::copy_if(expected_index.begin(), expected_index.end(), expected_index.begin(),
                          [&](uint32_t i) { return keep[i] != 0; });
  expected_index.erase(end, expected_index.end());
  REQUIRE(c.count == int64_t(expected_index.size()));
  const auto index = c.read_source();
  CHECK(index == expected_index);
  const auto got = c.read_records();
  size_t bad = 0;
  for (size_t k = 0; k < expected_index.size(); ++k)
    if (got[2 * k] != records[2 * expected_index[k]] || got[2 * k + 1] != records[2 * expected_index[k] + 1]) ++bad;
  CHECK(bad == 0);
}

}  // namespace

TEST_CASE("compact: odd and elongated sizes at every density, fan-out 4 and 16") {
  const std::pair<int, int> sizes[] = {{1, 1},    {1, 7},     {7, 1},   {1, 1000}, {1000, 1}, {5, 3},
                                       {4097, 3}, {37, 1023}, {17, 16}, {16, 17},  {257, 255}};
  for (int fanout : {4, 16}) {
    uint64_t seed = 100;
    for (auto [w, h] : sizes) {
      for (double d : {0.0, 1e-4, 0.5, 1.0}) {
        CAPTURE(fanout);
        CAPTURE(w);
        CAPTURE(h);
        CAPTURE(d);
        check_compaction(w, h, d, seed++, fanout);
      }
    }
  }
}

TEST_CASE("compact: 1024^2 and 4096^2") {
  for (int size : {1024, 4096}) {
    for (double d : {0.0, 1e-4, 0.5, 1.0}) {
      CAPTURE(size);
      CAPTURE(d);
      check_compaction(size, size, d, uint64_t(size) + uint64_t(d * 1000), size == 4096 ? 16 : 4);
    }
  }
}

TEST_CASE("compact: mismatched sizes are rejected") {
  gpgpu::Texture a(4, 4, Format::R8), b(4, 5, Format::RGBA32F);
  CHECK_THROWS_AS(gpgpu::compact(test::gpu(), a, b), std::invalid_argument);
  gpgpu::Texture c(4, 5, Format::R8);
  CHECK_THROWS_AS(gpgpu::compact(test::gpu(), c, b, 8), std::invalid_argument);
}
