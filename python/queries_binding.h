#pragma once
/// \file queries_binding.h
/// The Python module's queries, each on its front door (queries/distance/point_query.h,
/// clearance_pair.h, nurbs/tessellation/model_mesh.h, queries/raycast/raycast_query.h,
/// thickness_map.h): the arguments as nurbsgl/__init__.py passes them, the answers as a dict of
/// arrays and figures.
#include <pybind11/pybind11.h>

#include <string>

#include "python/model_binding.h"

namespace nurbsgl_python {

namespace py = pybind11;

/// Distance from each point of an (N, 3) array: distance, bound, point_bound, point, face, uv,
/// meets_tolerance and reason per point (with `signed_distance`, also signed_distance, negative
/// inside); tolerance (model units), engine, batched, seconds, prepare_seconds, failure.
py::dict point_distance(ModelBinding& m, const py::handle& points, double tol, const std::string& engine,
                        bool per_point, bool accept_partial, bool cache, bool signed_distance, bool strict);

/// The model's mesh: vertices (V, 3), triangles (T, 3), triangle_face (T), normals, eps, bound,
/// failure (empty when certified within bound).
/// queries::inspect of an (N, 3) scan; the verdicts as an (N, bands) int8 array (queries::Verdict:
/// 0 within, 1 outside, 2 undecided, 3 outlier, 4 not found).
py::dict inspect(ModelBinding& m, const py::handle& scan, const std::vector<double>& within, double max_distance,
                 double tol, const py::handle& transform, bool align, const std::vector<int>& align_faces,
                 size_t align_sample, const std::string& engine, bool accept_partial);
py::dict tessellate(ModelBinding& m, double eps, bool relative, bool watertight, bool guaranteed, bool check,
                    bool accept_partial);

/// Nearest hits of rays (unit directions made so; queries/raycast/raycast_query.h): hit, t, point,
/// face, uv per ray; method, mesh_triangles, hit_residual, seconds, failure.
py::dict raycast(ModelBinding& m, const py::handle& origins, const py::handle& directions, double t_min,
                 const std::string& engine, double tol, double mesh_tol, bool accept_partial);

/// The thickness map: per ray its origin, direction, face and thickness (-1: no hit); min, median,
/// mean, max; the rolling ball's per ray when asked; failure.
py::dict thickness(ModelBinding& m, long long samples, const std::string& engine, bool ball, double min_wall,
                   bool accept_partial);

/// The clearance of B (a second model, or None: A's file) at each placement of `motions` (a list
/// of 4 x 4 arrays; empty: where it is): a list of dicts as `nurbsgl clearance --json` has them.
py::list clearance(ModelBinding& a, ModelBinding* b, const py::list& motions, const std::string& body_a,
                   const std::string& body_b, double tol, const std::string& engine, bool voxel_stage,
                   bool accept_partial);

/// The clash report of the model's bodies (queries::clash_report): rows (one dict per pair, in the
/// report's order) and the counts; `pairs` (a list of (i, j)) a shard of the pairs, empty: all.
py::dict clash(ModelBinding& m, double min_clearance, double tol, const std::string& engine, bool accept_partial,
               const std::vector<std::pair<int, int>>& pairs);

}  // namespace nurbsgl_python
