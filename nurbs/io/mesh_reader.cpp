#include "nurbs/io/mesh_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "nurbs/io/input_file.h"
#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

static_assert(std::endian::native == std::endian::little, "the binary readers assume a little-endian host");

using Tokens = std::vector<std::string_view>;

/// Whitespace-separated words of a line.
void split(std::string_view line, Tokens& out) {
  out.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

/// Text lines with their 1-based numbers; "\r\n" and "\n" endings.
struct Lines {
  std::string_view text;
  size_t pos = 0;
  int number = 0;
  bool next(std::string_view& line) {
    if (pos >= text.size()) return false;
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    line = text.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = end + 1;
    ++number;
    return true;
  }
};

/// The finite number `token` is, or false (a leading '+' is allowed).
bool parse_number(std::string_view token, double& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size() && std::isfinite(value);
}

bool parse_integer(std::string_view token, long long& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

/// Welds bit-identical positions (STL repeats every vertex per facet).
class Welder {
 public:
  explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
  int add(const glm::dvec3& p) {
    const Key key{std::bit_cast<uint64_t>(p.x), std::bit_cast<uint64_t>(p.y), std::bit_cast<uint64_t>(p.z)};
    const auto [it, inserted] = index_.try_emplace(key, int(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(p);
    return it->second;
  }

 private:
  using Key = std::array<uint64_t, 3>;
  struct Hash {
    size_t operator()(const Key& k) const {
      return k[0] * 0x9E3779B97F4A7C15ull ^ (k[1] * 31 + k[2]) * 1099511628211ull;
    }
  };
  TriangleMesh& mesh_;
  std::unordered_map<Key, int, Hash> index_;
};

/// Most corners of one polygon: a fan of more is no longer a face of a mesh (a non-convex outline,
/// or a file made to multiply work).
constexpr size_t kMaxPolygonCorners = size_t(1) << 16;

/// Corners c0..cn-1 of a convex-enough polygon as the fan (c0, ci, ci+1), leaving out the triangles
/// that name one vertex twice (they have no area to measure). Returns what is wrong with the
/// polygon, empty when nothing: more than kMaxPolygonCorners corners.
std::string add_fan(TriangleMesh& mesh, const std::vector<int>& corners) {
  if (corners.size() > kMaxPolygonCorners)
    return fmt::format("polygon has {} corners, more than {}", corners.size(), kMaxPolygonCorners);
  for (size_t i = 1; i + 1 < corners.size(); ++i) {
    const int a = corners[0], b = corners[i], c = corners[i + 1];
    if (a != b && b != c && c != a) mesh.triangles.emplace_back(a, b, c);
  }
  return "";
}

/// What is wrong with a vertex at `p`, empty when its coordinates are within `limit` in magnitude
/// (nurbs::coordinate_limit of the model it is measured against).
std::string check_vertex(const glm::dvec3& p, double limit) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(p[c]) <= limit))
      return fmt::format("coordinate {:g} is beyond {:.3g}, the range double arithmetic carries for this model", p[c],
                         limit);
  return "";
}

/// Binary STL: 80-byte header, uint32 count, 50 bytes per facet (normal, 3 vertices, attribute).
TriangleMesh read_stl_binary(std::string_view data, const std::string& name, double limit) {
  if (data.size() < 84)
    throw ReadError(name, fmt::format("byte {}", data.size()),
                    fmt::format("binary STL header needs 84 bytes, the file has {} (truncated)", data.size()));
  uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  TriangleMesh mesh;
  Welder welder(mesh);
  for (uint32_t k = 0; k < count; ++k) {
    const size_t at = 84 + size_t(k) * 50;
    if (at + 50 > data.size())
      throw ReadError(name, fmt::format("byte {}", data.size()),
                      fmt::format("facet {} of {}: file ends (truncated)", k, count));
    float v[9];
    std::memcpy(v, data.data() + at + 12, sizeof v);
    glm::ivec3 t;
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3 p(v[3 * c], v[3 * c + 1], v[3 * c + 2]);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw ReadError(name, fmt::format("byte {}", at + 12 + 12 * c),
                        fmt::format("facet {} of {}: vertex {} is not finite", k, count, c));
      if (const std::string problem = check_vertex(p, limit); !problem.empty())
        throw ReadError(name, fmt::format("byte {}", at + 12 + 12 * c),
                        fmt::format("facet {} of {}: vertex {}: {}", k, count, c, problem));
      t[c] = welder.add(p);
    }
    if (t.x != t.y && t.y != t.z && t.z != t.x) mesh.triangles.push_back(t);
  }
  return mesh;
}

