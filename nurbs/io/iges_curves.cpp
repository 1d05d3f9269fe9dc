#include <fmt/format.h>

#include <algorithm>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <stdexcept>

#include "nurbs/io/conic_arcs.h"
#include "nurbs/io/curve_utils.h"
#include "nurbs/io/iges_geometry.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/read_error.h"
#include "nurbs/validate.h"

namespace nurbs::io {
namespace {

// Composite curves and 124 chains nest; deeper than this is a pointer cycle in practice.
constexpr int kMaxDepth = 64;

// Keeps `de` on the stack of composites being expanded while in scope (also when a face is
// dropped by an exception that the reader catches): the budget message names the outermost.
struct ExpansionGuard {
  ExpansionGuard(std::vector<int>& stack, int de) : stack_(stack) { stack_.push_back(de); }
  ~ExpansionGuard() { stack_.pop_back(); }
  ExpansionGuard(const ExpansionGuard&) = delete;
  ExpansionGuard& operator=(const ExpansionGuard&) = delete;
  std::vector<int>& stack_;
};

std::string type_list(std::initializer_list<int> types) {
  std::string s;
  for (int t : types) s += (s.empty() ? "" : "/") + std::to_string(t);
  return s;
}

}  // namespace

bool is_unsupported_curve_type(int type) { return type == 106 || type == 112 || type == 116 || type == 130; }

bool is_unsupported_surface_type(int type) {
  switch (type) {
    case 108:
    case 114:
    case 118:
    case 120:
    case 122:
    case 140:
    case 190:
    case 192:
    case 194:
    case 196:
    case 198:
      return true;
    default:
      return false;
  }
}

void IgesGeometry::check_point_budget(int de) const {
  const long long budget = kMaxPointsBase + static_cast<long long>(file_.text->size());
  if (points_made_ > budget)
    fail(de, fmt::format("reading it, the curves and surfaces read so far exceed {} control points, the budget of "
                         "{} + one per byte of the file (entities listed over and over?)",
                         budget, kMaxPointsBase));
}

void IgesGeometry::fail(int de, const std::string& problem) const {
  const IgesDirectoryEntry& e = file_.entry(de);
  throw ReadError(file_.name, fmt::format("line {}", e.line), entity_name(e) + ": " + problem);
}

int IgesGeometry::edge_id(int list_de, int ndx) {
  const auto [it, added] = edge_ids_.try_emplace((static_cast<long long>(list_de) << 32) | static_cast<unsigned>(ndx),
                                                 static_cast<int>(edge_ids_.size()));
  return it->second;
}

int IgesGeometry::expect(const EntityParams& p, int i, std::initializer_list<int> types, const char* what,
                         bool null_ok) {
  const int de = p.pointer(i, null_ok);
  if (de == 0) return 0;
  const int type = file_.entry(de).type;
  if (std::find(types.begin(), types.end(), type) != types.end()) {
    referenced_.insert(de);
    return de;
  }
  const bool wants_curve = std::find(types.begin(), types.end(), 126) != types.end();
  const bool wants_surface = std::find(types.begin(), types.end(), 128) != types.end();
  if ((wants_curve && is_unsupported_curve_type(type)) || (wants_surface && is_unsupported_surface_type(type)))
    throw UnsupportedEntity{de, type};
  p.fail(i, fmt::format("pointer D{} is an entity of type {}, expected {} ({})", de, type, what, type_list(types)));
}

glm::dmat4 IgesGeometry::transform(int de) {
  const IgesDirectoryEntry& e = file_.entry(de);
  if (e.transform == 0) return glm::dmat4(1.0);
  if (!file_.has_entry(e.transform))
    fail(de, fmt::format("transformation matrix pointer {} does not name a directory entry", e.transform));
  if (file_.entry(e.transform).type != 124)
    fail(de, fmt::format("transformation matrix pointer D{} is an entity of type {}, expected 124", e.transform,
                         file_.entry(e.transform).type));
  return matrix_124(e.transform, 0);
}

glm::dmat4 IgesGeometry::matrix_124(int de, int depth) {
  if (auto it = transforms_.find(de); it != transforms_.end()) return it->second;
  if (depth > kMaxDepth) fail(de, fmt::format("more than {} chained transformation matrices (cycle?)", kMaxDepth));
  EntityParams p(file_, file_.entry(de));
  p.require(12);
  glm::dmat4 m(1.0);  // IGES: x' = R x + T with R row-major in parameters 1-3, 5-7, 9-11
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) m[col][row] = p.real(row * 4 + col + 1);
    m[3][row] = p.real(row * 4 + 4);
  }
  p.check_trailing(12);
  if (std::abs(glm::determinant(glm::dmat3(m))) < 1e-12)  // 1e-12: rigid matrices have |det| = 1
    p.fail(0, "singular transformation matrix");
  const IgesDirectoryEntry& e = file_.entry(de);
  if (e.transform != 0) {
    if (!file_.has_entry(e.transform) || file_.entry(e.transform).type != 124)
      fail(de, fmt::format("transformation matrix pointer {} is not a 124 entity", e.transform));
    m = matrix_124(e.transform, depth + 1) * m;
  }
  transforms_[de] = m;
  return m;
}

