#include "nurbs/io/query_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <sstream>

#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

namespace nurbs::io {
namespace {

std::string beyond(double limit) {
  return fmt::format("lies beyond {:.3g}, the coordinates double arithmetic carries for this model", limit);
}

}  // namespace

glm::dvec3 parse_point(const std::string& text, const std::string& name, double limit) {
  std::string spaced = text;
  for (char& c : spaced)
    if (c == ',' || c == '\t') c = ' ';
  std::istringstream in(spaced);
  glm::dvec3 p;
  std::string rest;
  if (!(in >> p.x >> p.y >> p.z) || (in >> rest) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    throw ReadError(name, "", fmt::format("'{}' is not a point X,Y,Z of three finite numbers", text));
  if (!within_coordinate_limit(p, limit)) throw ReadError(name, "", fmt::format("'{}' {}", text, beyond(limit)));
  return p;
}

std::vector<glm::dvec3> parse_points(std::string_view text, const std::string& name, double limit) {
  std::istringstream in{std::string(text)};
  std::vector<glm::dvec3> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (line.back() == '\r') line.pop_back();
    out.push_back(parse_point(line, fmt::format("{}: line {}", name, n), limit));
  }
  if (out.empty()) throw ReadError(name, "", "no points in the file");
  return out;
}

std::vector<TextRay> parse_rays(std::string_view text, const std::string& name, double limit) {
  std::istringstream in{std::string(text)};
  std::vector<TextRay> rays;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = fmt::format("line {}", number);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::replace(line.begin(), line.end(), '\t', ' ');
    const size_t first = line.find_first_not_of(" \r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[6];
    int n = 0;
    for (std::string word; fields >> word;) {
      size_t used = 0;
      double x = 0.0;
      try {
        x = std::stod(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || !std::isfinite(x))
        throw ReadError(name, where, fmt::format("'{}' is not a finite number", word));
      if (n == 6) throw ReadError(name, where, "more than 6 numbers (ox oy oz dx dy dz)");
      v[n++] = x;
    }
    if (n != 6) throw ReadError(name, where, fmt::format("{} numbers, expected 6 (ox oy oz dx dy dz)", n));
    const glm::dvec3 origin(v[0], v[1], v[2]);
    if (!within_coordinate_limit(origin, limit))
      throw ReadError(name, where, fmt::format("the origin ({}, {}, {}) {}", v[0], v[1], v[2], beyond(limit)));
    // Scaled by its largest component first: a length of 1e200-sized components would overflow.
    const double largest = std::max({std::abs(v[3]), std::abs(v[4]), std::abs(v[5])});
    const glm::dvec3 d = largest > 0.0 ? glm::dvec3(v[3], v[4], v[5]) / largest : glm::dvec3(0.0);
    const double length = glm::length(d);
    if (!(length > 0.0) || !std::isfinite(length))
      throw ReadError(name, where, fmt::format("the direction ({}, {}, {}) has no length", v[3], v[4], v[5]));
    rays.push_back({origin, d / length});
  }
  if (rays.empty()) throw ReadError(name, "", "no rays in the file");
  return rays;
}

}  // namespace nurbs::io
