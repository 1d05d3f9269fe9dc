#pragma once
/// \file trimmed_surface.h
/// A face: a NURBS surface and trim loops of 2D NURBS curves in its (u, v) parameter plane.
/// Convention: outer loops counter-clockwise, inner loops (holes) clockwise, material on the left.
#include <string>
#include <vector>

#include "curve.h"
#include "surface.h"

namespace nurbs {

struct TrimLoop {
  std::vector<Curve2> curves;  ///< joined end to start, in order
  bool outer = true;
};

struct TrimmedSurface {
  Surface surface;
  /// No loops = the whole parameter rectangle is material (an untrimmed face).
  std::vector<TrimLoop> loops;
  int face_id = -1;  ///< index in the model, or the IGES directory entry number of the face
  std::string name;  ///< optional label from the file
  /// Which side is outside: the face's outward normal is Su x Sv, negated when `reversed` (IGES 5.3
  /// 514 shell face flag OF = 0, or its 186 solid's SOF / VOF = 0, not both). Trim loops do not
  /// depend on it: they follow the (u, v) convention above either way.
  bool reversed = false;
  /// Set by a reader whose repairs could not make the loops valid (a loop still open, or crossing
  /// itself or another): what is wrong, naming the loop. The face is kept as read, but no answer
  /// that may depend on it is certified (model_report.h).
  std::string trim_problem;
  /// Model units: how far the file's edges lie from the surface where the reader kept the face by
  /// its parameter curves or a projection of its edges (0 when they lie on it within the reader's
  /// tolerance). The face's boundary is known only this closely, so every bound that may depend
  /// on the face is widened by it (model_report.h).
  double edge_gap = 0.0;
};

}  // namespace nurbs
