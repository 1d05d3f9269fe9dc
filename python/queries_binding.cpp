#include "python/queries_binding.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/tessellation/model_mesh.h"
#include "python/convert.h"
#include "python/gl_thread.h"
#include "queries/distance/clash.h"
#include "queries/distance/clearance_pair.h"
#include "queries/inspection/inspect.h"
#include "queries/raycast/ray_caster.h"
#include "queries/raycast/raycast_query.h"
#include "queries/raycast/thickness_map.h"

namespace nurbsgl_python {
namespace {

queries::EngineChoice engine_of(const std::string& name) {
  try {
    return queries::engine_choice(name);
  } catch (const std::invalid_argument&) {
    throw py::value_error(fmt::format("engine: '{}' is not one of auto, cpu, gpu", name));
  }
}

double coordinate_limit(const nurbs::Model& model) { return nurbs::coordinate_limit(nurbs::model_box(model)); }

/// The prepared point query of `m` for these options, prepared on the GL thread on first use.
std::shared_ptr<queries::PointQuery> point_query(ModelBinding& m, const queries::PointQueryOptions& o) {
  // Checked before the cache is looked up: a key of NaN would find another tolerance's query.
  nurbs::require_relative_tolerance(o.tolerance, "tolerance");
  const ModelBinding::Key key{o.tolerance, o.per_point, int(o.engine), o.accept_partial, o.cache, o.signed_distance};
  std::lock_guard lock(m.mutex);  // one preparation per key, also when two threads ask at once
  if (auto it = m.point_queries.find(key); it != m.point_queries.end()) return it->second;
  std::unique_ptr<queries::PointQuery> q;
  GlThread::instance().run(
      [&] { q = std::make_unique<queries::PointQuery>(GlThread::instance().gpu(), *m.loaded, o); });
  auto shared = on_gl_thread(std::move(q));
  m.point_queries.emplace(key, shared);
  return shared;
}

}  // namespace

py::dict point_distance(ModelBinding& m, const py::handle& points, double tol, const std::string& engine,
                        bool per_point, bool accept_partial, bool cache, bool signed_distance, bool strict) {
  const std::vector<glm::dvec3> p = points_from(points, "points", coordinate_limit(m.loaded->model));
  queries::PointQueryOptions o;
  o.tolerance = tol, o.per_point = per_point, o.engine = engine_of(engine), o.accept_partial = accept_partial;
  o.cache = cache, o.signed_distance = signed_distance;
  queries::PointQueryResult r;
  std::shared_ptr<queries::PointQuery> q;
  {
    py::gil_scoped_release release;
    q = point_query(m, o);
    GlThread::instance().run([&] { r = q->query(p); });
  }
  const size_t n = r.answers.size();
  std::vector<double> distance(n), bound(n), point_bound(n);
  std::vector<glm::dvec3> closest(n);
  std::vector<glm::dvec2> uv(n);
  std::vector<int32_t> face(n);
  std::vector<char> meets(n), limited(n);
  std::vector<double> file_gap(n);
  std::vector<int32_t> gap_face(n);
  py::list reasons;
  for (size_t k = 0; k < n; ++k) {
    const queries::PointDistance& a = r.answers[k];
    distance[k] = a.found ? a.distance : std::nan("");
    bound[k] = a.found ? a.bound : std::nan("");
    point_bound[k] = a.found ? a.point_bound : std::nan("");
    closest[k] = a.point, uv[k] = a.uv, face[k] = a.found ? a.face : -1;
    meets[k] = r.meets(k);
    reasons.append(r.reason(k));
    const queries::FileLimit& l = r.file_limits[k];
    limited[k] = l.limited, file_gap[k] = l.widen > 0.0 ? l.gap : 0.0, gap_face[k] = l.widen > 0.0 ? l.face : -1;
  }
  py::dict d;
  d["distance"] = array1(distance), d["bound"] = array1(bound), d["point_bound"] = array1(point_bound);
  d["point"] = array3(closest), d["uv"] = array2(uv), d["face"] = array1(face), d["meets_tolerance"] = bools(meets);
  d["normal"] = array3(r.normals);
  d["reasons"] = reasons;
  d["limited_by_file"] = bools(limited), d["file_gap"] = array1(file_gap), d["gap_face"] = array1(gap_face);
  d["file_precision"] = r.file_precision();
  if (signed_distance) d["signed_distance"] = array1(r.signed_distance);
  d["tolerance"] = r.tolerance;
  d["engine"] = q->meshed() ? "mesh" : queries::engine_name(q->engine());
  d["batched"] = q->batched();
  d["path"] = q->meshed() ? "mesh" : q->batched() ? "batched" : "per-point";
  d["seconds"] = r.seconds;
  d["prepare_seconds"] = q->prepare_seconds();
  d["failure"] = r.failure(strict);
  return d;
}

py::dict inspect(ModelBinding& m, const py::handle& scan, const std::vector<double>& within, double max_distance,
                 double tol, const py::handle& transform, bool align, const std::vector<int>& align_faces,
                 size_t align_sample, const std::string& engine, bool accept_partial) {
  const std::vector<glm::dvec3> p = points_from(scan, "scan", coordinate_limit(m.loaded->model));
  queries::InspectOptions o;
  o.within = within, o.max_distance = max_distance, o.tolerance = tol, o.align = align;
  o.fit.faces = align_faces, o.fit.sample = align_sample;
  o.query.engine = engine_of(engine), o.query.accept_partial = accept_partial;
  if (!transform.is_none()) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(transform);
    if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
      throw py::value_error("transform: a 4 x 4 array (scan into model coordinates)");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) o.transform[c][r] = a.at(r, c);
  }
  queries::InspectResult r;
  {
    py::gil_scoped_release release;
    GlThread::instance().run([&] { r = queries::inspect(GlThread::instance().gpu(), *m.loaded, p, o); });
  }
  const size_t n = r.points.size(), nb = r.bands.size();
  std::vector<double> bound(n);
  std::vector<glm::dvec3> closest(n);
  std::vector<int32_t> face(n);
  py::array_t<int8_t> verdicts({py::ssize_t(n), py::ssize_t(nb)});
  for (size_t k = 0; k < n; ++k) {
    const queries::PointDistance& a = r.answers.answers[k];
    bound[k] = a.found ? a.bound : std::nan("");
    closest[k] = a.point, face[k] = a.found ? a.face : -1;
    for (size_t b = 0; b < nb; ++b)
      verdicts.mutable_at(py::ssize_t(k), py::ssize_t(b)) = int8_t(r.verdicts[k * nb + b]);
  }
  py::array_t<double> matrix({4, 4});
  for (int row = 0; row < 4; ++row)
    for (int c = 0; c < 4; ++c) matrix.mutable_at(row, c) = r.alignment.matrix[c][row];
  py::dict alignment;
  alignment["matrix"] = matrix, alignment["aligned"] = r.aligned, alignment["rms"] = r.alignment.rms;
  alignment["points_used"] = r.alignment.points_used, alignment["iterations"] = r.alignment.iterations;
  alignment["converged"] = r.alignment.converged, alignment["coarse_start"] = r.alignment.coarse_start;
  alignment["problem"] = r.alignment.problem;
  py::list bands;
  for (const queries::BandVerdicts& b : r.bands) {
    py::dict d;
    d["within"] = b.within, d["certainly_within"] = b.certainly_within, d["certainly_outside"] = b.certainly_outside;
    d["undecided"] = b.undecided, d["share_within"] = b.share_within, d["share_above"] = b.share_above;
    d["share_below"] = b.share_below;
    bands.append(d);
  }
  const queries::InspectStatistics& s = r.stats;
  py::dict stats;
  stats["points"] = s.points, stats["inliers"] = s.inliers, stats["outliers"] = s.outliers;
  stats["not_found"] = s.not_found, stats["min"] = s.min, stats["max"] = s.max, stats["mean"] = s.mean;
  stats["sigma"] = s.sigma, stats["rms"] = s.rms;
  py::dict percentiles;
  for (size_t i = 0; i < s.percentiles.size(); ++i)
    percentiles[py::float_(queries::InspectStatistics::kPercentiles[i])] = s.percentiles[i];
  stats["percentiles"] = percentiles;
  py::list reasons;
  for (size_t k = 0; k < n; ++k) reasons.append(r.answers.reason(k));
  py::dict d;
  d["points"] = array3(r.points), d["deviation"] = array1(r.deviation), d["bound"] = array1(bound);
  d["closest"] = array3(closest), d["normal"] = array3(r.answers.normals), d["face"] = array1(face);
  d["outlier"] = bools(r.outlier), d["verdicts"] = verdicts, d["reasons"] = reasons;
  d["signed"] = r.signed_values, d["unsigned_reason"] = r.unsigned_reason, d["tolerance"] = r.tolerance;
  d["alignment"] = alignment, d["bands"] = bands, d["statistics"] = stats;
  d["undecided_points"] = r.undecided_points, d["failure"] = r.failure();
  d["seconds"] = r.prepare_seconds + r.fit_seconds + r.query_seconds;
  return d;
}

