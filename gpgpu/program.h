#pragma once
/// \file program.h
/// A linked GL program (RAII) built from assembled sources, with uniform setters that do not touch
/// context state (glProgramUniform*). Compile and link failures throw ShaderError with the log; a
/// uniform name the sources do not declare throws std::invalid_argument naming program and name.
#include <GL/glcorearb.h>

#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "gpgpu/shader_library.h"

namespace gpgpu {

/// A compile or link failure; what() holds the stage, program name and the rewritten info log
/// (locations read "glsl/file.frag:LINE:COL").
class ShaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Program {
 public:
  Program() = default;
  /// Compiles `vertex` and `fragment` (names in `library`) with `defines` and links them.
  Program(const ShaderLibrary& library, std::string_view vertex, std::string_view fragment,
          const Defines& defines = {});
  ~Program();
  Program(Program&& other) noexcept;
  Program& operator=(Program&& other) noexcept;
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  [[nodiscard]] GLuint id() const { return id_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  /// Location of a uniform ("u_x", "u_levels[3]"), or -1 when it is declared but inactive (the
  /// compiler optimised it away: setting it is a no-op). Throws std::invalid_argument when the
  /// sources declare no such uniform (a misspelt name would otherwise be silently ignored).
  [[nodiscard]] GLint location(const std::string& uniform) const;
  /// Location of a sampler a pass binds a texture to: it must be active, since a texture bound to a
  /// sampler the program never reads is a mistake. Throws std::invalid_argument naming the program.
  [[nodiscard]] GLint active_location(const std::string& uniform) const;
  /// Uniform names the vertex and fragment sources declare (uniform_names.h).
  [[nodiscard]] const std::set<std::string>& declared_uniforms() const { return declared_; }

  void set(const std::string& uniform, int v) const;
  void set(const std::string& uniform, unsigned v) const;
  void set(const std::string& uniform, float v) const;
  void set(const std::string& uniform, int x, int y) const;
  void set(const std::string& uniform, int x, int y, int z, int w) const;
  void set(const std::string& uniform, float x, float y) const;
  void set(const std::string& uniform, float x, float y, float z) const;
  void set(const std::string& uniform, float x, float y, float z, float w) const;
  /// A mat4 from 16 floats in column-major order (glm's memory layout).
  void set_mat4(const std::string& uniform, const float* column_major) const;

 private:
  GLuint id_ = 0;
  std::string name_;
  std::set<std::string> declared_;
  mutable std::unordered_map<std::string, GLint> locations_;
};

}  // namespace gpgpu
