#pragma once
/// \file program.h
/// A linked GL program (RAII) built from assembled sources, with uniform setters that do not touch
/// context state (glProgramUniform*). Compile and link failures throw ShaderError with the log.
#include <GL/glcorearb.h>

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
  /// Location of a uniform, or -1 (unused uniforms are optimised away; setting them is a no-op).
  [[nodiscard]] GLint location(const std::string& uniform) const;

  void set(const std::string& uniform, int v) const;
  void set(const std::string& uniform, unsigned v) const;
  void set(const std::string& uniform, float v) const;
  void set(const std::string& uniform, int x, int y) const;
  void set(const std::string& uniform, int x, int y, int z, int w) const;
  void set(const std::string& uniform, float x, float y) const;
  void set(const std::string& uniform, float x, float y, float z) const;
  void set(const std::string& uniform, float x, float y, float z, float w) const;

 private:
  GLuint id_ = 0;
  std::string name_;
  mutable std::unordered_map<std::string, GLint> locations_;
};

}  // namespace gpgpu