py::dict tessellate(ModelBinding& m, double eps, bool relative, bool watertight, bool guaranteed, bool check,
                    bool accept_partial) {
  nurbs::tess::ModelMeshOptions o;
  o.eps = eps, o.relative = relative, o.check = check, o.accept_partial = accept_partial;
  o.tess.watertight = watertight;
  o.tess.mode = guaranteed ? nurbs::tess::TessMode::Guaranteed : nurbs::tess::TessMode::Approximate;
  nurbs::tess::ModelMesh mesh;
  {
    py::gil_scoped_release release;
    mesh = nurbs::tess::mesh_model(*m.loaded, o);
  }
  const nurbs::TriangleMesh& t = mesh.result.mesh;
  py::array_t<int32_t> triangles({py::ssize_t(t.triangles.size()), py::ssize_t(3)});
  int32_t* tri = triangles.mutable_data();
  for (size_t i = 0; i < t.triangles.size(); ++i)
    tri[3 * i] = t.triangles[i].x, tri[3 * i + 1] = t.triangles[i].y, tri[3 * i + 2] = t.triangles[i].z;
  py::dict d;
  d["vertices"] = array3(t.positions);
  d["triangles"] = triangles;
  d["triangle_face"] = array1(std::vector<int32_t>(t.triangle_face.begin(), t.triangle_face.end()));
  d["normals"] = array3(t.normals);
  d["eps"] = mesh.eps;
  d["bound"] = mesh.bound();
  d["guaranteed"] = mesh.guaranteed;
  d["failure"] = mesh.failure();
  if (mesh.deviation)
    d["deviation"] = std::max(mesh.deviation->surface_to_mesh, mesh.deviation->mesh_to_surface);
  return d;
}

