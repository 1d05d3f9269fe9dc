#pragma once
/// \file shader_library.h
/// GLSL sources embedded at build time, and the assembler that turns a kernel file into a program
/// source: `#version`, a generated `#define` block, the shared libraries it `#include`s, the kernel,
/// with `#line` markers so a compile error names the right file and line (see rewrite_log).
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gpgpu {

struct ShaderFile {
  std::string_view name;  ///< file name, e.g. "reduce_2x2.frag"
  std::string_view text;
};

/// The files of glsl/gpgpu/ (gpgpu's own kernels), embedded by cmake/embed_glsl.cmake.
std::span<const ShaderFile> embedded_glsl();

using Defines = std::vector<std::pair<std::string, std::string>>;

/// An assembled source and the file behind each GLSL source-string number used in its `#line`s.
struct AssembledSource {
  std::string text;
  std::vector<std::string> files;  ///< index = source-string number; 0 is the define block
};

class ShaderLibrary {
 public:
  /// `prefix` is prepended to file names in messages ("glsl/").
  void add(std::span<const ShaderFile> files, const std::string& prefix);
  [[nodiscard]] bool contains(std::string_view name) const;

  /// Assembles `name` with `#version 450 core`, `defines`, and every `#include "lib.glsl"` expanded
  /// once (recursively). Throws std::runtime_error naming the file and line of a bad include.
  [[nodiscard]] AssembledSource assemble(std::string_view name, const Defines& defines) const;

 private:
  struct Entry {
    std::string display_name;
    std::string_view text;
  };
  void expand(std::string_view name, AssembledSource& out, std::vector<std::string>& included) const;
  std::map<std::string, Entry, std::less<>> files_;
};

/// `#line` numbers are offset by kLineFileStride * file index, because drivers differ in
/// reporting the source-string number (Mesa prints 0 whatever `#line L S` said) but all report
/// the line: line L of file i is reported as i * kLineFileStride + L.
inline constexpr int kLineFileStride = 100000;

/// Rewrites "S:L(C)" (Mesa) and "S(L)" (NVIDIA) locations in a compiler log to "file:line:C" /
/// "file:line", decoding the file from the offset line number (see kLineFileStride).
std::string rewrite_log(const std::string& log, const AssembledSource& source);

}  // namespace gpgpu
