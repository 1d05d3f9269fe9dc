#include "gpgpu/program.h"

#include <fmt/format.h>

#include "gpgpu/gl_api.h"
#include "gpgpu/uniform_names.h"

namespace gpgpu {
namespace {

GLuint compile(GLenum stage, const AssembledSource& src, const std::string& file) {
  GLuint shader = gl::CreateShader(stage);
  const char* text = src.text.c_str();
  gl::ShaderSource(shader, 1, &text, nullptr);
  gl::CompileShader(shader);
  GLint ok = 0, len = 0;
  gl::GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  gl::GetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
  std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
  gl::GetShaderInfoLog(shader, len, nullptr, log.data());
  gl::DeleteShader(shader);
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  throw ShaderError(fmt::format("GLSL compile error in {}:\n{}", file, rewrite_log(log, src)));
}

}  // namespace

Program::Program(const ShaderLibrary& library, std::string_view vertex, std::string_view fragment,
                 const Defines& defines)
    : name_(fmt::format("{}+{}", vertex, fragment)) {
  const AssembledSource vs = library.assemble(vertex, defines);
  const AssembledSource fs = library.assemble(fragment, defines);
  declared_ = gpgpu::declared_uniforms(vs.text);
  declared_.merge(gpgpu::declared_uniforms(fs.text));
  GLuint v = compile(GL_VERTEX_SHADER, vs, std::string(vertex));
  GLuint f = 0;
  try {
    f = compile(GL_FRAGMENT_SHADER, fs, std::string(fragment));
  } catch (...) {
    gl::DeleteShader(v);
    throw;
  }
  id_ = gl::CreateProgram();
  gl::AttachShader(id_, v);
  gl::AttachShader(id_, f);
  gl::LinkProgram(id_);
  gl::DeleteShader(v);  // flagged for deletion; freed with the program
  gl::DeleteShader(f);
  GLint ok = 0, len = 0;
  gl::GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    gl::GetProgramiv(id_, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    gl::GetProgramInfoLog(id_, len, nullptr, log.data());
    gl::DeleteProgram(id_);
    id_ = 0;
    throw ShaderError(fmt::format("GLSL link error in {}:\n{}", name_, log.c_str()));
  }
}

Program::~Program() {
  if (id_ != 0) gl::DeleteProgram(id_);
}

Program::Program(Program&& other) noexcept
    : id_(std::exchange(other.id_, 0)),
      name_(std::move(other.name_)),
      declared_(std::move(other.declared_)),
      locations_(std::move(other.locations_)) {}

Program& Program::operator=(Program&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) gl::DeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
    name_ = std::move(other.name_);
    declared_ = std::move(other.declared_);
    locations_ = std::move(other.locations_);
  }
  return *this;
}

GLint Program::location(const std::string& uniform) const {
  auto it = locations_.find(uniform);
  if (it != locations_.end()) return it->second;
  const GLint loc = gl::GetUniformLocation(id_, uniform.c_str());
  if (loc < 0 && !declared_.contains(std::string(uniform_base_name(uniform))))
    throw std::invalid_argument(fmt::format("program {} declares no uniform '{}'", name_, uniform));
  locations_.emplace(uniform, loc);
  return loc;
}

GLint Program::active_location(const std::string& uniform) const {
  const GLint loc = location(uniform);
  if (loc < 0)
    throw std::invalid_argument(
        fmt::format("program {} never reads sampler '{}' (optimised away: nothing uses it)", name_, uniform));
  return loc;
}

void Program::set(const std::string& u, int v) const { gl::ProgramUniform1i(id_, location(u), v); }
void Program::set(const std::string& u, unsigned v) const { gl::ProgramUniform1ui(id_, location(u), v); }
void Program::set(const std::string& u, float v) const { gl::ProgramUniform1f(id_, location(u), v); }
void Program::set(const std::string& u, int x, int y) const { gl::ProgramUniform2i(id_, location(u), x, y); }
void Program::set(const std::string& u, int x, int y, int z, int w) const {
  gl::ProgramUniform4i(id_, location(u), x, y, z, w);
}
void Program::set(const std::string& u, float x, float y) const { gl::ProgramUniform2f(id_, location(u), x, y); }
void Program::set(const std::string& u, float x, float y, float z) const {
  gl::ProgramUniform3f(id_, location(u), x, y, z);
}
void Program::set(const std::string& u, float x, float y, float z, float w) const {
  gl::ProgramUniform4f(id_, location(u), x, y, z, w);
}

void Program::set_mat4(const std::string& u, const float* m) const {
  gl::ProgramUniformMatrix4fv(id_, location(u), 1, GL_FALSE, m);
}

}  // namespace gpgpu