py::dict raycast(ModelBinding& m, const py::handle& origins, const py::handle& directions, double t_min,
                 const std::string& engine, double tol, double mesh_tol, bool accept_partial) {
  using Limits = queries::RayCasterOptions;
  if (!(tol >= Limits::kMinTolerance && tol <= Limits::kMaxTolerance))
    throw py::value_error(fmt::format("tol {}: outside [{}, {}]", tol, Limits::kMinTolerance, Limits::kMaxTolerance));
  if (!(mesh_tol >= Limits::kMinMeshTolerance && mesh_tol <= Limits::kMaxMeshTolerance))
    throw py::value_error(
        fmt::format("mesh_tol {}: outside [{}, {}]", mesh_tol, Limits::kMinMeshTolerance, Limits::kMaxMeshTolerance));
  const double limit = coordinate_limit(m.loaded->model);
  const std::vector<glm::dvec3> o = points_from(origins, "origins", limit);
  const std::vector<glm::dvec3> dir = points_from(directions, "directions", 1e300);
  if (o.size() != dir.size())
    throw py::value_error(fmt::format("origins and directions: {} and {} rows", o.size(), dir.size()));
  std::vector<nurbs::ray::Ray> rays(o.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    const double len = glm::length(dir[i]);
    if (!(len > 0.0)) throw py::value_error(fmt::format("directions: row {} is zero", i));
    rays[i] = {o[i], dir[i] / len};
  }
  queries::RaycastOptions options;
  options.gpu = engine_of(engine) == queries::EngineChoice::Gpu;
  options.caster.method = options.gpu ? queries::RayMethod::Bvh : queries::RayMethod::Mesh;
  options.caster.tolerance = tol;
  options.caster.mesh_tolerance = mesh_tol;
  options.accept_partial = accept_partial;
  queries::Raycast r;
  {
    py::gil_scoped_release release;
    GlThread::instance().run([&] {
      r = queries::raycast(*m.loaded, rays, t_min, options, options.gpu ? &GlThread::instance().gpu() : nullptr);
    });
  }
  const std::vector<nurbs::ray::Hit>& hits = r.hits;
  std::vector<char> hit(hits.size());
  std::vector<double> t(hits.size());
  std::vector<glm::dvec3> point(hits.size());
  std::vector<glm::dvec2> uv(hits.size());
  std::vector<int32_t> face(hits.size());
  for (size_t i = 0; i < hits.size(); ++i) {
    hit[i] = hits[i].face >= 0;
    t[i] = hit[i] ? hits[i].t : std::nan("");
    point[i] = hits[i].point, uv[i] = hits[i].uv, face[i] = hits[i].face;
  }
  py::dict d;
  d["hit"] = bools(hit), d["t"] = array1(t), d["point"] = array3(point), d["uv"] = array2(uv);
  d["face"] = array1(face);
  d["method"] = queries::method_name(r.method);
  d["mesh_triangles"] = r.figures.mesh_triangles;
  d["hit_residual"] = r.hit_residual;
  d["seconds"] = r.figures.cast_seconds;
  d["failure"] = r.failure();
  return d;
}

