// Stream compaction against std::copy_if at densities 0, 1e-4, 0.5 and 1, sizes up to 4096^2,
// pyramid fan-outs 4 and 16: same count, same records, same order.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "gl_fixture.h"
#include "gpgpu/compact.h"

using gpgpu::Format;

namespace {

/// `cut`: through compact_at_most, the kept texels' values in [0, 1] (1 itself among them), the
/// others' above 1 or NaN, cut at 1.
void check_compaction(int w, int h, double density, uint64_t seed, int fanout, bool cut = false) {
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
  gpgpu::Texture pred(w, h, cut ? Format::RG32F : Format::R8), rec(w, h, Format::RG32F);
  if (cut) {
    std::vector<float> values(n * 2, 0.0f);
    for (size_t i = 0; i < n; ++i) {
      const uint64_t r = rng();
      if (keep[i])
        values[2 * i] = r % 7 == 0 ? 1.0f : float(r % 1000) / 1000.0f;
      else
        values[2 * i] = r % 5 == 0 ? std::nanf("") : std::nextafter(1.0f, 2.0f) + float(r % 1000) / 1000.0f;
    }
    pred.upload(values);
  } else {
    pred.upload(keep);
  }
  rec.upload(records);
  const gpgpu::Compacted c =
      cut ? gpgpu::compact_at_most(gpu, pred, 1.0f, rec, fanout) : gpgpu::compact(gpu, pred, rec, fanout);

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

TEST_CASE("compact: odd and elongated sizes at every density, fan-out 4 and 16, by predicate and by cut") {
  const std::pair<int, int> sizes[] = {{1, 1},    {1, 7},     {7, 1},   {1, 1000}, {1000, 1}, {5, 3},
                                       {4097, 3}, {37, 1023}, {17, 16}, {16, 17},  {257, 255}};
  for (bool cut : {false, true})
    for (int fanout : {4, 16}) {
      uint64_t seed = 100;
      for (auto [w, h] : sizes) {
        for (double d : {0.0, 1e-4, 0.5, 1.0}) {
          CAPTURE(cut);
          CAPTURE(fanout);
          CAPTURE(w);
          CAPTURE(h);
          CAPTURE(d);
          check_compaction(w, h, d, seed++, fanout, cut);
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
  CHECK_THROWS_AS(gpgpu::compact_at_most(test::gpu(), c, 1.0f, b), std::invalid_argument);  // an R8 "value"
}
