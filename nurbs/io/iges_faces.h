#pragma once
/// \file iges_faces.h
/// IGES face entities to TrimmedSurface: 144 (trimmed surface, loops from 142), 143 (bounded
/// surface, loops from 141), 510 (B-rep face, loops from 508) and bare 128. Internal to the reader.
#include <string>
#include <unordered_map>
#include <utility>

#include "nurbs/io/iges_geometry.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/trimmed_surface.h"

namespace nurbs::io {

/// Thrown when a face is dropped (see IgesReadOptions); caught per face by the reader.
struct SkipFace {
  std::string reason;
};

class IgesFaces {
 public:
  IgesFaces(IgesGeometry& geometry, const IgesReadOptions& options, IgesReadLog& log)
      : g_(geometry), options_(options), log_(log) {}

  /// The face of entity `de` (type 144, 143, 510 or 128), model space = parent * own transforms,
  /// with its loops as the file gives them; finish() repairs, checks and orients them.
  TrimmedSurface face(int de, const glm::dmat4& parent);

  /// Trim loop hygiene once the whole model is read: gaps closed (in (u, v), then on the surface
  /// within kTrimGap3d x `model_size`, trim_surface_gaps.h), problems logged, loops oriented, a domain
  /// outer loop added to faces with holes only.
  void finish(TrimmedSurface& f, double model_size);

  /// The surface pointer of a face entity (0 for 128 itself); marks what is not a face of its own.
  int surface_pointer(int de);

 private:
  TrimmedSurface face_144(const EntityParams& p, const glm::dmat4& m);
  TrimmedSurface face_143(const EntityParams& p, const glm::dmat4& m);
  TrimmedSurface face_510(const EntityParams& p, const glm::dmat4& m);
  std::pair<int, int> curve_142(int de);
  Curve2 projected(const Surface& s, const Curve3& c, int de);
  TrimLoop loop_141(int de, bool outer, const Surface& surface, const glm::dmat4& m);
  /// `surface`: the face's surface, onto which edges given only in model space are projected (null:
  /// not built yet, such edges refused).
  TrimLoop loop_508(int de, bool outer, const Surface* surface, const glm::dmat4& m);
  int edge_list_size(int de);
  [[noreturn]] void no_parameter_curve(int de, const std::string& what);

  IgesGeometry& g_;
  const IgesReadOptions& options_;
  IgesReadLog& log_;
  std::unordered_map<int, int> list_sizes_;  // 502/504 entry counts, parsed once
  double edge_gap_ = 0.0;                    // of the face being read: largest projection distance kept
};

/// IgesFaces::finish for faces of any reader: the same repairs, checks and orientation, counted in `log`.
void finish_trim_loops(TrimmedSurface& f, double model_size, IgesReadLog& log);

}  // namespace nurbs::io
