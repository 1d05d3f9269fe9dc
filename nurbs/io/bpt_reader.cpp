#include "nurbs/io/bpt_reader.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "nurbs/io/input_file.h"
#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

constexpr int kMaxDegree = 32;         // far above any real Bézier patch; bounds memory on bad input
constexpr int kMaxPatches = 10000000;  // likewise

class LineReader {
 public:
  LineReader(const std::string& text, const std::string& name) : text_(text), name_(name) {}

  // The numbers on the next non-blank line; `count` of them exactly, else ReadError.
  std::vector<double> numbers(size_t count, const std::string& what) {
    std::string_view line;
    do {
      if (pos_ >= text_.size())
        throw ReadError(name_, fmt::format("line {}", line_no_ + 1), fmt::format("{}: unexpected end of file", what));
      size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      line = std::string_view(text_).substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_no_;
    } while (line.find_first_not_of(" \t\r") == std::string_view::npos);
    std::vector<double> out;
    size_t i = 0;
    while (true) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i == line.size()) break;
      size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      double v = 0.0;
      const char* first = line.data() + i + (line[i] == '+' ? 1 : 0);
      auto [end, ec] = std::from_chars(first, line.data() + j, v);
      if (ec != std::errc() || end != line.data() + j)
        fail(fmt::format("{}: '{}' is not a number", what, line.substr(i, j - i)));
      if (!std::isfinite(v)) fail(fmt::format("{}: '{}' is not a finite number", what, line.substr(i, j - i)));
      out.push_back(v);
      i = j;
    }
    if (out.size() != count) fail(fmt::format("{}: expected {} numbers, found {}", what, count, out.size()));
    return out;
  }

  // Line number of the first non-blank line after the data read so far, 0 if there is none.
  int trailing_line() const {
    int line = line_no_ + 1;
    for (size_t i = pos_; i < text_.size(); ++i) {
      if (text_[i] == '\n')
        ++line;
      else if (text_[i] != ' ' && text_[i] != '\t' && text_[i] != '\r')
        return line;
    }
    return 0;
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw ReadError(name_, fmt::format("line {}", line_no_), problem);
  }

 private:
  const std::string& text_;
  const std::string& name_;
  size_t pos_ = 0;
  int line_no_ = 0;
};

int as_int(double v, int lo, int hi, const std::string& what, const LineReader& r) {
  if (v != std::floor(v) || v < lo || v > hi)
    r.fail(fmt::format("{} is {}, expected an integer in [{}, {}]", what, v, lo, hi));
  return static_cast<int>(v);
}

std::vector<double> bezier_knots(int degree) {
  std::vector<double> k(static_cast<size_t>(degree + 1), 0.0);
  k.insert(k.end(), static_cast<size_t>(degree + 1), 1.0);
  return k;
}

}  // namespace

Model read_bpt_text(const std::string& text, const std::string& name) {
  LineReader r(text, name);
  const int count = as_int(r.numbers(1, "patch count")[0], 1, kMaxPatches, "patch count", r);
  Body body{"patches", {}, glm::dmat4(1.0), {}};
  for (int k = 0; k < count; ++k) {
    const std::string patch = fmt::format("patch {}", k + 1);
    const auto deg = r.numbers(2, patch + " degrees");
    const int n = as_int(deg[0], 1, kMaxDegree, patch + " degree u", r);
    const int m = as_int(deg[1], 1, kMaxDegree, patch + " degree v", r);
    TrimmedSurface face;
    face.face_id = k;
    face.name = patch;
    Surface& s = face.surface;
    s.degree_u = n;
    s.degree_v = m;
    s.count_u = n + 1;
    s.count_v = m + 1;
    s.knots_u = bezier_knots(n);
    s.knots_v = bezier_knots(m);
    s.points.resize(static_cast<size_t>((n + 1) * (m + 1)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= m; ++j) {
        const auto p = r.numbers(3, fmt::format("{} point ({}, {})", patch, i, j));
        s.points[static_cast<size_t>(j * (n + 1) + i)] = {p[0], p[1], p[2]};  // row i = u index; Surface is u-fastest
      }
    body.faces.push_back(std::move(face));
  }
  if (int extra = r.trailing_line(); extra != 0)
    throw ReadError(name, fmt::format("line {}", extra),
                    fmt::format("data after the {} patches announced on line 1", count));
  Model model;
  model.source = name;
  model.bodies.push_back(std::move(body));
  return model;
}

Model read_bpt(const std::filesystem::path& path) {
  return read_bpt_text(read_input_file(path), path.string());
}

}  // namespace nurbs::io
