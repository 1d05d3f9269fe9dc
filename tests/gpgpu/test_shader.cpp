// Shader assembly: a compile error names the glsl file and line (also after an #include), a missing
// include names the including file and line, a link error throws with the log.
#include <doctest/doctest.h>

#include "gl_fixture.h"
#include "gpgpu/shader_library.h"

namespace {
// Line 4 of broken.frag uses an undeclared identifier, after an #include of an embedded library.
constexpr gpgpu::ShaderFile kTestFiles[] = {
    {"broken.frag", "#include \"lib_float.glsl\"\nout vec4 o;\nvoid main() {\n  o = vec4(undeclared_thing);\n}\n"},
    {"bad_include.frag", "// comment\n#include \"no_such_lib.glsl\"\nvoid main() {}\n"},
    {"ok.frag", "out vec4 o;\nvoid main() { o = vec4(1.0); }\n"},
    {"link_mismatch.vert",
     "out vec3 v_only_in_vs_mismatch;\nvoid main() { v_only_in_vs_mismatch = vec3(0); "
     "gl_Position = vec4(0); }\n"},
    {"link_mismatch.frag", "in vec4 v_only_in_vs_mismatch;\nout vec4 o;\nvoid main() { o = v_only_in_vs_mismatch; }\n"},
};
}  // namespace

TEST_CASE("shader: compile error names file and line") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kTestFiles, "tests/");
  try {
    gpu.program("broken.frag");
    FAIL("broken shader compiled");
  } catch (const gpgpu::ShaderError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("tests/broken.frag:4") != std::string::npos);
    CHECK(what.find("undeclared_thing") != std::string::npos);
  }
}

TEST_CASE("shader: missing include names the including file and line") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kTestFiles, "tests/");
  CHECK_THROWS_WITH(gpu.program("bad_include.frag"),
                    "tests/bad_include.frag:2: #include \"no_such_lib.glsl\" is not an embedded GLSL file");
}

TEST_CASE("shader: assembly puts version first and maps #line numbers") {
  gpgpu::ShaderLibrary lib;
  lib.add(kTestFiles, "tests/");
  lib.add(gpgpu::embedded_glsl(), "glsl/gpgpu/");
  const gpgpu::AssembledSource s = lib.assemble("broken.frag", {{"ANSWER", "42"}});
  CHECK(s.text.rfind("#version 450 core\n", 0) == 0);
  CHECK(s.text.find("#define ANSWER 42") != std::string::npos);
  REQUIRE(s.files.size() == 3);
  CHECK(s.files[1] == "tests/broken.frag");
  CHECK(s.files[2] == "glsl/gpgpu/lib_float.glsl");
  // Mesa and NVIDIA log formats are both rewritten.
  CHECK(gpgpu::rewrite_log("0:100004(7): error: x", s) == "tests/broken.frag:4:7: error: x");
  CHECK(gpgpu::rewrite_log("0(200003) : error C1008: y", s) == "glsl/gpgpu/lib_float.glsl:3: error C1008: y");
  CHECK(s.text.find("#line 100002\n") != std::string::npos);  // back in broken.frag after the include
}

TEST_CASE("shader: link error throws with the log") {
  gpgpu::Gpu& gpu = test::gpu();
  gpu.shaders().add(kTestFiles, "tests/");
  CHECK_THROWS_AS(gpgpu::Program(gpu.shaders(), "link_mismatch.vert", "link_mismatch.frag"), gpgpu::ShaderError);
  CHECK_NOTHROW(gpgpu::Program(gpu.shaders(), "fullscreen.vert", "ok.frag"));
}
