#pragma once
/// \file iges_reader.h
/// Native IGES 5.3 reader: trimmed NURBS faces of a file as a nurbs::Model.
///
/// Read: 128 surfaces, and 120, 122, 190-198 as exact rational NURBS under 144 and 510 faces
/// (iges_analytic.h); faces from 144 (trimmed surface), 143 (bounded surface), 510 (B-rep face,
/// grouped by 514 shells and 186 solids into bodies) and independent 128s; trim loops from 142,
/// 141 and 508 as parameter-space curves of types 100, 102, 104, 110 and 126, all as Curve2 in the
/// surface's (u, v) plane. 124 transforms are applied to model-space geometry (chained, parents
/// first). 314, 402, 406 and 0 are ignored; every other type is counted in
/// Model::skipped_entities. Geometry stays in file units; Model::unit_scale_to_mm says what a
/// unit is (G14/G15) unless options.convert_to_mm.
///
/// Trim curves given only in model space (142 with BPTR = 0, 141 and 508 curves with K = 0) are
/// projected onto the surface (project_curve.h). 514 face and 186 shell orientation flags set
/// TrimmedSurface::reversed. Loops are finished once the whole model is read: small (u, v) gaps
/// closed, loops going round a closed surface's seam closed along it (trim_seams.h), gaps that are
/// one point on the surface within kTrimGap3d x model size closed (trim_surface_gaps.h), then
/// checked (IgesReadLog::trim_problems) and oriented.
///
/// Loops: outer counter-clockwise, holes clockwise (reversed where the file differs). A face
/// whose outer boundary is the domain boundary (144 N1 = 0, 510 with no outer loop) gets no loop
/// when it has no holes (= untrimmed) and a 4-line domain-rectangle outer loop when it has holes,
/// so that winding-number classification works on every face.
#include <filesystem>
#include <string>
#include <vector>

#include "nurbs/io/iges_file.h"
#include "nurbs/model.h"

namespace nurbs::io {

struct IgesReadOptions {
  /// Scale all geometry to millimetres and set Model::unit_scale_to_mm = 1.
  bool convert_to_mm = false;
  /// Drop faces whose trim curves cannot be used (142 with neither curve, 141 or 508 curves only in
  /// model space over an analytic surface, model-space curves farther than kEdgeGapLimit from the
  /// surface), each in Model::dropped_faces with the reason (a model that lost faces answers
  /// nothing certified unless the caller accepts it: model_report.h), as OpenCASCADE reads the
  /// rest of such files; false throws ReadError naming the entity instead.
  /// Faces needing an unsupported surface/curve type are always dropped with a warning.
  bool skip_faces_without_parameter_curves = true;
};

/// What the reader did besides the model: for `nurbsgl info` and tests.
struct IgesReadLog {
  IgesGlobal global;
  int reoriented_loops = 0;    ///< loops reversed to get outer CCW / inner CW
  int outer_loops_fixed = 0;   ///< faces whose declared outer loop lay inside another loop (fix_outer_loop)
  int loops_wrapped = 0;  ///< faces whose loops were brought into a closed surface's domain (trim_seams.h)
  int reordered_loops = 0;     ///< loops whose curves were chained again (out of order or reversed)
  int domain_loops_added = 0;  ///< rectangle outer loops added to faces with holes only
  int gaps_closed = 0;         ///< trim-curve gaps closed (see kTrimGapRepair)
  int ranges_restricted = 0;   ///< 126/128 cut to a declared parameter range inside their domain
  int curves_projected = 0;    ///< trim curves given only in model space, projected (project_curve.h)
  /// Loops that still do not close, or cross (check_trim_loops), each "face N: ...".
  std::vector<std::string> trim_problems;
  std::vector<std::string> warnings;  ///< one per dropped face, naming it and the reason
};

/// Gaps between consecutive trim curves up to this fraction of the face's trim extent are closed
/// (as CAD readers do, counted in IgesReadLog::gaps_closed); larger ones are reported. Gaps up to
/// kTrimGapRounding of the extent are rounding of joined end points: left as they are, not counted.
inline constexpr double kTrimGapRepair = 1e-4;
inline constexpr double kTrimGapRounding = 1e-12;

/// Trim curves given only in model space (142 with BPTR = 0) are projected onto the surface within
/// this fraction of the surface's control-point box diagonal: every sample of the curve that far
/// from the surface at most, every chord in (u, v) that close to the curve. A curve farther off
/// (the file's edges and surface disagree, as in real files) is projected within twice its
/// distance, and the face keeps it with TrimmedSurface::edge_gap = the largest distance measured
/// between the file's curve and the surface points of the trim, up to kEdgeGapLimit; beyond that
/// the face is dropped (or the file refused, see IgesReadOptions).
inline constexpr double kProjectionTolerance = 1e-6;
/// Largest edge gap a face is kept with, as a fraction of its surface's control-point box diagonal:
/// farther, the model-space curve is not an edge of this surface (a wrong pointer, a damaged file).
inline constexpr double kEdgeGapLimit = 0.05;

/// Limits that keep reading, and the queries after it, bounded whatever a file holds (damaged or
/// hostile input); beyond each the reader throws ReadError naming the entity.
/// Degree of a 126 curve or 128 surface: evaluation costs grow as degree^2 per point, and CAD data
/// stays far below (OpenCASCADE's own limit is 25).
inline constexpr int kMaxDegree = 32;
/// Largest magnitude of a coordinate or knot, after 124 transforms; weights must lie in
/// [1 / kMaxCoordinate, kMaxCoordinate]. Squared distances, box diagonals and the Filip bound's
/// products of such numbers then stay far from double overflow (about 1.8e308).
inline constexpr double kMaxCoordinate = 1e100;
/// Control points the reader may create in all, counted over every curve and surface it builds:
/// kMaxPointsBase plus one per byte of the file. Entities listed many times (a composite curve
/// naming a sub-curve twice, chained: 2^depth curves) would otherwise expand without bound; a file
/// that names each entity once creates well under one point per byte.
inline constexpr long long kMaxPointsBase = 1'000'000;

/// Reads an IGES file. Throws ReadError ("FILE: line L: entity Dn (type t): problem") on any
/// malformed record or geometry, on a face listing the same loop twice, on input beyond the limits
/// above, and when the file cannot be opened.
Model read_iges(const std::filesystem::path& path, const IgesReadOptions& options = {}, IgesReadLog* log = nullptr);

/// Same as read_iges on text already in memory; `name` is used in messages and Model::source.
Model read_iges_text(std::string text, const std::string& name, const IgesReadOptions& options = {},
                     IgesReadLog* log = nullptr);

}  // namespace nurbs::io
