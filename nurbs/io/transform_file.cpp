#include "nurbs/io/transform_file.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "nurbs/io/input_file.h"
#include "nurbs/io/query_text.h"
#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

glm::dmat4 from_rows(const std::vector<double>& v, const std::string& name) {
  if (v.size() != 16) throw ReadError(name, "", fmt::format("{} numbers, 16 expected (a 4 x 4 matrix)", v.size()));
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const double x = v[size_t(r * 4 + c)];
      if (!std::isfinite(x)) throw ReadError(name, "", fmt::format("row {} column {} is not finite", r + 1, c + 1));
      m[c][r] = x;  // glm is column-major
    }
  return m;
}

}  // namespace

glm::dmat4 parse_transform(const std::string& text, const std::string& name) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  std::vector<double> v;
  if (first != std::string::npos && (text[first] == '{' || text[first] == '[')) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      throw ReadError(name, "", std::string("not valid JSON: ") + e.what());
    }
    if (j.is_object() && j.contains("alignment")) j = j["alignment"];
    if (j.is_object() && j.contains("matrix")) j = j["matrix"];
    if (!j.is_array() || j.size() != 4) throw ReadError(name, "", "no matrix of four rows in the JSON");
    for (const auto& row : j) {
      if (!row.is_array() || row.size() != 4) throw ReadError(name, "", "a row of the matrix is not four numbers");
      for (const auto& x : row) {
        if (!x.is_number()) throw ReadError(name, "", "a row of the matrix is not four numbers");
        v.push_back(x.get<double>());
      }
    }
    return from_rows(v, name);
  }
  size_t line = 1;
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') {
      ++line, ++i;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == ',') {
      ++i;
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    size_t j = i;
    while (j < text.size() && std::string_view(" \t\r\n,").find(text[j]) == std::string_view::npos) ++j;
    const std::optional<double> x = parse_number(std::string_view(text).substr(i, j - i));
    if (!x)
      throw ReadError(name, fmt::format("line {}", line), fmt::format("'{}' is not a number", text.substr(i, j - i)));
    v.push_back(*x);
    i = j;
  }
  return from_rows(v, name);
}

glm::dmat4 read_transform_file(const std::filesystem::path& path) {
  return parse_transform(read_input_file(path), path.string());
}

}  // namespace nurbs::io
