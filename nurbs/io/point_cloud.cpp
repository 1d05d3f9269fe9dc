#include "nurbs/io/point_cloud.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>

#include "nurbs/io/input_file.h"
#include "nurbs/io/query_text.h"
#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

namespace nurbs::io {
namespace {

/// Points reserved ahead of a count the file states: no more than this until the bytes exist.
constexpr size_t kTrustedReserve = size_t(1) << 20;
/// A PLY or .npy header is at most this long (the formats' own headers are a few hundred bytes).
constexpr size_t kHeaderLimit = size_t(1) << 20;

/// The stream read in blocks, with the offset of the next byte (errors name it).
class Bytes {
 public:
  Bytes(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  uint64_t offset() const { return offset_; }
  /// Up to `n` bytes more in the window (fewer at the end of the stream); returns the bytes available.
  size_t want(size_t n) {
    if (end_ - pos_ >= n) return n;
    buf_.erase(0, pos_), end_ -= pos_, pos_ = 0;
    while (end_ < n) {
      const size_t chunk = std::max(n - end_, kBlock);
      buf_.resize(end_ + chunk);
      in_.read(buf_.data() + end_, std::streamsize(chunk));
      const auto got = size_t(in_.gcount());
      end_ += got;
      if (in_.bad()) throw ReadError(name_, "", "cannot be read (read failed)");
      if (got < chunk) break;
    }
    return std::min(n, end_);
  }
  const char* data() const { return buf_.data() + pos_; }
  void skip(size_t n) { pos_ += n, offset_ += n; }
  /// The next byte, or none at the end.
  std::optional<char> peek() { return want(1) ? std::optional<char>(buf_[pos_]) : std::nullopt; }

 private:
  static constexpr size_t kBlock = size_t(1) << 22;
  std::istream& in_;
  std::string name_;
  std::string buf_;
  size_t pos_ = 0, end_ = 0;
  uint64_t offset_ = 0;
};

/// Lines of the stream, without their end ("\n" or "\r\n"), numbered from 1.
class Lines {
 public:
  explicit Lines(Bytes& bytes) : bytes_(bytes) {}
  /// The next line, or none at the end; valid until the next call.
  std::optional<std::string_view> next(size_t limit = std::numeric_limits<size_t>::max()) {
    size_t n = 0, scanned = 0;
    for (;;) {
      const size_t have = bytes_.want(std::max<size_t>(scanned * 2, 4096));
      const char* d = bytes_.data();
      const void* nl = std::memchr(d + scanned, '\n', have - scanned);
      if (nl) {
        n = size_t(static_cast<const char*>(nl) - d);
        line_.assign(d, n);
        bytes_.skip(n + 1);
        break;
      }
      if (have == scanned) {  // the end of the stream
        if (have == 0) return std::nullopt;
        line_.assign(d, have);
        bytes_.skip(have);
        break;
      }
      scanned = have;
      if (scanned > limit) throw ReadError(bytes_.name(), fmt::format("line {}", number_ + 1), "line too long");
    }
    ++number_;
    std::string_view v(line_);
    if (!v.empty() && v.back() == '\r') v.remove_suffix(1);
    return v;
  }
  std::string where() const { return fmt::format("line {}", number_); }