/// ASCII STL: solid / facet normal / outer loop / vertex x y z (x3) / endloop / endfacet / endsolid.
TriangleMesh read_stl_ascii(std::string_view text, const std::string& name, double limit) {
  TriangleMesh mesh;
  Welder welder(mesh);
  Lines lines{text};
  Tokens w;
  enum { Outside, InSolid, InFacet, InLoop } state = Outside;
  std::vector<int> corners;
  auto fail = [&](const std::string& problem) { throw ReadError(name, fmt::format("line {}", lines.number), problem); };
  for (std::string_view line; lines.next(line);) {
    split(line, w);
    if (w.empty()) continue;
    const std::string_view key = w[0];
    if (key == "solid" && state == Outside) {
      state = InSolid;
    } else if (key == "facet" && state == InSolid) {
      state = InFacet;
      corners.clear();
    } else if (key == "outer" && state == InFacet) {
      state = InLoop;
    } else if (key == "vertex" && state == InLoop) {
      glm::dvec3 p;
      if (w.size() != 4) fail(fmt::format("'vertex' needs 3 numbers, got {}", w.size() - 1));
      for (int c = 0; c < 3; ++c)
        if (!parse_number(w[size_t(c) + 1], p[c])) fail(fmt::format("'{}' is not a finite number", w[size_t(c) + 1]));
      if (const std::string problem = check_vertex(p, limit); !problem.empty()) fail("vertex: " + problem);
      corners.push_back(welder.add(p));
    } else if (key == "endloop" && state == InLoop) {
      state = InFacet;
    } else if (key == "endfacet" && state == InFacet) {
      if (corners.size() < 3) fail(fmt::format("facet has {} vertices, expected 3", corners.size()));
      if (const std::string problem = add_fan(mesh, corners); !problem.empty()) fail(problem);
      state = InSolid;
    } else if (key == "endsolid" && state == InSolid) {
      state = Outside;
    } else {
      fail(fmt::format("unexpected '{}'", key));
    }
  }
  if (state == InFacet || state == InLoop) fail("file ends inside a facet (truncated)");
  if (state == InSolid) fail("file ends before 'endsolid' (truncated)");
  return mesh;
}

/// Binary when the size matches the facet count at byte 80 or the file does not start with "solid"
/// followed by text (binary headers may start with "solid" too).
TriangleMesh read_stl(std::string_view data, const std::string& name, double limit) {
  if (data.size() >= 84) {
    uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if (84 + 50 * uint64_t(count) == data.size()) return read_stl_binary(data, name, limit);
  }
  size_t first = data.find_first_not_of(" \t\r\n");
  const bool solid = first != std::string_view::npos && data.substr(first, 5) == "solid";
  const std::string_view head = data.substr(0, 512);
  const bool text = std::none_of(head.begin(), head.end(), [](char c) { return c == '\0'; });
  return solid && text ? read_stl_ascii(data, name, limit) : read_stl_binary(data, name, limit);
}

