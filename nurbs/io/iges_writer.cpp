#include "nurbs/io/iges_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "nurbs/io/output_file.h"

namespace nurbs::io {
namespace {

// Shortest round-trip text of a double, with a '.' or exponent as IGES reals need.
std::string real(double v) {
  std::string s = fmt::format("{}", v);
  for (char& c : s)
    if (c == 'e') c = 'E';
  if (s.find_first_of(".E") == std::string::npos) s += '.';
  return s;
}

std::string hollerith(const std::string& s) { return fmt::format("{}H{}", s.size(), s); }

struct Entity {
  int type = 0;
  int status = 0;  // 8 digits: blank, subordinate, use, hierarchy
  std::vector<std::string> params;
};

class Writer {
 public:
  int add(int type, int status) {
    entities_.push_back({type, status, {std::to_string(type)}});
    return de(entities_.size() - 1);
  }
  std::vector<std::string>& params(int de) { return entities_[static_cast<size_t>(de - 1) / 2].params; }
  static int de(size_t index) { return static_cast<int>(2 * index + 1); }

  int surface(const Surface& s, const glm::dmat4& m, int status);
  int curve(const Curve2& c);
  int loop(const TrimLoop& loop, int surface_de);
  void face(const TrimmedSurface& f, const glm::dmat4& m);
  void write(std::ostream& out, const std::string& file_name, double unit_mm) const;

