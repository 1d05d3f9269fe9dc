#include "nurbs/io/iges_params.h"

#include <fmt/format.h>

#include <cmath>

#include "nurbs/io/read_error.h"

namespace nurbs::io {

std::string entity_name(const IgesDirectoryEntry& e) { return fmt::format("entity D{} (type {})", e.de, e.type); }

EntityParams::EntityParams(const IgesFile& file, const IgesDirectoryEntry& entry) : file_(file), entry_(entry) {
  const int first = entry.parameter_start;
  const int count = entry.parameter_lines;
  const int available = static_cast<int>(file.parameters.size());
  if (first < 1 || count < 1 || first > available || count > available - first + 1)
    throw ReadError(file.name, fmt::format("line {}", entry.line),
                    fmt::format("{}: parameter lines {}..{} are outside the parameter section (P1..P{})",
                                entity_name(entry), first, first + count - 1, available));
  first_line_ = file.parameters[static_cast<size_t>(first - 1)].line;
  data_.reserve(static_cast<size_t>(count) * 64);
  for (int k = 0; k < count; ++k) {
    const IgesParameterLine& p = file.parameters[static_cast<size_t>(first - 1 + k)];
    if (p.de != entry.de)
      throw ReadError(
          file.name, fmt::format("line {}", p.line),
          fmt::format("parameter line P{} belongs to D{}, but {} claims it", first + k, p.de, entity_name(entry)));
    data_.append(p.data);
  }
  IgesTokens t = tokenize_iges(data_, 0, file.global.parameter_delimiter, file.global.record_delimiter);
  if (!t.error.empty())
    throw ReadError(file.name, fmt::format("line {}", first_line_ + static_cast<int>(t.error_offset / 64)),
                    fmt::format("{}: {}", entity_name(entry), t.error));
  if (!t.terminated)
    throw ReadError(file.name, fmt::format("line {}", first_line_ + count - 1),
                    fmt::format("parameter record of {} truncated (no '{}' in its {} lines)", entity_name(entry),
                                file.global.record_delimiter, count));
  fields_ = std::move(t.fields);
  auto type = parse_iges_int(fields_.front().text);
  if (!type || *type != entry.type)
    fail(0, fmt::format("parameter record starts with '{}', expected the entity type {}", fields_.front().text,
                        entry.type));
}

std::string EntityParams::where(int i) const {
  size_t offset =
      (i >= 0 && i < static_cast<int>(fields_.size())) ? fields_[static_cast<size_t>(i)].offset : data_.size() - 1;
  return fmt::format("line {}: {}", first_line_ + static_cast<int>(offset / 64), entity_name(entry_));
}

void EntityParams::fail(int i, const std::string& problem) const {
  std::string where_text = where(i);
  size_t colon = where_text.find(": ");
  std::string what =
      i > 0 ? fmt::format("{}, parameter {}", where_text.substr(colon + 2), i) : where_text.substr(colon + 2);
  throw ReadError(file_.name, where_text.substr(0, colon), what + ": " + problem);
}

void EntityParams::require(int count) const {
  if (size() < count)
    fail(size(), fmt::format("bad parameter count: needs at least {} parameters, the record has {}", count, size()));
}

double EntityParams::real(int i) const {
  require(i);
  std::string_view s = fields_[static_cast<size_t>(i)].text;
  auto v = parse_iges_real(s);
  if (!v) fail(i, fmt::format("expected a real number, got '{}'", s));
  if (!std::isfinite(*v)) fail(i, fmt::format("'{}' is not a finite number", s));
  return *v;
}

int EntityParams::integer(int i) const {
  require(i);
  std::string_view s = fields_[static_cast<size_t>(i)].text;
  auto v = parse_iges_int(s);
  if (!v) fail(i, fmt::format("expected an integer, got '{}'", s));
  return *v;
}

int EntityParams::integer(int i, int lo, int hi, const char* what) const {
  int v = integer(i);
  if (v < lo || v > hi) fail(i, fmt::format("{} is {}, must be in [{}, {}]", what, v, lo, hi));
  return v;
}

int EntityParams::pointer(int i, bool allow_null) const {
  int v = integer(i);
  if (v == 0 && allow_null) return 0;
  if (v <= 0 || v % 2 == 0 || !file_.has_entry(v))
    fail(i, fmt::format("pointer {} does not name a directory entry (D1..D{}, odd)", v, 2 * file_.entries.size() - 1));
  return v;
}

std::string EntityParams::string(int i) const {
  require(i);
  return std::string(fields_[static_cast<size_t>(i)].text);
}

void EntityParams::check_trailing(int used) const {
  int i = used + 1;
  for (int group = 0; group < 2 && i <= size(); ++group) {
    int n = integer(i);
    if (n < 0 || n > size() - i)
      fail(i, fmt::format("bad parameter count: {} extra parameters after the entity data", size() - used));
    for (int k = 1; k <= n; ++k) {
      int v = integer(i + k);
      if (v != 0 && !file_.has_entry(std::abs(v)))
        fail(i + k, fmt::format("bad parameter count or pointer: trailing pointer {} names no directory entry", v));
    }
    i += n + 1;
  }
  if (i <= size())
    fail(i, fmt::format("bad parameter count: {} extra parameters after the entity data", size() - used));
}

}  // namespace nurbs::io
