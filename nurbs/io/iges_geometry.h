#pragma once
/// \file iges_geometry.h
/// IGES entities to NURBS geometry: transformation matrices (124), curves (100, 102, 104, 110,
/// 126) and surfaces (128). Internal to the IGES reader, public for its tests.
#include <glm/mat4x4.hpp>
#include <initializer_list>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "nurbs/curve.h"
#include "nurbs/io/iges_file.h"
#include "nurbs/io/iges_params.h"
#include "nurbs/surface.h"

namespace nurbs::io {

/// Thrown (and caught per face by the reader) when a face needs an entity of a legal IGES type
/// that this reader does not convert, e.g. a 120 surface of revolution.
struct UnsupportedEntity {
  int de = 0;
  int type = 0;
};

/// Entity types that may stand for a curve / surface in IGES but are not converted here.
bool is_unsupported_curve_type(int type);
bool is_unsupported_surface_type(int type);

class IgesGeometry {
 public:
  explicit IgesGeometry(const IgesFile& file) : file_(file) {}

  /// The matrix of the entry's transformation field (124 chain, IGES 5.3 §4.21), identity if 0.
  /// Chained 124s compose outer * inner; cycles and wrong types throw ReadError.
  glm::dmat4 transform(int de);

  /// A curve entity as one or more 3D NURBS curves (composites flattened), each mapped by
  /// parent * (its own transform chain). Throws ReadError on malformed data, on composites nested
  /// deeper than 64 (a cycle), and beyond the reader's point budget (kMaxPointsBase in iges_reader.h).
  std::vector<Curve3> curves(int de, const glm::dmat4& parent, int depth = 0);

  /// A curve entity used in a surface's parameter space: (x, y) of curves(de, identity).
  std::vector<Curve2> parameter_curves(int de);

  /// A 128 surface mapped by parent * (its own transform chain); checked (knots, weights, counts).
  /// With `restrict_to_range`, cut to its declared range U(0)..U(1) x V(0)..V(1) when that lies inside
  /// the knot domain: right where the range is the face's boundary (a bare 128, a 144 with N1 = 0).
  /// Faces with an outer trim loop keep the whole surface, as OpenCASCADE does: real files (OCCT's
  /// hammer) have trim curves reaching up to 7e-4 of the domain beyond the declared range.
  Surface surface(int de, const glm::dmat4& parent, bool restrict_to_range = true);

  /// Pointer parameter `i` of `p` that must name an entity of one of `types` (`what` describes
  /// them in the message). Types in the unsupported lists throw UnsupportedEntity; 0 is returned
  /// only when `null_ok`.
  int expect(const EntityParams& p, int i, std::initializer_list<int> types, const char* what, bool null_ok = false);

  /// Throws ReadError at the directory line of `de`: "line L: entity Dn (type t): problem".
  [[noreturn]] void fail(int de, const std::string& problem) const;

  [[nodiscard]] const IgesFile& file() const { return file_; }

  /// The model-wide number of B-rep edge NDX of the 504 edge list `list_de` (Curve::edge): edges
  /// numbered from 0 in the order the loops first use them, so both faces of an edge get the same.
  int edge_id(int list_de, int ndx);

  /// True when `de` was handed out by expect(): some entity the reader converted uses it (a 116
  /// point or 123 direction of an analytic surface, say), so it is read even if its type is not.
  [[nodiscard]] bool referenced(int de) const { return referenced_.count(de) != 0; }

  /// How many 126/128 entities declared a parameter range inside their knot domain and were
  /// restricted to it (nurbs/restrict.h).
  [[nodiscard]] int ranges_restricted() const { return ranges_restricted_; }

  /// What was read differently from the letter of the file, each naming its line and entity
  /// (Model::read_warnings): a 128 whose declared parameter range is empty keeps its knot domain.
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  glm::dmat4 matrix_124(int de, int depth);
  Curve3 bspline_curve(const EntityParams& p);
  /// Throws ReadError at `de` once the control points created so far exceed the budget.
  void check_point_budget(int de) const;

  const IgesFile& file_;
  std::unordered_map<int, glm::dmat4> transforms_;
  int ranges_restricted_ = 0;
  std::vector<std::string> warnings_;
  long long points_made_ = 0;                    // control points of every curve and surface built so far
  std::vector<int> composites_;                  // the 102s being expanded, outermost first: cycle detection
  std::unordered_set<int> referenced_;           // entries returned by expect()
  std::unordered_map<long long, int> edge_ids_;  // (504 entry, NDX) -> edge_id
};

}  // namespace nurbs::io