std::vector<Curve3> IgesGeometry::curves(int de, const glm::dmat4& parent, int depth) {
  if (depth > kMaxDepth) fail(de, fmt::format("curves nested more than {} deep (pointer cycle?)", kMaxDepth));
  const IgesDirectoryEntry& e = file_.entry(de);
  const glm::dmat4 m = parent * transform(de);
  EntityParams p(file_, e);
  std::vector<Curve3> out;
  switch (e.type) {
    case 102: {  // composite curve: N, then N pointers to its pieces in order
      const int n = p.integer(1, 1, std::max(1, p.size() - 1), "number of curves N");
      const ExpansionGuard guard(composites_, de);
      for (int k = 0; k < n; ++k) {
        const int child = expect(p, 2 + k, {100, 102, 104, 110, 126}, "a curve");
        for (Curve3& c : curves(child, m, depth + 1)) out.push_back(std::move(c));
      }
      p.check_trailing(1 + n);
      return out;
    }
    case 110: {  // line: start and end point
      const glm::dvec3 a(p.real(1), p.real(2), p.real(3)), b(p.real(4), p.real(5), p.real(6));
      p.check_trailing(6);
      if (a == b) p.fail(0, "line has zero length");
      out.push_back(line_segment(a, b));
      break;
    }
    case 100:    // circular arc: ZT, centre, start, end (counter-clockwise)
    case 104: {  // conic arc: A..F, ZT, start, end
      const bool circle = e.type == 100;
      const int base = circle ? 1 : 7;
      std::array<double, 6> coef{};
      if (!circle)
        for (int k = 0; k < 6; ++k) coef[static_cast<size_t>(k)] = p.real(k + 1);
      const double z = p.real(base);
      const glm::dvec2 a(p.real(base + 1), p.real(base + 2)), b(p.real(base + 3), p.real(base + 4));
      try {
        if (circle) {
          const glm::dvec2 c(p.real(base + 5), p.real(base + 6));
          p.check_trailing(7);
          out.push_back(circle_arc(a, b, c, z));
        } else {
          p.check_trailing(11);
          out.push_back(conic_arc(coef, a, b, z, e.form));
        }
      } catch (const std::invalid_argument& ex) {
        p.fail(0, ex.what());
      }
      break;
    }
    case 126:
      out.push_back(bspline_curve(p));
      break;
    default:
      fail(de, "is not a curve");
  }
  transform_points(out.back(), m);
  if (const std::vector<std::string> problems = validate_magnitude(out.back(), kMaxCoordinate); !problems.empty())
    p.fail(0, "out of range: " + problems.front());
  points_made_ += static_cast<long long>(out.back().points.size());
  check_point_budget(composites_.empty() ? de : composites_.front());  // names the outermost composite
  return out;
}

std::vector<Curve2> IgesGeometry::parameter_curves(int de) {
  std::vector<Curve2> out;
  for (const Curve3& c : curves(de, glm::dmat4(1.0))) out.push_back(to_2d(c));
  return out;
}

}  // namespace nurbs::io
