// Mip levels ("hierarchy levels"): a pyramid built level by level inside one texture, each
// pass reading the finer level while it renders the coarser one, then read whole through one
// sampler with texelFetch(sampler, p, lod); and the passes the runner must refuse.
#include <doctest/doctest.h>

#include <vector>

#include "gl_fixture.h"
#include "gpgpu/gl_api.h"

using gpgpu::Format;

namespace {
constexpr gpgpu::ShaderFile kMipFiles[] = {
    // Sum of the 2x2 children: the finer level is this sampler's lod 0 (Input::level).
    {"mip_sum_2x2.frag",
     "uniform sampler2D u_fine;\n"
     "out vec4 o;\n"
     "void main() {\n"
     "  ivec2 size = textureSize(u_fine, 0);\n"
     "  o = vec4(0.0);\n"
     "  for (int k = 0; k < 4; ++k) {  // children outside the finer level (1-texel rows) count 0\n"
     "    ivec2 c = 2 * ivec2(gl_FragCoord.xy) + ivec2(k & 1, k >> 1);\n"
     "    if (c.x < size.x && c.y < size.y) o += texelFetch(u_fine, c, 0);\n"
     "  }\n"
     "}\n"},
    // Texel (0, 0) of level x: a lod that differs between neighbouring fragments.
    {"mip_fetch_varying.frag",
     "uniform sampler2D u_pyramid;\n"
     "out vec4 o;\n"
     "void main() { o = texelFetch(u_pyramid, ivec2(0), int(gl_FragCoord.x)); }\n"},
    // Texel (x, y) of level (x + 3y) % 3, clamped to that level's size.
    {"mip_fetch_scatter.frag",
     "uniform sampler2D u_pyramid;\n"
     "out vec4 o;\n"
     "void main() { ivec2 g = ivec2(gl_FragCoord.xy); int l = (g.x + 3 * g.y) % 3;\n"
     "  o = texelFetch(u_pyramid, min(g, max(ivec2(8, 4) >> l, ivec2(1)) - 1), l); }\n"},
    // Texel (x, 0) of level u_lod of the whole pyramid.
    {"mip_fetch_lod.frag",
     "uniform sampler2D u_pyramid;\n"
     "uniform int u_lod;\n"
     "out vec4 o;\n"
     "void main() { o = texelFetch(u_pyramid, ivec2(int(gl_FragCoord.x), 0), u_lod); }\n"},
};
}  // namespace