py::dict thickness(ModelBinding& m, long long samples, const std::string& engine, bool ball, double min_wall,
                   bool accept_partial) {
  queries::ThicknessMapOptions o;
  o.samples = samples, o.ball = ball, o.min_wall = min_wall, o.accept_partial = accept_partial;
  o.gpu = engine_of(engine) == queries::EngineChoice::Gpu;
  if (o.gpu) o.caster.method = queries::RayMethod::Bvh;  // the only method of the GPU pass
  queries::ThicknessMap map;
  {
    py::gil_scoped_release release;
    GlThread::instance().run([&] {
      map = queries::thickness_map(*m.loaded, o, o.gpu || o.ball ? &GlThread::instance().gpu() : nullptr);
    });
  }
  const size_t n = map.rays.rays.size();
  std::vector<glm::dvec3> origin(n), direction(n);
  std::vector<double> value(n, -1.0), ball_value;
  std::vector<int32_t> face(n);
  for (size_t i = 0; i < n; ++i) {
    origin[i] = map.rays.rays[i].origin, direction[i] = map.rays.rays[i].direction;
    const auto [f, g] = map.rays.source[i];
    face[i] = map.samples.faces[size_t(f)].face;
    value[i] = map.thickness[size_t(f)][size_t(g)];
  }
  if (map.ball)
    for (const nurbs::ray::BallThickness& b : map.ball->samples) ball_value.push_back(b.thickness);
  py::dict d;
  d["origin"] = array3(origin), d["direction"] = array3(direction), d["face"] = array1(face);
  d["thickness"] = array1(value);
  if (map.ball) d["ball"] = array1(ball_value);
  d["min"] = map.summary.min, d["median"] = map.summary.median, d["mean"] = map.summary.mean;
  d["max"] = map.summary.max, d["hits"] = map.hit_count, d["below_min_wall"] = map.below_min_wall;
  d["spacing"] = map.spacing;
  d["failure"] = map.failure();
  return d;
}