 private:
  Bytes& bytes_;
  std::string line_;
  size_t number_ = 0;
};

bool separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r'; }

/// The words of a line, split at separators.
void split(std::string_view line, std::vector<std::string_view>& words) {
  words.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && separator(line[i])) ++i;
    const size_t b = i;
    while (i < line.size() && !separator(line[i])) ++i;
    if (i > b) words.push_back(line.substr(b, i - b));
  }
}

void check_point(const glm::dvec3& p, double limit, const std::string& name, const std::string& where) {
  if (within_coordinate_limit(p, limit)) return;
  const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  throw ReadError(name, where,
                  fmt::format("the point ({:g}, {:g}, {:g}) {}", p.x, p.y, p.z,
                              finite ? beyond_limit(limit) : "is not of three finite numbers"));
}

/// The role of a named column (text header, PLY property): 0-2 x y z, 3-5 normal, 6-8 colour, -1 none.
int role(std::string_view raw) {
  std::string s;
  for (const char c : raw)
    if (c != '/' && c != '"' && c != '\'') s += char(std::tolower(static_cast<unsigned char>(c)));
  static const std::array<std::pair<const char*, int>, 21> names{{{"x", 0},
                                                                  {"y", 1},
                                                                  {"z", 2},
                                                                  {"nx", 3},
                                                                  {"ny", 4},
                                                                  {"nz", 5},
                                                                  {"normal_x", 3},
                                                                  {"normal_y", 4},
                                                                  {"normal_z", 5},
                                                                  {"r", 6},
                                                                  {"g", 7},
                                                                  {"b", 8},
                                                                  {"red", 6},
                                                                  {"green", 7},
                                                                  {"blue", 8},
                                                                  {"diffuse_red", 6},
                                                                  {"diffuse_green", 7},
                                                                  {"diffuse_blue", 8},
                                                                  {"scalar_r", 6},
                                                                  {"scalar_g", 7},
                                                                  {"scalar_b", 8}}};
  for (const auto& [n, r] : names)
    if (s == n) return r;
  return -1;
}

/// Columns of the nine roles (-1: absent), from named columns; normals and colours only when all
/// three of theirs are there.
struct Columns {
  std::array<int, 9> at{-1, -1, -1, -1, -1, -1, -1, -1, -1};
  bool normals() const { return at[3] >= 0 && at[4] >= 0 && at[5] >= 0; }
  bool colors() const { return at[6] >= 0 && at[7] >= 0 && at[8] >= 0; }
};

uint8_t color_byte(double v, bool unit) {
  const double c = unit ? v * 255.0 : v;
  return uint8_t(std::clamp(std::lround(std::isfinite(c) ? c : 0.0), 0L, 255L));
}

// ---------------------------------------------------------------------------------------------
// Text

PointCloud read_text(Bytes& bytes, double limit) {
  PointCloud out;
  out.format = "text";
  const std::string& name = bytes.name();
  Lines lines(bytes);
  std::vector<std::string_view> words;
  Columns cols;
  cols.at[0] = 0, cols.at[1] = 1, cols.at[2] = 2;
  bool first = true, named = false, float_colors = false;
  int needed = 3;
  std::vector<glm::dvec3> colors;  // read as numbers, made bytes at the end (their scale known then)
  while (auto line = lines.next(kHeaderLimit)) {
    std::string_view l = *line;
    while (!l.empty() && (l.front() == ' ' || l.front() == '\t')) l.remove_prefix(1);
    if (l.empty()) continue;
    if (l.front() == '#') continue;
    const bool comment = l.starts_with("//");  // a header in the first line, else a comment
    split(l, words);
    if (first) {
      first = false;
      const bool words_only =
          std::none_of(words.begin(), words.end(), [](std::string_view w) { return parse_number(w); });
      if (l.starts_with("//") || (!comment && words_only)) {  // a header naming the columns
        Columns header;
        for (size_t k = 0; k < words.size(); ++k)
          if (const int r = role(words[k]); r >= 0 && header.at[size_t(r)] < 0) header.at[size_t(r)] = int(k);
        if (header.at[0] < 0 || header.at[1] < 0 || header.at[2] < 0)
          throw ReadError(name, lines.where(),
                          fmt::format("the header '{}' names no x, y and z columns", std::string(l.substr(0, 200))));
        cols = header;
        named = true;
        if (!cols.normals()) cols.at[3] = cols.at[4] = cols.at[5] = -1;
        if (!cols.colors()) cols.at[6] = cols.at[7] = cols.at[8] = -1;
        needed = 1 + *std::max_element(cols.at.begin(), cols.at.end());
        continue;
      }
      if (!comment && words.size() == 1 && l.find_first_not_of("0123456789") == std::string_view::npos)
        continue;  // a PTS point count
    }
    if (comment) continue;
    if (!named && (words.size() < 3 || !parse_number(words[0]) || !parse_number(words[1]) || !parse_number(words[2])))
      (void)parse_point(std::string(l.substr(0, 200)), fmt::format("{}: {}", name, lines.where()), limit);
    if (int(words.size()) < needed)
      throw ReadError(
          name, lines.where(),
          fmt::format("{} columns, {} expected: '{}'", words.size(), needed, std::string(l.substr(0, 200))));
    std::array<double, 9> v{};
    for (size_t r = 0; r < 9; ++r) {
      if (cols.at[r] < 0) continue;
      const std::string_view w = words[size_t(cols.at[r])];
      const auto x = parse_number(w);
      if (!x)
        throw ReadError(name, lines.where(),
                        fmt::format("column {} '{}' is not a number", cols.at[r] + 1, std::string(w.substr(0, 60))));
      v[r] = *x;
    }
    const glm::dvec3 p(v[0], v[1], v[2]);
    if (!named && !within_coordinate_limit(p, limit))  // parse_point's message, of the point's three words
      (void)parse_point(fmt::format("{} {} {}", words[0], words[1], words[2]),
                        fmt::format("{}: {}", name, lines.where()), limit);
    check_point(p, limit, name, lines.where());
    out.points.push_back(p);
    if (cols.normals()) out.normals.emplace_back(v[3], v[4], v[5]);
    if (cols.colors()) {
      colors.emplace_back(v[6], v[7], v[8]);
      float_colors = float_colors || v[6] != std::floor(v[6]) || v[7] != std::floor(v[7]) || v[8] != std::floor(v[8]);
    }
  }
  // Colours of fractions (some channel not a whole number) are 0-1; whole numbers 0-255.
  for (const glm::dvec3& c : colors)
    out.colors.emplace_back(color_byte(c.x, float_colors), color_byte(c.y, float_colors),
                            color_byte(c.z, float_colors));
  return out;
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

std::optional<Scalar> scalar_type(std::string_view s) {
  static const std::array<std::pair<const char*, Scalar>, 16> types{{{"char", Scalar::I8},
                                                                     {"int8", Scalar::I8},
                                                                     {"uchar", Scalar::U8},
                                                                     {"uint8", Scalar::U8},
                                                                     {"short", Scalar::I16},
                                                                     {"int16", Scalar::I16},
                                                                     {"ushort", Scalar::U16},
                                                                     {"uint16", Scalar::U16},
                                                                     {"int", Scalar::I32},
                                                                     {"int32", Scalar::I32},
                                                                     {"uint", Scalar::U32},
                                                                     {"uint32", Scalar::U32},
                                                                     {"float", Scalar::F32},
                                                                     {"float32", Scalar::F32},
                                                                     {"double", Scalar::F64},
                                                                     {"float64", Scalar::F64}}};
  for (const auto& [n, t] : types)
    if (s == n) return t;
  return std::nullopt;
}

size_t scalar_size(Scalar t) {
  switch (t) {
    case Scalar::I8:
    case Scalar::U8:
      return 1;
    case Scalar::I16:
    case Scalar::U16:
      return 2;
    case Scalar::I32:
    case Scalar::U32:
    case Scalar::F32:
      return 4;
    case Scalar::F64:
      return 8;
  }
  return 8;
}

/// The scalar at `p` in the file's byte order (`swap`: big endian on this machine or the reverse).
double decode(const char* p, Scalar t, bool swap) {
  std::array<unsigned char, 8> b{};
  const size_t n = scalar_size(t);
  std::memcpy(b.data(), p, n);
  if (swap) std::reverse(b.begin(), b.begin() + long(n));
  auto as = [&]<class T>(T) {
    T v;
    std::memcpy(&v, b.data(), sizeof(T));
    return double(v);
  };
  switch (t) {
    case Scalar::I8:
      return as(int8_t{});
    case Scalar::U8:
      return as(uint8_t{});
    case Scalar::I16:
      return as(int16_t{});
    case Scalar::U16:
      return as(uint16_t{});
    case Scalar::I32:
      return as(int32_t{});
    case Scalar::U32:
      return as(uint32_t{});
    case Scalar::F32:
      return as(float{});
    case Scalar::F64:
      return as(double{});
  }
  return 0.0;
}

struct PlyProperty {
  std::string name;
  Scalar type = Scalar::F32;
  bool list = false;
  Scalar count_type = Scalar::U8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

/// One instance of a binary element read into `values` (the scalars; lists skipped), the bytes
/// consumed returned; throws when the file ends inside it.
size_t binary_instance(Bytes& bytes, const PlyElement& e, bool swap, std::array<double, 9>* values,
                       const std::array<int, 9>& at, const std::string& what) {
  size_t used = 0;
  for (size_t k = 0; k < e.properties.size(); ++k) {
    const PlyProperty& p = e.properties[k];
    if (p.list) {
      const size_t cs = scalar_size(p.count_type);
      if (bytes.want(used + cs) < used + cs)
        throw ReadError(bytes.name(), fmt::format("byte {}", bytes.offset() + used), what + ": the file ends");
      const double c = decode(bytes.data() + used, p.count_type, swap);
      if (!(c >= 0.0) || c > 1e9)
        throw ReadError(bytes.name(), fmt::format("byte {}", bytes.offset() + used),
                        fmt::format("{}: list '{}' of {:g} items", what, p.name, c));
      used += cs + size_t(c) * scalar_size(p.type);
      continue;
    }
    const size_t n = scalar_size(p.type);
    if (bytes.want(used + n) < used + n)
      throw ReadError(bytes.name(), fmt::format("byte {}", bytes.offset() + used), what + ": the file ends");
    if (values)
      for (size_t r = 0; r < 9; ++r)
        if (at[r] == int(k)) (*values)[r] = decode(bytes.data() + used, p.type, swap);
    used += n;
  }
  if (bytes.want(used) < used)
    throw ReadError(bytes.name(), fmt::format("byte {}", bytes.offset() + used), what + ": the file ends");
  return used;
}

PointCloud read_ply(Bytes& bytes, double limit) {
  const std::string& name = bytes.name();
  Lines lines(bytes);
  std::vector<std::string_view> words;
  (void)lines.next();  // "ply"
  std::vector<PlyElement> elements;
  int format = -1;  // 0 ascii, 1 little endian, 2 big endian
  for (;;) {
    const auto line = lines.next(kHeaderLimit);
    if (!line) throw ReadError(name, lines.where(), "the header has no end_header");
    if (bytes.offset() > kHeaderLimit) throw ReadError(name, lines.where(), "the header is too long");
    split(*line, words);
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "end_header") break;
    if (words[0] == "format") {
      if (words.size() < 2 || format >= 0) throw ReadError(name, lines.where(), "bad format line");
      if (words[1] == "ascii")
        format = 0;
      else if (words[1] == "binary_little_endian")
        format = 1;
      else if (words[1] == "binary_big_endian")
        format = 2;
      else
        throw ReadError(name, lines.where(), fmt::format("unknown format '{}'", std::string(words[1].substr(0, 60))));
    } else if (words[0] == "element") {
      const auto count = words.size() == 3 ? parse_number(words[2]) : std::nullopt;
      if (!count || *count < 0 || *count != std::floor(*count) || *count > 1e15)
        throw ReadError(name, lines.where(), "an element line is 'element NAME COUNT'");
      elements.push_back({std::string(words[1]), uint64_t(*count), {}});
    } else if (words[0] == "property") {
      if (elements.empty()) throw ReadError(name, lines.where(), "a property before any element");
      PlyProperty p;
      if (words.size() == 5 && words[1] == "list") {
        const auto ct = scalar_type(words[2]), it = scalar_type(words[3]);
        if (!ct || !it || *ct == Scalar::F32 || *ct == Scalar::F64)
          throw ReadError(name, lines.where(), "bad list property");
        p = {std::string(words[4]), *it, true, *ct};
      } else {
        const auto t = words.size() == 3 ? scalar_type(words[1]) : std::nullopt;
        if (!t) throw ReadError(name, lines.where(), "a property line is 'property TYPE NAME'");
        p = {std::string(words[2]), *t, false, Scalar::U8};
      }
      elements.back().properties.push_back(p);
    } else {
      throw ReadError(name, lines.where(), fmt::format("unknown header line '{}'", std::string(line->substr(0, 80))));
    }
  }
  if (format < 0) throw ReadError(name, lines.where(), "the header has no format line");
  const auto vertex =
      std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == elements.end()) throw ReadError(name, "", "no vertex element");
  Columns cols;
  for (size_t k = 0; k < vertex->properties.size(); ++k)
    if (const int r = role(vertex->properties[k].name); r >= 0 && !vertex->properties[k].list && cols.at[size_t(r)] < 0)
      cols.at[size_t(r)] = int(k);
  if (cols.at[0] < 0 || cols.at[1] < 0 || cols.at[2] < 0)
    throw ReadError(name, "", "the vertex element has no x, y, z");
  if (!cols.normals()) cols.at[3] = cols.at[4] = cols.at[5] = -1;
  if (!cols.colors()) cols.at[6] = cols.at[7] = cols.at[8] = -1;
  const bool unit_colors = cols.colors() && (vertex->properties[size_t(cols.at[6])].type == Scalar::F32 ||
                                             vertex->properties[size_t(cols.at[6])].type == Scalar::F64);

  PointCloud out;
  out.format = format == 0 ? "ply ascii" : format == 1 ? "ply binary little endian" : "ply binary big endian";
  const uint64_t n = vertex->count;
  out.points.reserve(size_t(std::min<uint64_t>(n, kTrustedReserve)));
  auto keep = [&](const std::array<double, 9>& v) {  // its coordinates checked
    out.points.emplace_back(v[0], v[1], v[2]);
    if (cols.normals()) out.normals.emplace_back(v[3], v[4], v[5]);
    if (cols.colors())
      out.colors.emplace_back(color_byte(v[6], unit_colors), color_byte(v[7], unit_colors),
                              color_byte(v[8], unit_colors));
  };
  if (format == 0) {
    for (const PlyElement& e : elements) {
      const bool is_vertex = &e == &*vertex;
      for (uint64_t i = 0; i < e.count; ++i) {
        const std::string what = fmt::format("{} {} of {}", e.name, i, e.count);
        auto line = lines.next(kHeaderLimit);
        if (!line) throw ReadError(name, lines.where(), what + ": the file ends");
        split(*line, words);
        size_t w = 0;
        std::array<double, 9> v{};
        for (size_t k = 0; k < e.properties.size(); ++k) {
          const PlyProperty& p = e.properties[k];
          auto value = [&]() {
            const auto x = w < words.size() ? parse_number(words[w]) : std::nullopt;
            if (!x)
              throw ReadError(name, lines.where(),
                              fmt::format("{}: property '{}' is missing or not a number", what, p.name));
            ++w;
            return *x;
          };
          if (p.list) {
            const double c = value();
            if (!(c >= 0.0) || c > double(words.size())) throw ReadError(name, lines.where(), what + ": bad list");
            w += size_t(c);
            continue;
          }
          const double x = value();
          for (size_t r = 0; r < 9; ++r)
            if (cols.at[r] == int(k)) v[r] = x;
        }
        if (is_vertex) {
          check_point(glm::dvec3(v[0], v[1], v[2]), limit, name, lines.where());
          keep(v);
        }
      }
      if (is_vertex) break;
    }
    return out;
  }
  const bool swap = (format == 2) == (std::endian::native == std::endian::little);
  for (const PlyElement& e : elements) {
    const bool is_vertex = &e == &*vertex;
    const bool fixed =
        std::none_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& p) { return p.list; });
    size_t stride = 0;
    for (const PlyProperty& p : e.properties) stride += scalar_size(p.type);
    for (uint64_t i = 0; i < e.count;) {
      if (fixed && is_vertex) {  // a block of whole vertices at once
        const uint64_t block = std::min<uint64_t>(e.count - i, (uint64_t(1) << 22) / std::max<size_t>(stride, 1) + 1);
        const size_t have = bytes.want(size_t(block) * stride) / std::max<size_t>(stride, 1);
        if (have == 0)
          throw ReadError(name, fmt::format("byte {}", bytes.offset()),
                          fmt::format("vertex {} of {}: the file ends", i, e.count));
        std::array<size_t, 9> offset{};
        for (size_t r = 0; r < 9; ++r)
          for (int k = 0; k < cols.at[r]; ++k) offset[r] += scalar_size(e.properties[size_t(k)].type);
        for (size_t j = 0; j < have; ++j, ++i) {
          const char* d = bytes.data() + j * stride;
          std::array<double, 9> v{};
          for (size_t r = 0; r < 9; ++r)
            if (cols.at[r] >= 0) v[r] = decode(d + offset[r], e.properties[size_t(cols.at[r])].type, swap);
          const glm::dvec3 p(v[0], v[1], v[2]);
          if (!within_coordinate_limit(p, limit))
            check_point(p, limit, name,
                        fmt::format("byte {}: vertex {} of {}", bytes.offset() + j * stride, i, e.count));
          keep(v);
        }
        bytes.skip(have * stride);
        continue;
      }
      const std::string what = fmt::format("{} {} of {}", e.name, i, e.count);
      std::array<double, 9> v{};
      const uint64_t at = bytes.offset();
      const size_t used = binary_instance(bytes, e, swap, is_vertex ? &v : nullptr, cols.at, what);
      if (is_vertex) {
        check_point(glm::dvec3(v[0], v[1], v[2]), limit, name, fmt::format("byte {}: {}", at, what));
        keep(v);
      }
      bytes.skip(used);
      ++i;
    }
    if (is_vertex) break;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// NumPy .npy

/// The value of `key` in the header's dict text (up to the next ',' or '}' outside brackets).
std::optional<std::string> dict_value(std::string_view dict, std::string_view key) {
  for (const char q : {'\'', '"'}) {
    const std::string k = std::string(1, q) + std::string(key) + std::string(1, q);
    const size_t at = dict.find(k);
    if (at == std::string_view::npos) continue;
    size_t i = dict.find(':', at + k.size());
    if (i == std::string_view::npos) return std::nullopt;
    ++i;
    int depth = 0;
    size_t b = i;
    for (; i < dict.size(); ++i) {
      const char c = dict[i];
      if (c == '(' || c == '[') ++depth;
      if (c == ')' || c == ']') --depth;
      if (depth == 0 && (c == ',' || c == '}')) break;
      if (depth < 0) return std::nullopt;
    }
    std::string v(dict.substr(b, i - b));
    v.erase(std::remove_if(v.begin(), v.end(), [](char c) { return c == ' ' || c == '\'' || c == '"'; }), v.end());
    return v;
  }
  return std::nullopt;
}

PointCloud read_npy(Bytes& bytes, double limit) {
  const std::string& name = bytes.name();
  if (bytes.want(10) < 10) throw ReadError(name, "byte 0", "a truncated .npy header");
  const auto* h = reinterpret_cast<const unsigned char*>(bytes.data());
  const int major = h[6];
  if (major < 1 || major > 3) throw ReadError(name, "byte 6", fmt::format("unknown .npy version {}", major));
  size_t header_len = size_t(h[8]) | size_t(h[9]) << 8, start = 10;
  if (major >= 2) {
    if (bytes.want(12) < 12) throw ReadError(name, "byte 0", "a truncated .npy header");
    h = reinterpret_cast<const unsigned char*>(bytes.data());
    header_len = size_t(h[8]) | size_t(h[9]) << 8 | size_t(h[10]) << 16 | size_t(h[11]) << 24, start = 12;
  }
  if (header_len > kHeaderLimit) throw ReadError(name, "byte 8", "the .npy header is too long");
  if (bytes.want(start + header_len) < start + header_len) throw ReadError(name, "byte 8", "a truncated .npy header");
  const std::string dict(bytes.data() + start, header_len);
  bytes.skip(start + header_len);
  const auto descr = dict_value(dict, "descr"), order = dict_value(dict, "fortran_order"),
             shape = dict_value(dict, "shape");
  if (!descr || !order || !shape)
    throw ReadError(name, "byte 10", "the .npy header lacks descr, fortran_order or shape");
  if (descr->size() != 3 || (descr->substr(1) != "f4" && descr->substr(1) != "f8") ||
      ((*descr)[0] != '<' && (*descr)[0] != '>' && (*descr)[0] != '='))
    throw ReadError(name, "byte 10", fmt::format("the array's type '{}' is not float32 or float64", printable(*descr)));
  const bool fortran = *order == "True";
  if (!fortran && *order != "False") throw ReadError(name, "byte 10", "fortran_order is not True or False");
  // shape "(N,K)" with K >= 3
  std::vector<uint64_t> dims;
  {
    std::string_view s(*shape);
    if (s.size() < 2 || s.front() != '(' || s.back() != ')') throw ReadError(name, "byte 10", "bad shape");
    s = s.substr(1, s.size() - 2);
    while (!s.empty()) {
      const size_t c = s.find(',');
      const std::string_view w = s.substr(0, c);
      if (!w.empty()) {
        uint64_t d = 0;
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), d);
        if (ec != std::errc() || end != w.data() + w.size()) throw ReadError(name, "byte 10", "bad shape");
        dims.push_back(d);
      }
      if (c == std::string_view::npos) break;
      s.remove_prefix(c + 1);
    }
  }
  if (dims.size() != 2 || dims[1] < 3 || dims[1] > 4096)
    throw ReadError(name, "byte 10", fmt::format("the array's shape {} is not N x 3 (or more columns)", *shape));
  const uint64_t rows = dims[0], columns = dims[1];
  const size_t size = (*descr)[2] == '4' ? 4 : 8;
  const Scalar type = size == 4 ? Scalar::F32 : Scalar::F64;
  const bool big = (*descr)[0] == '>' || ((*descr)[0] == '=' && std::endian::native == std::endian::big);
  const bool swap = big == (std::endian::native == std::endian::little);
  PointCloud out;
  out.format = size == 4 ? "npy float32" : "npy float64";
  out.points.reserve(size_t(std::min<uint64_t>(rows, kTrustedReserve)));
  auto where = [&](uint64_t row) { return fmt::format("byte {}: row {} of {}", bytes.offset(), row, rows); };
  if (!fortran) {
    const size_t stride = size_t(columns) * size;
    for (uint64_t i = 0; i < rows;) {
      const uint64_t block = std::min<uint64_t>(rows - i, (uint64_t(1) << 22) / stride + 1);
      const size_t have = bytes.want(size_t(block) * stride) / stride;
      if (have == 0) throw ReadError(name, where(i), "the file ends");
      for (size_t j = 0; j < have; ++j, ++i) {
        const char* d = bytes.data() + j * stride;
        const glm::dvec3 p(decode(d, type, swap), decode(d + size, type, swap), decode(d + 2 * size, type, swap));
        if (!within_coordinate_limit(p, limit))
          check_point(p, limit, name, fmt::format("byte {}: row {} of {}", bytes.offset() + j * stride, i, rows));
        out.points.push_back(p);
      }
      bytes.skip(have * stride);
    }
    return out;
  }
  // Fortran order: column x of every row, then y, then z.
  for (int c = 0; c < 3; ++c)
    for (uint64_t i = 0; i < rows;) {
      const uint64_t block = std::min<uint64_t>(rows - i, (uint64_t(1) << 22) / size);
      const size_t have = bytes.want(size_t(block) * size) / size;
      if (have == 0) throw ReadError(name, where(i), fmt::format("column {}: the file ends", c));
      if (c == 0) out.points.resize(out.points.size() + have);
      for (size_t j = 0; j < have; ++j, ++i) out.points[size_t(i)][c] = decode(bytes.data() + j * size, type, swap);
      bytes.skip(have * size);
    }
  for (size_t i = 0; i < out.points.size(); ++i)
    if (!within_coordinate_limit(out.points[i], limit))
      check_point(out.points[i], limit, name, fmt::format("row {} of {}", i, rows));
  return out;
}

}  // namespace

PointCloud read_point_cloud(std::istream& in, const std::string& name, double limit) {
  Bytes bytes(in, name);
  const size_t have = bytes.want(6);
  const std::string_view head(bytes.data(), have);
  PointCloud out;
  if (head.size() >= 6 && head == std::string_view("\x93NUMPY", 6))
    out = read_npy(bytes, limit);
  else if (head.size() >= 4 && head.substr(0, 3) == "ply" && (head[3] == '\n' || head[3] == '\r'))
    out = read_ply(bytes, limit);
  else
    out = read_text(bytes, limit);
  if (out.points.empty()) throw ReadError(name, "", "no points in the file");
  return out;
}

PointCloud read_point_cloud_file(const std::filesystem::path& path, double limit) {
  std::ifstream in = open_input_file(path);
  return read_point_cloud(in, path.string(), limit);
}

}  // namespace nurbs::io
