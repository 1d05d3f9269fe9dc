#pragma once
/// \file step_reader.h
/// Native STEP (ISO 10303-21 files of AP203, AP214 and AP242) reader for the B-rep geometry
/// subset, giving the same nurbs::Model as the IGES reader.
///
/// Read (ISO 10303-42 geometry and topology):
/// - bodies: MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS and SHELL_BASED_SURFACE_MODEL, each of CLOSED_SHELL
///   / OPEN_SHELL (ORIENTED_CLOSED_SHELL / ORIENTED_OPEN_SHELL turn their faces round) of
///   ADVANCED_FACE or FACE_SURFACE, also as ORIENTED_FACE. Instances are read by the positions of
///   their attributes in ISO 10303-42, the derived ones (written *) included;
/// - surfaces: B_SPLINE_SURFACE_WITH_KNOTS (also the RATIONAL_B_SPLINE_SURFACE complex instance),
///   PLANE, CYLINDRICAL_, CONICAL_, SPHERICAL_ and TOROIDAL_SURFACE, SURFACE_OF_REVOLUTION and
///   SURFACE_OF_LINEAR_EXTRUSION, all as exact (rational) NURBS (analytic_nurbs.h);
/// - edges: EDGE_LOOP of ORIENTED_EDGE of EDGE_CURVE between VERTEX_POINTs on LINE, CIRCLE,
///   ELLIPSE, POLYLINE, B_SPLINE_CURVE_WITH_KNOTS (rational too), TRIMMED_CURVE and the 3D curve of
///   SURFACE_CURVE / SEAM_CURVE / INTERSECTION_CURVE (SEAM_EDGE as ORIENTED_EDGE); VERTEX_LOOP adds
///   nothing;
/// - units: SI_UNIT with prefixes and CONVERSION_BASED_UNIT (inch, degree...) for lengths and plane
///   angles; the uncertainty of GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT as Model::resolution;
/// - assemblies: REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION with ITEM_DEFINED_TRANSFORMATION
///   (which side is the component is read from the NEXT_ASSEMBLY_USAGE_OCCURRENCE of its
///   CONTEXT_DEPENDENT_SHAPE_REPRESENTATION), nested to any depth: one body per placed instance of
///   a solid, its placement applied to the geometry, named "PRODUCT" or "PRODUCT #k" by the product.
///
/// Trims: edges are given in model space; each is brought into its face's (u, v) plane. On planes
/// the map is affine (exact, the curve's control points are mapped); on the other analytic
/// surfaces the surface's own parameters of the edge's points are computed in closed form
/// (angles unwrapped along the loop, so loops over a seam stay continuous) and the edge is
/// flattened there within kStepTrimTolerance of the face's size; on B-spline surfaces edges are
/// projected (project_curve.h), or their PCURVEs taken where given. Loops then go through the IGES
/// reader's repairs and checks (finish_trim_loops). ADVANCED_FACE same_sense = .F. sets
/// TrimmedSurface::reversed.
///
/// Edges off their surface: a face whose edges lie farther from its surface than 1e-4 of its size
/// (and 10 times the file's uncertainty) keeps its PCURVEs where given, else the edges' projection,
/// and TrimmedSurface::edge_gap says how far (model units; measured at 33 samples of every edge and
/// those the trim takes). Beyond kStepMaxEdgeGap of its size the face is dropped with the reason.
///
/// Damaged records (step_file.h: a reference out of range, a malformed number) fail the read only
/// when the reader uses them; the others are named in Model::read_warnings. Model::skipped_types
/// counts geometry and topology that no body holds (faces dropped for a reason are in
/// Model::dropped_faces instead); the PCURVEs of read edges, units and styling are not counted.
///
/// Edges are numbered model-wide (Curve2::edge), the same edge on both of its faces, separately
/// per placed instance, so `--watertight` welds as on the IGES B-rep path. Face ids are the STEP
/// instance numbers of the faces.
#include <filesystem>
#include <string>

#include "nurbs/io/iges_reader.h"
#include "nurbs/model.h"

namespace nurbs::io {

/// Edges are flattened into their face's parameter plane within this fraction of the face's size
/// (the diagonal of its edges' box).
inline constexpr double kStepTrimTolerance = 1e-7;

/// A face whose edges lie farther than this fraction of its size from its surface (or from the
/// surface points of its trims) does not bound a region of that surface: it is dropped. Nearer, it
/// is kept with its edge gap, which widens the bounds near it: a lost face would leave every answer
/// on the model uncertified (KiCad's 0603 package: 8 faces 0.0025 off at size 0.026, 10 %).
inline constexpr double kStepMaxEdgeGap = 0.15;

/// Reads a STEP file. Throws ReadError ("FILE: line L: #ID (TYPE): problem") on malformed data,
/// references to missing or wrong instances, reference cycles, and input beyond the IGES reader's
/// limits (kMaxDegree, kMaxCoordinate). Faces on unsupported geometry are dropped with a warning in
/// the log naming the entity; unread geometric entities are counted in Model::skipped_types.
Model read_step(const std::filesystem::path& path, IgesReadLog* log = nullptr);

/// Same on text in memory; `name` is used in messages and Model::source.
Model read_step_text(const std::string& text, const std::string& name, IgesReadLog* log = nullptr);

}  // namespace nurbs::io