/// Wavefront OBJ: "v x y z [w]" and "f a b c ..." with a, a/t, a//n, a/t/n, negative = relative.
TriangleMesh read_obj(std::string_view text, const std::string& name, double limit) {
  TriangleMesh mesh;
  Lines lines{text};
  Tokens w;
  std::vector<int> corners;
  auto fail = [&](const std::string& problem) { throw ReadError(name, fmt::format("line {}", lines.number), problem); };
  for (std::string_view line; lines.next(line);) {
    split(line, w);
    if (w.empty() || w[0][0] == '#') continue;
    if (w[0] == "v") {
      if (w.size() < 4) fail(fmt::format("'v' needs 3 coordinates, got {}", w.size() - 1));
      glm::dvec3 p;
      for (int c = 0; c < 3; ++c)
        if (!parse_number(w[size_t(c) + 1], p[c])) fail(fmt::format("'{}' is not a finite number", w[size_t(c) + 1]));
      if (const std::string problem = check_vertex(p, limit); !problem.empty())
        fail(fmt::format("vertex {}: {}", mesh.positions.size() + 1, problem));
      mesh.positions.push_back(p);
    } else if (w[0] == "f") {
      if (w.size() < 4) fail(fmt::format("face has {} vertices, expected at least 3", w.size() - 1));
      corners.clear();
      const long long n = (long long)mesh.positions.size();
      for (size_t c = 1; c < w.size(); ++c) {
        long long i = 0;
        if (!parse_integer(w[c].substr(0, w[c].find('/')), i)) fail(fmt::format("'{}' is not a vertex index", w[c]));
        if (i == 0) fail("vertex index 0 (OBJ counts from 1)");
        const long long index = i > 0 ? i - 1 : n + i;
        if (index < 0 || index >= n) fail(fmt::format("vertex index {} out of range ({} vertices so far)", i, n));
        corners.push_back(int(index));
      }
      if (const std::string problem = add_fan(mesh, corners); !problem.empty()) fail(problem);
    }
    // vn, vt, g, o, s, usemtl, mtllib, l, p, ...: not geometry we measure.
  }
  return mesh;
}

/// PLY scalar types, by their size in bytes and whether they are integers / signed.
enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

bool ply_type(std::string_view word, PlyType& t) {
  static const std::pair<std::string_view, PlyType> names[] = {
      {"char", PlyType::I8},   {"int8", PlyType::I8},     {"uchar", PlyType::U8},   {"uint8", PlyType::U8},
      {"short", PlyType::I16}, {"int16", PlyType::I16},   {"ushort", PlyType::U16}, {"uint16", PlyType::U16},
      {"int", PlyType::I32},   {"int32", PlyType::I32},   {"uint", PlyType::U32},   {"uint32", PlyType::U32},
      {"float", PlyType::F32}, {"float32", PlyType::F32}, {"double", PlyType::F64}, {"float64", PlyType::F64}};
  for (const auto& [n, type] : names)
    if (n == word) return t = type, true;
  return false;
}

struct PlyProperty {
  std::string name;
  bool list = false;
  PlyType count_type = PlyType::U8, type = PlyType::F32;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

/// The body of a PLY file: one scalar at a time, ASCII tokens or little-endian binary values.
/// `element`, `item`, `count` say what is being read, for the error message.
struct PlyBody {
  std::string_view data;
  size_t pos = 0;
  bool binary = false;
  int line = 0;  ///< ASCII: line of the next token
  const std::string& name;
  const PlyElement* element = nullptr;
  long long item = 0;

  [[noreturn]] void fail(const std::string& problem) const {
    throw ReadError(name, binary ? fmt::format("byte {}", pos) : fmt::format("line {}", line),
                    fmt::format("{} {} of {}: {}", element->name, item, element->count, problem));
  }

  template <typename T>
  double get() {
    T v;
    if (pos + sizeof(T) > data.size()) pos = data.size(), fail("file ends (truncated)");
    std::memcpy(&v, data.data() + pos, sizeof(T));
    pos += sizeof(T);
    return double(v);
  }

