#pragma once
/// \file iges_faces.h
/// IGES face entities to TrimmedSurface: 144 (trimmed surface, loops from 142), 143 (bounded
/// surface, loops from 141), 510 (B-rep face, loops from 508) and bare 128. Internal to the reader.
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

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
  TrimmedSurface face_144_on_plane(const EntityParams& p, const glm::dmat4& m, int pts,
                                   const std::vector<int>& loops, int n1);
  TrimmedSurface face_143(const EntityParams& p, const glm::dmat4& m);
  TrimmedSurface face_510(const EntityParams& p, const glm::dmat4& m);
  std::pair<int, int> curve_142(int de);
  void add_model_curve(const TrimmedSurface& f, int de);
  Curve2 projected(const Surface& s, const Curve3& c, int de);
  TrimLoop loop_141(int de, bool outer, const Surface& surface, const glm::dmat4& m);
  /// `surface`: the face's surface, onto which edges given only in model space are projected (null:
  /// not built yet, such edges refused). `index`: the loop's place in its face (EdgeUse::loop).
  TrimLoop loop_508(int de, bool outer, const Surface* surface, const glm::dmat4& m, size_t index);
  /// The parameters of entity `de` (a 502/504 list, a 142), parsed once.
  const EntityParams& parsed(int de);
  int edge_list_size(int de);
  void measure_edge_gaps(const TrimmedSurface& f, const glm::dmat4& m);
  [[noreturn]] void no_parameter_curve(int de, const std::string& what);

  IgesGeometry& g_;
  const IgesReadOptions& options_;
  IgesReadLog& log_;
  /// Curves of a loop of the face being read that the file gives in both spaces: the parameter
  /// curves f.loops[loop].curves[first, first + count) and the model-space curve that parameter
  /// `parameter` of entity `entity` names (504 CURV, 142 CPTR), read only to measure the gap.
  struct EdgeUse {
    size_t loop = 0, first = 0, count = 0;
    int entity = 0, parameter = 0;
  };

  std::unordered_map<int, EntityParams> parsed_;  // see parsed(); built in place, never moved
  std::vector<EdgeUse> edge_uses_;                // of the face being read
  double edge_gap_ = 0.0;  // of the face being read: largest distance of its file edges from its trims
};

/// IgesFaces::finish for faces of any reader: the same repairs, checks and orientation, counted in `log`.
/// A face whose trim curves are not all valid B-splines is left as it is, its problem said.
void finish_trim_loops(TrimmedSurface& f, double model_size, IgesReadLog& log);

/// Whether every trim curve of `f` is a valid B-spline (nurbs::validate): one that is not cannot be
/// evaluated, so the readers drop its face, with the problem as the reason.
[[nodiscard]] bool trims_evaluable(const TrimmedSurface& f);

}  // namespace nurbs::io
