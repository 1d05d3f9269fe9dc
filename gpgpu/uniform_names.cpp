#include "gpgpu/uniform_names.h"

#include <cctype>
#include <vector>

namespace gpgpu {
namespace {

bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// `glsl` with // and /* */ comments replaced by spaces.
std::string strip_comments(std::string_view glsl) {
  std::string out(glsl);
  for (size_t i = 0; i + 1 < out.size(); ++i) {
    if (out[i] == '/' && out[i + 1] == '/') {
      while (i < out.size() && out[i] != '\n') out[i++] = ' ';
    } else if (out[i] == '/' && out[i + 1] == '*') {
      const size_t end = out.find("*/", i + 2);
      const size_t stop = end == std::string::npos ? out.size() : end + 2;
      for (; i < stop; ++i)
        if (out[i] != '\n') out[i] = ' ';
      --i;
    }
  }
  return out;
}

/// The declarators of one declaration body ("vec2 a, b[2] = ..."), split at top-level commas.
std::vector<std::string_view> split_declarators(std::string_view body) {
  std::vector<std::string_view> parts;
  int depth = 0;
  size_t start = 0;
  for (size_t i = 0; i < body.size(); ++i) {
    const char c = body[i];
    if (c == '(' || c == '[') ++depth;
    if (c == ')' || c == ']') --depth;
    if (c == ',' && depth == 0) {
      parts.push_back(body.substr(start, i - start));
      start = i + 1;
    }
  }
  parts.push_back(body.substr(start));
  return parts;
}

/// The last identifier before any '=' or '[' of a declarator ("highp sampler2D u_src" -> u_src).
std::string declarator_name(std::string_view d) {
  d = d.substr(0, d.find_first_of("=["));
  size_t end = d.size();
  while (end > 0 && !ident_char(d[end - 1])) --end;
  size_t begin = end;
  while (begin > 0 && ident_char(d[begin - 1])) --begin;
  return std::string(d.substr(begin, end - begin));
}

}  // namespace

std::set<std::string> declared_uniforms(std::string_view glsl) {
  const std::string text = strip_comments(glsl);
  std::set<std::string> names;
  constexpr std::string_view kKeyword = "uniform";
  for (size_t at = text.find(kKeyword); at != std::string::npos; at = text.find(kKeyword, at + 1)) {
    const size_t after = at + kKeyword.size();
    if ((at > 0 && ident_char(text[at - 1])) || (after < text.size() && ident_char(text[after]))) continue;
    const size_t end = text.find_first_of(";{", after);
    if (end == std::string::npos || text[end] == '{') continue;  // a uniform block: not set by name here
    for (std::string_view d : split_declarators(std::string_view(text).substr(after, end - after))) {
      std::string name = declarator_name(d);
      if (!name.empty()) names.insert(std::move(name));
    }
  }
  return names;
}

std::string_view uniform_base_name(std::string_view path) { return path.substr(0, path.find_first_of("[.")); }

}  // namespace gpgpu