  double scalar(PlyType t) {
    if (binary) switch (t) {
        case PlyType::I8:
          return get<int8_t>();
        case PlyType::U8:
          return get<uint8_t>();
        case PlyType::I16:
          return get<int16_t>();
        case PlyType::U16:
          return get<uint16_t>();
        case PlyType::I32:
          return get<int32_t>();
        case PlyType::U32:
          return get<uint32_t>();
        case PlyType::F32:
          return get<float>();
        case PlyType::F64:
          return get<double>();
      }
    while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) line += data[pos++] == '\n';
    if (pos >= data.size()) {  // name the file's last line, not the one after its final newline
      line = int(std::count(data.begin(), data.end(), '\n')) + (data.empty() || data.back() != '\n');
      fail("file ends (truncated)");
    }
    const size_t start = pos;
    while (pos < data.size() && !std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
    double v = 0;
    const std::string_view token = data.substr(start, pos - start);
    if (!parse_number(token, v)) fail(fmt::format("'{}' is not a number", token));
    return v;
  }

  /// A list count or vertex index: an integer in [0, limit).
  long long index(PlyType t, long long limit, const char* what) {
    const double v = scalar(t);
    if (v != std::floor(v) || v < 0 || v >= double(limit))
      fail(fmt::format("{} {} out of range ({} allowed)", what, v, limit));
    return (long long)v;
  }
};

/// Bytes one item of `e` takes at the least: binary, its scalars and list counts; ASCII, a character
/// per property (the separators left uncounted, so that a short file is named where it ends).
size_t ply_least_item_bytes(const PlyElement& e, bool binary) {
  static constexpr size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};  // by PlyType
  size_t bytes = 0;
  for (const PlyProperty& p : e.properties) bytes += binary ? sizes[size_t(p.list ? p.count_type : p.type)] : 1;
  return bytes;
}