namespace {

py::dict answer_dict(const queries::ClearanceAnswer& answer) {
  const queries::Clearance& c = answer.clearance;
  py::dict d;
  d["found"] = c.found, d["distance"] = c.distance, d["bound"] = c.bound, d["point_bound"] = c.point_bound();
  d["point_a"] = py::make_tuple(c.point_a.x, c.point_a.y, c.point_a.z);
  d["point_b"] = py::make_tuple(c.point_b.x, c.point_b.y, c.point_b.z);
  d["face_a"] = c.face_a, d["face_b"] = c.face_b;
  d["uv_a"] = py::make_tuple(c.uv_a.x, c.uv_a.y), d["uv_b"] = py::make_tuple(c.uv_b.x, c.uv_b.y);
  d["intersecting"] = c.intersecting;
  if (c.intersecting) d["intersection"] = py::make_tuple(c.intersection.x, c.intersection.y, c.intersection.z);
  d["meets_tolerance"] = answer.meets();
  d["uncertified"] = answer.reason;
  d["limited_by_file"] = answer.limited_by_file();
  d["file_gap"] = answer.widen > 0.0 ? answer.gap : 0.0;
  d["reason"] = answer.shortfall();
  d["failure"] = answer.failure();
  d["tolerance"] = answer.tolerance;
  d["seconds"] = answer.seconds;
  return d;
}

}  // namespace

py::dict clash(ModelBinding& m, double min_clearance, double tol, const std::string& engine, bool accept_partial,
               const std::vector<std::pair<int, int>>& pairs) {
  queries::ClashOptions o;
  o.clearance.tolerance = tol, o.clearance.engine = engine_of(engine), o.clearance.accept_partial = accept_partial;
  o.min_clearance = min_clearance;
  o.pairs = pairs;
  queries::ClashReport r;
  {
    py::gil_scoped_release release;
    GlThread::instance().run([&] { r = queries::clash_report(*m.loaded, o, &GlThread::instance().gpu()); });
  }
  py::list rows;
  for (const queries::ClashRow& row : r.rows) {
    py::dict d = row.computed ? answer_dict(row.answer) : py::dict();
    d["body_a"] = row.body_a, d["body_b"] = row.body_b, d["name_a"] = row.name_a, d["name_b"] = row.name_b;
    d["box_distance"] = row.box_distance, d["computed"] = row.computed;
    d["beyond_min_clearance"] = row.beyond(r.min_clearance);
    if (row.computed) d["engine"] = row.engine;
    rows.append(d);
  }
  py::dict d;
  d["rows"] = rows, d["bodies"] = r.bodies, d["pairs"] = r.rows.size(), d["pairs_computed"] = r.computed;
  d["pairs_beyond"] = r.beyond_boxes, d["pairs_beyond_computed"] = r.beyond_computed;
  d["pairs_intersecting"] = r.intersecting, d["pairs_uncertified"] = r.uncertified;
  d["pairs_limited_by_file"] = r.limited_by_file;
  d["min_clearance"] = r.min_clearance, d["seconds"] = r.seconds, d["failure"] = r.failure();
  return d;
}

py::list clearance(ModelBinding& a, ModelBinding* b, const py::list& motions, const std::string& body_a,
                   const std::string& body_b, double tol, const std::string& engine, bool voxel_stage,
                   bool accept_partial) {
  std::vector<glm::dmat4> frames;
  for (const py::handle& h : motions) {
    const auto arr = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
    if (!arr || arr.ndim() != 2 || arr.shape(0) != 4 || arr.shape(1) != 4)
      throw py::value_error("motion: a 4 x 4 array (row-major, acting on column vectors) is wanted");
    glm::dmat4 f(1.0);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        f[c][r] = arr.at(r, c);
        if (!std::isfinite(f[c][r])) throw py::value_error("motion: not finite");
      }
    frames.push_back(f);
  }
  if (frames.empty()) frames.emplace_back(1.0);
  queries::ClearanceOptions o;
  o.tolerance = tol, o.engine = engine_of(engine), o.voxel_stage = voxel_stage, o.accept_partial = accept_partial;
  o.body_a = body_a, o.body_b = body_b;
  std::vector<queries::ClearanceAnswer> answers;
  {
    py::gil_scoped_release release;
    GlThread::instance().run([&] {
      queries::ClearancePair pair(*a.loaded, b ? b->loaded.get() : nullptr, o, &GlThread::instance().gpu());
      pair.prepare(frames);
      for (const glm::dmat4& f : frames) answers.push_back(pair.query(f));
    });
  }
  py::list out;
  for (const queries::ClearanceAnswer& answer : answers) out.append(answer_dict(answer));
  return out;
}

}  // namespace nurbsgl_python