 private:
  std::vector<Entity> entities_;
  double max_coord_ = 0.0;  // G20: largest absolute coordinate
};

void check_sizes(size_t points, size_t knots, int degree, size_t weights, const char* what) {
  if (degree < 1 || points < static_cast<size_t>(degree) + 1 || knots != points + static_cast<size_t>(degree) + 1 ||
      (weights != 0 && weights != points))
    throw std::invalid_argument(fmt::format("write_iges: {} has inconsistent degree/knot/point/weight counts", what));
}

int Writer::surface(const Surface& s, const glm::dmat4& m, int status) {
  check_sizes(static_cast<size_t>(s.count_u), s.knots_u.size(), s.degree_u, 0, "surface (u)");
  check_sizes(static_cast<size_t>(s.count_v), s.knots_v.size(), s.degree_v, 0, "surface (v)");
  const size_t n = static_cast<size_t>(s.count_u) * static_cast<size_t>(s.count_v);
  if (s.points.size() != n || (s.rational() && s.weights.size() != n))
    throw std::invalid_argument("write_iges: surface points/weights do not match count_u * count_v");
  const int d = add(128, status);
  auto& p = params(d);
  for (int v : {s.count_u - 1, s.count_v - 1, s.degree_u, s.degree_v, 0, 0, s.rational() ? 0 : 1, 0, 0})
    p.push_back(std::to_string(v));
  for (double k : s.knots_u) p.push_back(real(k));
  for (double k : s.knots_v) p.push_back(real(k));
  for (size_t i = 0; i < n; ++i) p.push_back(real(s.rational() ? s.weights[i] : 1.0));
  for (const glm::dvec3& q : s.points) {
    const glm::dvec3 t(m * glm::dvec4(q, 1.0));
    for (int c = 0; c < 3; ++c) {
      p.push_back(real(t[c]));
      max_coord_ = std::max(max_coord_, std::abs(t[c]));
    }
  }
  for (double v : {s.knots_u[static_cast<size_t>(s.degree_u)], s.knots_u[static_cast<size_t>(s.count_u)],
                   s.knots_v[static_cast<size_t>(s.degree_v)], s.knots_v[static_cast<size_t>(s.count_v)]})
    p.push_back(real(v));
  return d;
}

int Writer::curve(const Curve2& c) {
  check_sizes(c.points.size(), c.knots.size(), c.degree, c.weights.size(), "trim curve");
  const int d = add(126, 10500);  // physically dependent, used in 2D parameter space
  auto& p = params(d);
  for (int v : {static_cast<int>(c.points.size()) - 1, c.degree, 1, 0, c.rational() ? 0 : 1, 0})
    p.push_back(std::to_string(v));
  for (double k : c.knots) p.push_back(real(k));
  for (size_t i = 0; i < c.points.size(); ++i) p.push_back(real(c.rational() ? c.weights[i] : 1.0));
  for (const glm::dvec2& q : c.points) {
    p.push_back(real(q.x));
    p.push_back(real(q.y));
    p.push_back(real(0.0));
  }
  p.push_back(real(c.knots[static_cast<size_t>(c.degree)]));
  p.push_back(real(c.knots[c.points.size()]));
  for (double v : {0.0, 0.0, 1.0}) p.push_back(real(v));  // planar in z = 0
  return d;
}

int Writer::loop(const TrimLoop& loop, int surface_de) {
  std::vector<int> curves;
  for (const Curve2& c : loop.curves) curves.push_back(curve(c));
  const int composite = add(102, 10500);
  params(composite).push_back(std::to_string(curves.size()));
  for (int c : curves) params(composite).push_back(std::to_string(c));
  const int on_surface = add(142, 10500);
  for (int v : {0, surface_de, composite, 0, 1}) params(on_surface).push_back(std::to_string(v));
  return on_surface;
}

void Writer::face(const TrimmedSurface& f, const glm::dmat4& m) {
  if (f.loops.empty()) {
    surface(f.surface, m, 0);
    return;
  }
  const auto outer_count = std::count_if(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; });
  if (outer_count > 1)
    throw std::invalid_argument(
        fmt::format("write_iges: face {} has {} outer loops, a 144 holds one", f.face_id, outer_count));
  const int trimmed = add(144, 0);
  const int s = surface(f.surface, m, 10000);
  int outer = 0;
  std::vector<int> holes;
  for (const TrimLoop& l : f.loops) {
    const int d = loop(l, s);
    if (l.outer)
      outer = d;
    else
      holes.push_back(d);
  }
  auto& p = params(trimmed);
  for (int v : {s, outer != 0 ? 1 : 0, static_cast<int>(holes.size()), outer}) p.push_back(std::to_string(v));
  for (int h : holes) p.push_back(std::to_string(h));
}

struct UnitCode {
  double mm;
  int flag;
  const char* name;
};
constexpr UnitCode kUnitCodes[] = {{1.0, 2, "MM"},   {25.4, 1, "IN"},   {10.0, 10, "CM"},  {1000.0, 6, "M"},
                                   {304.8, 4, "FT"}, {1.0e-3, 9, "UM"}, {0.0254, 8, "MIL"}};

// Lines of `width` data columns from fields joined by ',' and ended by ';'. A field is not split
// unless it is longer than a line (only Hollerith strings can be).
std::vector<std::string> pack(const std::vector<std::string>& fields, size_t width) {
  std::vector<std::string> lines(1);
  for (size_t i = 0; i < fields.size(); ++i) {
    std::string f = fields[i] + (i + 1 == fields.size() ? ';' : ',');
    if (lines.back().size() + f.size() > width && !lines.back().empty()) lines.emplace_back();
    while (lines.back().size() + f.size() > width) {
      const size_t room = width - lines.back().size();
      lines.back() += f.substr(0, room);
      f.erase(0, room);
      lines.emplace_back();
    }
    lines.back() += f;
  }
  return lines;
}

void record(std::ostream& out, const std::string& data, char section, int seq) {
  out << fmt::format("{:<72}{}{:7}\n", data, section, seq);
}

void Writer::write(std::ostream& out, const std::string& file_name, double unit_mm) const {
  const UnitCode* unit = nullptr;
  for (const UnitCode& u : kUnitCodes)
    if (u.mm == unit_mm) unit = &u;
  if (!unit) throw std::invalid_argument(fmt::format("write_iges: no IGES unit for unit_scale_to_mm = {}", unit_mm));
  record(out, "nurbsgl IGES writer", 'S', 1);
  // Fixed dates keep the output byte-for-byte reproducible for generated models.
  const std::string date = hollerith("20000101.000000");
  const std::vector<std::string> global = {hollerith(","),
                                           hollerith(";"),
                                           hollerith("nurbsgl"),
                                           hollerith(file_name),
                                           hollerith("nurbsgl"),
                                           hollerith("0.1"),
                                           "32",
                                           "308",
                                           "15",
                                           "308",
                                           "15",
                                           hollerith(file_name),
                                           "1.",
                                           std::to_string(unit->flag),
                                           hollerith(unit->name),
                                           "1",
                                           "0.01",
                                           date,
                                           "1E-07",
                                           real(max_coord_),
                                           hollerith("nurbsgl"),
                                           "",
                                           "11",
                                           "0",
                                           date};
  int g = 0;
  for (const std::string& line : pack(global, 72)) record(out, line, 'G', ++g);
  // Directory: parameter line numbers first, since the DE lines point at them.
  std::vector<std::vector<std::string>> plines;
  for (const Entity& e : entities_) plines.push_back(pack(e.params, 64));
  int d = 0, p = 1;
  for (size_t i = 0; i < entities_.size(); ++i) {
    const Entity& e = entities_[i];
    record(out, fmt::format("{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:08}", e.type, p, 0, 0, 0, 0, 0, 0, e.status), 'D', ++d);
    record(out, fmt::format("{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}", e.type, 0, 0, plines[i].size(), 0, "", "", "", 0),
           'D', ++d);
    p += static_cast<int>(plines[i].size());
  }
  p = 0;
  for (size_t i = 0; i < entities_.size(); ++i)
    for (const std::string& line : plines[i]) record(out, fmt::format("{:<64} {:7}", line, de(i)), 'P', ++p);
  record(out, fmt::format("S{:7}G{:7}D{:7}P{:7}", 1, g, d, p), 'T', 1);
}

}  // namespace

void write_iges(std::ostream& out, const Model& model, const std::string& file_name) {
  Writer w;
  for (const Body& b : model.bodies)
    for (const TrimmedSurface& f : b.faces) w.face(f, b.transform);
  w.write(out, file_name, model.unit_scale_to_mm);
}

std::string write_iges_text(const Model& model, const std::string& file_name) {
  std::ostringstream out;
  write_iges(out, model, file_name);
  return std::move(out).str();
}

void write_iges_file(const std::filesystem::path& path, const Model& model) {
  write_file(path, [&](std::ostream& out) { write_iges(out, model, path.filename().string()); });
}

}  // namespace nurbs::io