/// PLY header ("ply", format, element/property lines, end_header), then the elements in order.
TriangleMesh read_ply(std::string_view data, const std::string& name, double limit) {
  Lines lines{data};
  Tokens w;
  std::vector<PlyElement> elements;
  bool binary = false, ended = false, format = false;
  auto fail = [&](const std::string& problem) { throw ReadError(name, fmt::format("line {}", lines.number), problem); };
  for (std::string_view line; !ended && lines.next(line);) {
    split(line, w);
    if (lines.number == 1) {
      if (w.size() != 1 || w[0] != "ply") fail("not a PLY file (no 'ply' magic)");
    } else if (w.empty() || w[0] == "comment" || w[0] == "obj_info") {
    } else if (w[0] == "format" && w.size() == 3) {
      if (w[1] != "ascii" && w[1] != "binary_little_endian") fail(fmt::format("format {} is not supported", w[1]));
      binary = w[1] != "ascii", format = true;
    } else if (w[0] == "element" && w.size() == 3) {
      PlyElement e;
      e.name = std::string(w[1]);
      if (!parse_integer(w[2], e.count) || e.count < 0) fail(fmt::format("bad element count '{}'", w[2]));
      elements.push_back(e);
    } else if (w[0] == "property" && !elements.empty()) {
      PlyProperty p;
      p.list = w.size() == 5 && w[1] == "list";
      if (p.list ? !ply_type(w[2], p.count_type) || !ply_type(w[3], p.type) : w.size() != 3 || !ply_type(w[1], p.type))
        fail(fmt::format("bad property '{}'", line));
      p.name = std::string(w.back());
      elements.back().properties.push_back(p);
    } else if (w[0] == "end_header") {
      ended = true;
    } else {
      fail(fmt::format("unexpected header line '{}'", line));
    }
  }
  if (!ended) fail("file ends before 'end_header' (truncated)");
  if (!format) throw ReadError(name, "header", "no 'format' line");
  TriangleMesh mesh;
  PlyBody body{data, lines.pos, binary, lines.number + 1, name};
  bool have_vertices = false;
  std::vector<int> corners;
  for (const PlyElement& e : elements) {
    const bool vertex = e.name == "vertex", face = e.name == "face";
    int xyz[3] = {-1, -1, -1}, indices = -1;
    for (size_t k = 0; k < e.properties.size(); ++k) {
      const PlyProperty& p = e.properties[k];
      for (int c = 0; c < 3; ++c)
        if (vertex && !p.list && p.name == std::string(1, char('x' + c))) xyz[c] = int(k);
      if (face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) indices = int(k);
    }
    if (vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0))
      throw ReadError(name, "header", "element 'vertex' lacks one of the properties x, y, z");
    if (face && indices < 0) throw ReadError(name, "header", "element 'face' has no list 'vertex_indices'");
    if (face && !have_vertices) throw ReadError(name, "header", "element 'face' comes before 'vertex'");
    have_vertices |= vertex;
    body.element = &e;
    // The count is not trusted before the bytes behind it exist (an item without properties reads
    // nothing: its count would only spin).
    if (e.properties.empty()) continue;
    const size_t least = ply_least_item_bytes(e, binary), left = data.size() - std::min(body.pos, data.size());
    if (e.count > 0 && size_t(e.count) > left / least)
      throw ReadError(name, binary ? fmt::format("byte {}", body.pos) : fmt::format("line {}", body.line),
                      fmt::format("element '{}' has {} items of at least {} bytes, the file has {} bytes left (truncated)",
                                  e.name, e.count, least, left));
    const long long nv = (long long)mesh.positions.size();
    for (body.item = 0; body.item < e.count; ++body.item) {
      glm::dvec3 p(0.0);
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        if (!prop.list) {
          const double v = body.scalar(prop.type);
          for (int c = 0; c < 3; ++c)
            if (int(k) == xyz[c]) p[c] = v;
          continue;
        }
        const long long n = body.index(prop.count_type, 1LL << 31, "list length");
        if (int(k) != indices) {
          for (long long i = 0; i < n; ++i) (void)body.scalar(prop.type);
          continue;
        }
        if (n < 3) body.fail(fmt::format("has {} vertices, expected at least 3", n));
        corners.clear();
        for (long long i = 0; i < n; ++i) corners.push_back(int(body.index(prop.type, nv, "vertex index")));
        if (const std::string problem = add_fan(mesh, corners); !problem.empty()) body.fail(problem);
      }
      if (vertex && !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        body.fail("coordinate is not finite");
      if (const std::string problem = vertex ? check_vertex(p, limit) : ""; !problem.empty()) body.fail(problem);
      if (vertex) mesh.positions.push_back(p);
    }
  }
  return mesh;
}

TriangleMesh read_mesh_data(std::string_view data, MeshFormat format, const std::string& name, double limit) {
  switch (format) {
    case MeshFormat::Stl:
      return read_stl(data, name, limit);
    case MeshFormat::Obj:
      return read_obj(data, name, limit);
    case MeshFormat::Ply:
      return read_ply(data, name, limit);
  }
  throw ReadError(name, "", "unknown mesh format");
}

}  // namespace

TriangleMesh read_mesh(std::istream& in, MeshFormat format, const std::string& name, double coordinate_limit) {
  return read_mesh_data(read_input_stream(in, name), format, name, coordinate_limit);
}

TriangleMesh read_mesh_file(const std::filesystem::path& path, double coordinate_limit) {
  const std::string name = path.string();
  if (!std::filesystem::exists(path)) throw ReadError(name, "", "no such file");
  MeshFormat format;
  try {
    format = mesh_format_of(path);
  } catch (const std::invalid_argument&) {
    throw ReadError(name, "", "unknown mesh format '" + path.extension().string() + "' (use .obj, .ply or .stl)");
  }
  return read_mesh_data(read_input_file(path), format, name, coordinate_limit);
}

}  // namespace nurbs::io
