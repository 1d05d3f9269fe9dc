#include "nurbs/io/query_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <glm/geometric.hpp>
#include <optional>

#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

namespace nurbs::io {
namespace {

bool separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r'; }

/// The words of one line (separated by spaces, tabs and commas; a trailing CR ignored) and their
/// numbers, in order, up to the first word that is not one number (a leading '+' allowed): false then,
/// that word last in `words`.
bool line_numbers(std::string_view line, std::vector<double>& out, std::vector<std::string_view>& words) {
  out.clear(), words.clear();
  for (size_t i = 0;;) {
    while (i < line.size() && separator(line[i])) ++i;
    if (i >= line.size()) return true;
    size_t j = i;
    while (j < line.size() && !separator(line[j])) ++j;
    words.push_back(line.substr(i, j - i));
    const std::optional<double> x = parse_number(words.back());
    if (!x) return false;
    out.push_back(*x);
    i = j;
  }
}

/// The point of a line of three finite numbers within `limit`; nullopt for anything else.
std::optional<glm::dvec3> point_of(std::string_view line, double limit, std::vector<double>& v,
                                   std::vector<std::string_view>& words) {
  if (!line_numbers(line, v, words) || v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) ||
      !std::isfinite(v[2]) || !within_coordinate_limit(glm::dvec3(v[0], v[1], v[2]), limit))
    return std::nullopt;
  return glm::dvec3(v[0], v[1], v[2]);
}

/// Calls line(number, text) for every line of `text` (1-based, without its newline).
template <class F>
void for_lines(std::string_view text, F&& line) {
  int number = 1;
  for (size_t start = 0; start < text.size(); ++number) {
    const size_t end = std::min(text.find('\n', start), text.size());
    line(number, text.substr(start, end - start));
    start = end + 1;
  }
}

}  // namespace

std::optional<double> parse_number(std::string_view word) {
  if (word.size() > 1 && word[0] == '+' && word[1] != '-') word.remove_prefix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), x);
  if (ec != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return x;
}

std::string beyond_limit(double limit) {
  return fmt::format("lies beyond {:.3g}, the coordinates double arithmetic carries for this model", limit);
}

glm::dvec3 parse_point(const std::string& text, const std::string& name, double limit) {
  std::vector<double> v;
  std::vector<std::string_view> words;
  if (const auto p = point_of(text, limit, v, words)) return *p;
  if (v.size() == 3 && words.size() == 3 && std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))
    throw ReadError(name, "", fmt::format("'{}' {}", text, beyond_limit(limit)));
  throw ReadError(name, "", fmt::format("'{}' is not a point X,Y,Z of three finite numbers", text));
}

std::vector<TextRay> parse_rays(std::string_view text, const std::string& name, double limit) {
  std::vector<TextRay> rays;
  std::vector<double> v;
  std::vector<std::string_view> words;
  for_lines(text, [&](int number, std::string_view line) {
    const size_t first = line.find_first_not_of(" \t,\r");
    if (first == std::string_view::npos || line[first] == '#') return;
    const auto where = [number] { return fmt::format("line {}", number); };
    line_numbers(line, v, words);
    // Word by word: the first that is not a finite number, else a seventh.
    for (size_t k = 0; k < words.size() && k < 7; ++k) {
      if (k >= v.size() || !std::isfinite(v[k]))
        throw ReadError(name, where(), fmt::format("'{}' is not a finite number", words[k]));
      if (k == 6) throw ReadError(name, where(), "more than 6 numbers (ox oy oz dx dy dz)");
    }
    if (v.size() != 6)
      throw ReadError(name, where(), fmt::format("{} numbers, expected 6 (ox oy oz dx dy dz)", v.size()));
    const glm::dvec3 origin(v[0], v[1], v[2]);
    if (!within_coordinate_limit(origin, limit))
      throw ReadError(name, where(), fmt::format("the origin ({}, {}, {}) {}", v[0], v[1], v[2], beyond_limit(limit)));
    // Scaled by its largest component first: a length of 1e200-sized components would overflow.
    const double largest = std::max({std::abs(v[3]), std::abs(v[4]), std::abs(v[5])});
    const glm::dvec3 d = largest > 0.0 ? glm::dvec3(v[3], v[4], v[5]) / largest : glm::dvec3(0.0);
    const double length = glm::length(d);
    if (!(length > 0.0) || !std::isfinite(length))
      throw ReadError(name, where(), fmt::format("the direction ({}, {}, {}) has no length", v[3], v[4], v[5]));
    rays.push_back({origin, d / length});
  });
  if (rays.empty()) throw ReadError(name, "", "no rays in the file");
  return rays;
}

}  // namespace nurbs::io
