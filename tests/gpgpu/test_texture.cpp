// Textures, layouts, framebuffers and the pass runner.
#include <doctest/doctest.h>

#include <numeric>

#include "gl_fixture.h"
#include "gpgpu/framebuffer.h"
#include "gpgpu/gl_api.h"
#include "gpgpu/layout.h"
#include "gpgpu/ping_pong.h"

using gpgpu::Format;

TEST_CASE("texture: upload and read back every format, whole and region") {
  test::gpu();
  std::mt19937_64 rng(7);
  for (Format f : {Format::R32F, Format::RG32F, Format::RGBA32F}) {
    CAPTURE(gpgpu::format_name(f));
    gpgpu::Texture t(13, 7, f);
    const auto data = test::random_floats(rng, 13 * 7 * size_t(gpgpu::channels(f)), -1e6f, 1e6f);
    t.upload(data);
    CHECK(t.read() == data);  // float storage: bit-exact round trip
    const auto part = t.read({2, 3, 4, 2});
    const int c = gpgpu::channels(f);
    REQUIRE(part.size() == size_t(4 * 2 * c));
    CHECK(part[0] == data[size_t((3 * 13 + 2) * c)]);
    CHECK(part.back() == data[size_t(((3 + 1) * 13 + 2 + 3) * c + c - 1)]);
  }
  gpgpu::Texture mask(5, 3, Format::R8);
  std::vector<uint8_t> bytes(15);
  std::iota(bytes.begin(), bytes.end(), uint8_t(0));
  mask.upload(bytes);
  CHECK(mask.read()[14] == doctest::Approx(14.0 / 255.0).epsilon(1e-6));
  gpgpu::Texture counts(3, 2, Format::R32UI);
  const std::vector<uint32_t> big{0u, 1u, 0xffffffffu, 16777217u, 7u, 8u};  // > 2^24: exact as integers
  counts.upload(big);
  CHECK(counts.read_u32() == big);
}

TEST_CASE("texture: bad sizes and uploads are rejected") {
  test::gpu();
  CHECK_THROWS_AS(gpgpu::Texture(0, 4, Format::R32F), std::invalid_argument);
  CHECK_THROWS_AS(gpgpu::Texture(test::gpu().info().max_texture_size + 1, 1, Format::R32F), std::invalid_argument);
  gpgpu::Texture t(4, 4, Format::RG32F);
  CHECK_THROWS_AS(t.upload(std::vector<float>(16)), std::invalid_argument);  // needs 32 values
  CHECK_THROWS_AS(t.read({3, 3, 2, 2}), std::out_of_range);
}

TEST_CASE("layout: 1D arrays in 2D within the maximum size") {
  for (int64_t n : {int64_t(0), int64_t(1), int64_t(2), int64_t(17), int64_t(1000003), int64_t(16384) * 16384}) {
    const gpgpu::Layout2D l = gpgpu::layout_for(n, 16384);
    CAPTURE(n);
    CHECK(l.capacity() >= n);
    CHECK((n == 0 || l.capacity() - n < l.width));  // at most one partial row
    CHECK(l.width <= 16384);
    CHECK(l.height <= 16384);
  }
  CHECK(gpgpu::layout_for(50, 8).width == 8);
  CHECK(gpgpu::layout_for(50, 8).height == 7);
  CHECK(gpgpu::layout_for(64, 8).height == 8);
  CHECK_THROWS_AS(gpgpu::layout_for(65, 8), std::length_error);
}

TEST_CASE("framebuffer: incomplete framebuffers raise with the GL status") {
  test::gpu();
  CHECK_THROWS_WITH_AS(gpgpu::Framebuffer(std::span<const GLuint>{}),
                       "framebuffer incomplete: GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT (0 colour attachment(s))",
                       gpgpu::FramebufferError);
  GLuint no_storage = 0;  // a texture object whose image was never specified
  gpgpu::gl::CreateTextures(GL_TEXTURE_2D, 1, &no_storage);
  const GLuint ids[] = {no_storage};
  CHECK_THROWS_WITH_AS(gpgpu::Framebuffer(std::span<const GLuint>(ids)),
                       "framebuffer incomplete: GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT (1 colour attachment(s))",
                       gpgpu::FramebufferError);
  gpgpu::gl::DeleteTextures(1, &no_storage);
  // The pass runner checks too: a pass with no outputs raises instead of drawing nowhere.
  gpgpu::Texture t(2, 2, Format::RGBA32F);
  const gpgpu::Input in[] = {{"u_src", &t}};
  CHECK_THROWS_AS(test::gpu().run("no outputs", test::gpu().program("add_constant.frag"), in, {}),
                  gpgpu::FramebufferError);
}

TEST_CASE("pass runner: ping-pong map passes over an odd-sized texture, viewport limits writes") {
  gpgpu::Gpu& gpu = test::gpu();
  gpgpu::PingPong pp(31, 17, Format::RGBA32F);
  std::vector<float> zeros(31 * 17 * 4, 0.0f);
  pp.src().upload(zeros);
  gpgpu::Program& add = gpu.program("add_constant.frag");
  add.set("u_value", 1.0f, 2.0f, 0.5f, -1.0f);
  for (int i = 0; i < 5; ++i) {
    const gpgpu::Input in[] = {{"u_src", &pp.src()}};
    gpgpu::Texture* out[] = {&pp.dst()};
    gpu.run("add", add, in, out);
    pp.swap();
  }
  const auto v = pp.src().read();
  CHECK(v[0] == 5.0f);
  CHECK(v[1] == 10.0f);
  CHECK(v[2] == 2.5f);
  CHECK(v[v.size() - 1] == -5.0f);
  // Only the 4x3 viewport at (2, 1) changes.
  const gpgpu::Input in[] = {{"u_src", &pp.src()}};
  pp.dst().upload(zeros);
  gpgpu::Texture* out[] = {&pp.dst()};
  gpu.run("add region", add, in, out, gpgpu::Region{2, 1, 4, 3});
  const auto r = pp.dst().read();
  CHECK(r[size_t((1 * 31 + 2) * 4)] == 6.0f);
  CHECK(r[size_t((1 * 31 + 1) * 4)] == 0.0f);
  CHECK(r[size_t((4 * 31 + 2) * 4)] == 0.0f);
}