TEST_CASE("mip levels: a 2x2-sum pyramid built in place, read back per level and through one sampler") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kMipFiles, "tests/");
  // 8 x 4: levels 8x4, 4x2, 2x1, 1x1 (a non-square pyramid; the last levels are 1 texel high).
  gpgpu::Texture t(8, 4, Format::RGBA32F, 4);
  CHECK(t.levels() == 4);
  CHECK(t.level_width(2) == 2);
  CHECK(t.level_height(2) == 1);
  std::vector<float> base(8 * 4 * 4);
  for (size_t i = 0; i < base.size(); ++i) base[i] = float(i % 7) + 0.25f * float(i % 4);  // small exact values
  t.upload(base);
  gpgpu::Program& sum = gpu.program("mip_sum_2x2.frag");
  for (int l = 1; l < 4; ++l) {
    const gpgpu::Input in[] = {{"u_fine", &t, l - 1}};
    gpgpu::Texture* out[] = {&t};
    gpu.run("mip sum", sum, in, out, std::nullopt, l);
  }
  // CPU twin: the same sums (exact in float: small multiples of 0.25).
  std::vector<float> level = base;
  for (int l = 1; l < 4; ++l) {
    const int fw = t.level_width(l - 1), w = t.level_width(l), h = t.level_height(l);
    std::vector<float> next(size_t(w) * size_t(h) * 4, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 4; ++k)
          for (int c = 0; c < 4; ++c)
            if (2 * y + (k >> 1) < t.level_height(l - 1))
              next[size_t((y * w + x) * 4 + c)] += level[size_t(((2 * y + (k >> 1)) * fw + 2 * x + (k & 1)) * 4 + c)];
    level = next;
    CHECK(t.read_level(l) == level);
  }
  CHECK(t.read_level(3)[0] > 0.0f);
  // After the build every level is visible again: one sampler fetches any of them by lod.
  gpgpu::Program& fetch = gpu.program("mip_fetch_lod.frag");
  gpgpu::Texture row(2, 1, Format::RGBA32F);
  fetch.set("u_lod", 2);
  const gpgpu::Input whole[] = {{"u_pyramid", &t}};
  gpgpu::Texture* out_row[] = {&row};
  gpu.run("mip fetch", fetch, whole, out_row);
  CHECK(row.read() == t.read_level(2));
  // Lod and texel both varying between fragments (the box descent's pattern): fragment (x, y)
  // reads level (x + 3y) % 3 at (x, y) clamped to that level.
  gpgpu::Program& scatter = gpu.program("mip_fetch_scatter.frag");
  gpgpu::Texture scattered(8, 4, Format::RGBA32F);
  gpgpu::Texture* out_scattered[] = {&scattered};
  gpu.run("mip fetch scattered", scatter, whole, out_scattered);
  const std::vector<float> fetched = scattered.read();
  int differ = 0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const int l = (x + 3 * y) % 3, w = t.level_width(l), h = t.level_height(l);
      const std::vector<float> want = t.read_level(l);
      for (int c = 0; c < 4; ++c)
        differ +=
            fetched[size_t((y * 8 + x) * 4 + c)] != want[size_t((std::min(y, h - 1) * w + std::min(x, w - 1)) * 4 + c)];
    }
  CHECK(differ == 0);
  // A lod that varies per fragment (each fragment of one 2x2 quad on its own level).
  gpgpu::Program& varying = gpu.program("mip_fetch_varying.frag");
  gpgpu::Texture per_level(4, 1, Format::RGBA32F);
  gpgpu::Texture* out_levels[] = {&per_level};
  gpu.run("mip fetch varying", varying, whole, out_levels);
  const std::vector<float> got = per_level.read();
  for (int l = 0; l < 4; ++l) {
    CAPTURE(l);
    const std::vector<float> want = t.read_level(l);
    CHECK(std::vector<float>(got.begin() + 4 * l, got.begin() + 4 * l + 4) ==
          std::vector<float>(want.begin(), want.begin() + 4));
  }
  gpgpu::gl::check_error("after the mip passes");
}

TEST_CASE("mip levels: bad level counts, same-level feedback and missing levels are refused") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kMipFiles, "tests/");
  CHECK_THROWS_WITH_AS(gpgpu::Texture(8, 4, Format::RGBA32F, 5), "5 mip levels for a 8x4 texture (it can have 1..4)",
                       std::invalid_argument);
  CHECK_THROWS_AS(gpgpu::Texture(8, 4, Format::RGBA32F, 0), std::invalid_argument);
  gpgpu::Texture t(8, 4, Format::RGBA32F, 3);
  gpgpu::Program& sum = gpu.program("mip_sum_2x2.frag");
  gpgpu::Texture* out[] = {&t};
  const gpgpu::Input same[] = {{"u_fine", &t, 1}};
  CHECK_THROWS_WITH_AS(gpu.run("mip same", sum, same, out, std::nullopt, 1),
                       doctest::Contains("pass 'mip same' (program fullscreen.vert+mip_sum_2x2.frag): sampler "
                                         "'u_fine' reads texture"),
                       std::invalid_argument);
  const gpgpu::Input missing[] = {{"u_fine", &t, 3}};
  CHECK_THROWS_WITH_AS(gpu.run("mip missing", sum, missing, out, std::nullopt, 1),
                       "pass 'mip missing': sampler 'u_fine' reads level 3 of a texture with 3 level(s)",
                       std::invalid_argument);
  CHECK_THROWS_AS((void)t.read_level(3), std::out_of_range);
  gpgpu::gl::check_error("after the refused passes");
}
