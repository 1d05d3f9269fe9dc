#include "gpgpu/shader_library.h"

#include <fmt/format.h>

#include <algorithm>
#include <regex>
#include <stdexcept>

namespace gpgpu {

void ShaderLibrary::add(std::span<const ShaderFile> files, const std::string& prefix) {
  for (const ShaderFile& f : files) files_[std::string(f.name)] = Entry{prefix + std::string(f.name), f.text};
}

bool ShaderLibrary::contains(std::string_view name) const { return files_.find(name) != files_.end(); }

AssembledSource ShaderLibrary::assemble(std::string_view name, const Defines& defines) const {
  AssembledSource out;
  out.text = "#version 450 core\n#line 1\n";
  out.files.emplace_back("<defines>");
  for (const auto& [key, value] : defines) out.text += fmt::format("#define {} {}\n", key, value);
  std::vector<std::string> included;
  expand(name, out, included);
  return out;
}

void ShaderLibrary::expand(std::string_view name, AssembledSource& out, std::vector<std::string>& included) const {
  auto it = files_.find(name);
  if (it == files_.end()) throw std::runtime_error(fmt::format("GLSL file '{}' is not embedded", name));
  included.emplace_back(name);
  const int id = static_cast<int>(out.files.size());
  out.files.push_back(it->second.display_name);
  out.text += fmt::format("#line {}\n", id * kLineFileStride + 1);

  std::string_view text = it->second.text;
  int line_no = 0;
  while (!text.empty()) {
    const size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_no;
    const size_t first = line.find_first_not_of(" \t");
    if (first != std::string_view::npos && line.substr(first).starts_with("#include")) {
      const size_t a = line.find('"'), b = line.rfind('"');
      if (a == std::string_view::npos || b <= a)
        throw std::runtime_error(fmt::format("{}:{}: malformed #include", it->second.display_name, line_no));
      std::string lib(line.substr(a + 1, b - a - 1));
      if (!contains(lib))
        throw std::runtime_error(
            fmt::format("{}:{}: #include \"{}\" is not an embedded GLSL file", it->second.display_name, line_no, lib));
      if (std::find(included.begin(), included.end(), lib) == included.end()) expand(lib, out, included);
      out.text += fmt::format("#line {}\n", id * kLineFileStride + line_no + 1);
      continue;
    }
    out.text.append(line);
    out.text += '\n';
  }
}

std::string rewrite_log(const std::string& log, const AssembledSource& source) {
  static const std::regex mesa(R"((\d+):(\d+)\((\d+)\))");
  static const std::regex nvidia(R"((^|\n)(\d+)\((\d+)\) ?:)");
  auto where = [&](const std::string& line) {
    const long l = std::stol(line);
    const size_t file = size_t(l / kLineFileStride);
    const std::string name = file < source.files.size() ? source.files[file] : "<unknown source>";
    return fmt::format("{}:{}", name, l % kLineFileStride);
  };
  std::string out;
  auto begin = std::sregex_iterator(log.begin(), log.end(), mesa);
  size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    out.append(log, last, static_cast<size_t>(m.position()) - last);
    out += fmt::format("{}:{}", where(m[2].str()), m[3].str());
    last = static_cast<size_t>(m.position() + m.length());
  }
  out.append(log, last);
  if (out != log) return out;
  std::string nv;
  last = 0;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), nvidia); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    nv.append(log, last, static_cast<size_t>(m.position()) - last);
    nv += fmt::format("{}{}:", m[1].str(), where(m[3].str()));
    last = static_cast<size_t>(m.position() + m.length());
  }
  nv.append(log, last);
  return nv;
}

}  // namespace gpgpu
