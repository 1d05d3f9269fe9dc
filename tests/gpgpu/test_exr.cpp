// EXR dumps: every format round-trips through write_exr/read_exr, and Gpu::dump names files.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "gl_fixture.h"
#include "gpgpu/exr_dump.h"

using gpgpu::Format;

TEST_CASE("exr: float, mask and count textures round-trip") {
  test::gpu();
  // One folder per process: ctest runs this program for several backends at once.
  const auto dir = std::filesystem::temp_directory_path() / ("nurbsgl_test_exr_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::mt19937_64 rng(5);
  gpgpu::Texture t(9, 4, Format::RGBA32F);
  const auto data = test::random_floats(rng, 9 * 4 * 4, -3.0f, 3.0f);
  t.upload(data);
  gpgpu::write_exr(dir / "rgba.exr", t);
  const gpgpu::ExrImage img = gpgpu::read_exr(dir / "rgba.exr");
  CHECK(img.width == 9);
  CHECK(img.height == 4);
  // OpenEXR stores channels sorted by name: A, B, G, R.
  REQUIRE(img.channels == std::vector<std::string>{"A", "B", "G", "R"});
  CHECK(img.values[3] == data[0]);                              // R of texel (0,0)
  CHECK(img.values[0] == data[3]);                              // A of texel (0,0)
  CHECK(img.values[size_t(4 * 9 + 3)] == data[size_t(4 * 9)]);  // R of texel (0,1): no row flip

  gpgpu::Texture counts(3, 1, Format::R32UI);
  counts.upload(std::vector<uint32_t>{1u, 2u, 3000000u});
  gpgpu::write_exr(dir / "counts.exr", counts);
  CHECK(gpgpu::read_exr(dir / "counts.exr").values == std::vector<float>{1.0f, 2.0f, 3000000.0f});

  test::gpu().set_dump_dir(dir / "dump");
  test::gpu().dump("mask", counts);
  CHECK(std::filesystem::exists(dir / "dump" / "000_mask.exr"));
  std::filesystem::remove_all(dir);
  CHECK_THROWS_AS(gpgpu::write_exr("/nonexistent/dir/x.exr", t), std::runtime_error);
}
