// Silent GL mistakes made loud: a uniform the sources do not declare, a sampler the program never
// reads, a pass that reads the texture it writes, and (with KHR_debug output) the driver's message.
#include <doctest/doctest.h>

#include "gl_fixture.h"
#include "gpgpu/gl_api.h"
#include "gpgpu/gl_debug.h"
#include "gpgpu/uniform_names.h"

using gpgpu::Format;

namespace {
// u_unused and u_unused_scale are declared but not read: the compiler drops them (no location).
constexpr gpgpu::ShaderFile kCheckFiles[] = {
    {"checks_scale.frag",
     "uniform sampler2D u_src;\n"
     "uniform sampler2D u_unused;  // declared, never read\n"
     "uniform float u_scale, u_unused_scale;\n"
     "out vec4 o;\n"
     "void main() { o = u_scale * texelFetch(u_src, ivec2(gl_FragCoord.xy), 0); }\n"},
};
}  // namespace

TEST_CASE("uniform names: declarations are read from the source text") {
  const auto names = gpgpu::declared_uniforms(
      "// uniform float u_comment;\n/* uniform int u_block_comment; */\n"
      "layout(binding = 0) uniform highp sampler2D u_tex;\nuniform vec2 u_a, u_b[4] = vec2[4](vec2(0), vec2(1),\n"
      "  vec2(2), vec2(3));\nuniform Block { float u_in_block; };\nfloat nonuniform_x;\n");
  CHECK(names == std::set<std::string>{"u_tex", "u_a", "u_b"});
  CHECK(gpgpu::uniform_base_name("u_levels[3]") == "u_levels");
  CHECK(gpgpu::uniform_base_name("u_light.pos") == "u_light");
}

TEST_CASE("program: a uniform name the sources lack throws; an optimised-away one is a no-op") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kCheckFiles, "tests/");
  const gpgpu::Program& p = gpu.program("checks_scale.frag");
  CHECK(p.declared_uniforms().contains("u_unused_scale"));
  CHECK_NOTHROW(p.set("u_scale", 2.0f));
  CHECK(p.location("u_unused_scale") == -1);
  CHECK_NOTHROW(p.set("u_unused_scale", 2.0f));
  CHECK_THROWS_WITH_AS(p.set("u_scael", 2.0f),
                       "program fullscreen.vert+checks_scale.frag declares no uniform 'u_scael'",
                       std::invalid_argument);
  gpgpu::gl::check_error("setting uniforms");
}

TEST_CASE("pass runner: unknown or unread samplers and feedback loops throw, naming pass and program") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kCheckFiles, "tests/");
  gpgpu::Program& p = gpu.program("checks_scale.frag");
  p.set("u_scale", 3.0f);
  gpgpu::Texture a(3, 2, Format::RGBA32F), b(3, 2, Format::RGBA32F);
  a.upload(std::vector<float>(3 * 2 * 4, 1.0f));
  gpgpu::Texture* out_b[] = {&b};
  const gpgpu::Input good[] = {{"u_src", &a}};
  gpu.run("scale", p, good, out_b);
  CHECK(b.read()[0] == 3.0f);  // exact: 3 * 1

  const gpgpu::Input typo[] = {{"u_scr", &a}};
  CHECK_THROWS_WITH_AS(gpu.run("scale", p, typo, out_b),
                       "pass 'scale': program fullscreen.vert+checks_scale.frag declares no uniform 'u_scr'",
                       std::invalid_argument);
  const gpgpu::Input unread[] = {{"u_src", &a}, {"u_unused", &a}};
  CHECK_THROWS_WITH_AS(gpu.run("scale", p, unread, out_b),
                       "pass 'scale': program fullscreen.vert+checks_scale.frag never reads sampler 'u_unused' "
                       "(optimised away: nothing uses it)",
                       std::invalid_argument);
  const gpgpu::Input self[] = {{"u_src", &b}};
  CHECK_THROWS_WITH_AS(gpu.run("scale in place", p, self, out_b),
                       doctest::Contains("pass 'scale in place' (program fullscreen.vert+checks_scale.frag): sampler "
                                         "'u_src' reads texture"),
                       std::invalid_argument);
  // Nothing was left bound by the rejected passes: the good pass still runs.
  gpu.run("scale", p, good, out_b);
  CHECK(b.read()[0] == 3.0f);
  gpgpu::gl::check_error("after the rejected passes");
}

TEST_CASE("KHR_debug: the driver's message comes with the GL error" *
          doctest::skip(!gpgpu::gl::debug_output_requested())) {
  REQUIRE(test::gpu().info().debug_output);
  const GLuint not_a_texture = 0x7fffffff;
  gpgpu::gl::BindTextureUnit(0, not_a_texture);  // GL_INVALID_OPERATION: not a texture name
  CHECK_THROWS_WITH(gpgpu::gl::check_error("binding a bad name"),
                    doctest::Contains("GL error GL_INVALID_OPERATION after binding a bad name (driver: "));
  CHECK_NOTHROW(gpgpu::gl::check_error("the next call"));  // the message was consumed
}
