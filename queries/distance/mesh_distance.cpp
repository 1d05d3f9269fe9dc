#include "queries/distance/mesh_distance.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "nurbs/parallel.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/stopwatch.h"
#include "queries/distance/point_batch_descent.h"

namespace queries {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Rays: the shells lie this many eps along the vertex normals to either side of the mesh, the
/// tubes have this many eps as radius (the faces lie within eps of the mesh).
constexpr double kShellOffset = 1.5, kTubeRadius = 2.0;
/// Rays: the longest piece of a tube, in tube radii.
constexpr double kTubePiece = 32.0;

/// One point's search: the point in double, the best triangle so far.
struct ClosestSearch {
  const nurbs::TriangleMesh* mesh = nullptr;
  glm::dvec3 p{0.0};
  double slack = 0.0;  ///< the float rounding allowance added to Embree's radius
  double best = kInf;
  int triangle = -1;
  glm::dvec3 point{0.0}, weights{0.0};
  long long tested = 0;
};

bool closest_triangle(RTCPointQueryFunctionArguments* args) {
  ClosestSearch& s = *static_cast<ClosestSearch*>(args->userPtr);
  const glm::ivec3 t = s.mesh->triangles[args->primID];
  glm::dvec3 w;
  const glm::dvec3 q = closest_on_triangle(s.p, s.mesh->positions[size_t(t.x)], s.mesh->positions[size_t(t.y)],
                                           s.mesh->positions[size_t(t.z)], w);
  ++s.tested;
  const double d = glm::length(q - s.p);
  // The nearest, the lowest index among equals: the same answer whatever the tree and the order
  // of the walk (a triangle as near as the best is never pruned).
  if (!(d < s.best) && !(d == s.best && int(args->primID) < s.triangle)) return false;
  const bool nearer = d < s.best;
  s.best = d, s.triangle = int(args->primID), s.point = q, s.weights = w;
  if (!nearer) return false;
  args->query->radius = float(d * (1.0 + 1e-6) + s.slack);
  return true;
}

/// Rays: the mesh boundary edge of a tube piece (geometry `tube_geometry`), or a ball's vertex
/// twice (the geometry after it), and that edge's face (-1 without vertex faces).
std::pair<glm::ivec2, int> boundary_of(unsigned geometry, unsigned primitive, int tube_geometry,
                                       const std::vector<glm::ivec2>& tubes, const std::vector<int>& balls,
                                       const nurbs::TriangleMesh& m) {
  const glm::ivec2 e = int(geometry) == tube_geometry ? tubes[primitive] : glm::ivec2(balls[primitive]);
  return {e, m.vertex_face.empty() ? -1 : m.vertex_face[size_t(e.x)]};
}

/// One point's search for the slabs and tubes that may hold it (slabs_at).
struct SlabSearch {
  const nurbs::TriangleMesh* mesh = nullptr;
  const std::vector<glm::ivec2>* tubes = nullptr;
  const std::vector<int>* balls = nullptr;
  int tube_geometry = -1;
  glm::dvec3 p{0.0};
  double shell_reach = 0.0, tube_reach = 0.0;  ///< with the float allowance
  SlabsAt* out = nullptr;
};

bool slab_holding(RTCPointQueryFunctionArguments* args) {
  SlabSearch& s = *static_cast<SlabSearch*>(args->userPtr);
  const nurbs::TriangleMesh& m = *s.mesh;
  SlabsAt& out = *s.out;
  // A face found once is found: its first triangle or edge within reach gives the (u, v).
  const bool shell = args->geomID <= 1;
  const auto [e, face] = shell ? std::pair{glm::ivec2(-1), m.triangle_face[args->primID]}
                               : boundary_of(args->geomID, args->primID, s.tube_geometry, *s.tubes, *s.balls, m);
  for (int i = 0; i < out.count; ++i)
    if (out.faces[size_t(i)].face == face) return false;
  MeshRayHit h;
  h.face = face;
  if (shell) {
    const glm::ivec3 t = m.triangles[args->primID];
    glm::dvec3 w;
    const glm::dvec3 q = closest_on_triangle(s.p, m.positions[size_t(t.x)], m.positions[size_t(t.y)],
                                             m.positions[size_t(t.z)], w);
    h.t = glm::length(q - s.p);
    if (!(h.t <= s.shell_reach)) return false;
    h.triangle = int(args->primID);
    h.uv = w.x * m.uv[size_t(t.x)] + w.y * m.uv[size_t(t.y)] + w.z * m.uv[size_t(t.z)];
  } else {
    const glm::dvec3 a = m.positions[size_t(e.x)], b = m.positions[size_t(e.y)];
    const double ab = glm::dot(b - a, b - a);
    const double f = ab > 0.0 ? std::clamp(glm::dot(s.p - a, b - a) / ab, 0.0, 1.0) : 0.0;
    h.t = glm::length(a + f * (b - a) - s.p);
    if (!(h.t <= s.tube_reach)) return false;
    h.boundary = true;
    h.edge = e;
    h.uv = (1.0 - f) * m.uv[size_t(e.x)] + f * m.uv[size_t(e.y)];
  }
  if (out.count < int(out.faces.size()))
    out.faces[size_t(out.count++)] = h;
  else
    out.more = true;
  return false;
}

}  // namespace

struct MeshDistance::Scene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Scene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

/// The key of the edge between vertices a and b, either way round.
uint64_t edge_key(int a, int b) { return uint64_t(uint32_t(std::min(a, b))) << 32 | uint32_t(std::max(a, b)); }

/// The keys of the edges of `m` that one triangle alone uses (per face: each face's vertices are
/// its own), sorted.
std::vector<uint64_t> boundary_edges(const nurbs::TriangleMesh& m) {
  std::vector<uint64_t> keys;
  keys.reserve(3 * m.triangles.size());
  for (const glm::ivec3& t : m.triangles)
    for (const auto& [a, b] : {std::pair{t.x, t.y}, {t.y, t.z}, {t.z, t.x}}) keys.push_back(edge_key(a, b));
  std::sort(keys.begin(), keys.end());
  std::vector<uint64_t> out;
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i == 1) out.push_back(keys[i]);
    i = j;
  }
  return out;
}

}  // namespace

MeshDistance::MeshDistance(const std::vector<nurbs::TrimmedSurface>& faces, double eps, int threads,
                           long long max_cells, bool rays)
    : eps_(eps), threads_(threads), rays_(rays), scene_(std::make_unique<Scene>()) {
  nurbs::tess::TessellateOptions o;
  o.eps = eps;
  o.mode = nurbs::tess::TessMode::Guaranteed;
  o.subdivision = nurbs::tess::Subdivision::Grid;
  o.threads = threads;
  o.max_cells = max_cells;
  auto t0 = std::chrono::steady_clock::now();
  tess_ = nurbs::tess::tessellate(faces, o);
  // The tessellation's trim stage against the exact trims (one point-in-polygon test per triangle
  // centroid): a face whose triangles lie outside its trim by more than eps (a loop the half-edge
  // stage read otherwise, e.g. one touching itself where a hole meets the outline) is not meshed
  // within the bound, and fails as a face that gave no triangles.
  const std::vector<nurbs::tess::OutsideTrim> outside =
      nurbs::tess::triangles_outside_trim(faces, tess_.mesh, eps, /*centroids_only=*/true);
  for (size_t f = 0; f < outside.size(); ++f)
    if (outside[f].triangles > 0)
      tess_.failures.push_back({int(f), fmt::format("{} triangles lie outside its trim, up to {:.3g} beyond its "
                                                    "edges (the mesh's trim differs from the face's)",
                                                    outside[f].triangles, outside[f].distance)});
  tess_seconds_ = nurbs::seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const nurbs::TriangleMesh& m = tess_.mesh;
  if (m.triangles.size() >= size_t(std::numeric_limits<unsigned>::max()))
    throw std::length_error(fmt::format("MeshDistance: {} triangles", m.triangles.size()));
  glm::dvec3 lo(kInf), hi(-kInf);
  for (const glm::dvec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (!m.positions.empty()) centre_ = 0.5 * (lo + hi), lo_ = lo, hi_ = hi;
  for (const glm::dvec3& p : m.positions) radius_ = std::max(radius_, glm::length(p - centre_));

  const std::string config = threads > 0 ? fmt::format("threads={}", threads) : std::string();
  scene_->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!scene_->device) throw std::runtime_error(fmt::format("Embree: no device ({})", int(rtcGetDeviceError(nullptr))));
  scene_->scene = rtcNewScene(scene_->device);
  // Rays: Embree's fast traversal culls thin boxes in float and loses crossings of the shells at
  // shallow angles (a ray grazing a sphere missed the shell it entered); the robust mode keeps them.
  if (rays) rtcSetSceneFlags(scene_->scene, RTC_SCENE_FLAG_ROBUST);
  if (!rays) {
    add_triangles(scene_->scene, m.positions, 0.0);
    // Per triangle, which of its edges lie on its face's mesh boundary (bit k: the edge opposite
    // corner k), for on_trim_edge.
    boundary_.assign(m.triangles.size(), 0);
    const std::vector<uint64_t> keys = boundary_edges(m);
    const auto on_boundary = [&](int a, int b) { return std::binary_search(keys.begin(), keys.end(), edge_key(a, b)); };
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const glm::ivec3 t = m.triangles[i];
      boundary_[i] = uint8_t((on_boundary(t.y, t.z) ? 1 : 0) | (on_boundary(t.z, t.x) ? 2 : 0) |
                             (on_boundary(t.x, t.y) ? 4 : 0));
    }
  } else {  // the two shells, inside and outside (geometries 0 and 1), then the tubes and balls
    add_triangles(scene_->scene, m.positions, -kShellOffset * eps);
    add_triangles(scene_->scene, m.positions, kShellOffset * eps);
    std::vector<std::pair<int, int>> edges;
    for (const uint64_t key : boundary_edges(m)) edges.emplace_back(int(key >> 32), int(key & 0xffffffffu));
    if (!edges.empty()) {
      tube_geometry_ = 2;
      // Embree's round curves lose crossings of a tube far longer than its radius (a ray along a
      // 315-long edge with radius 0.08 passed 1.25 radii from it unseen): each edge's tube is made
      // of pieces at most kTubePiece radii long.
      const double r = kTubeRadius * eps;
      std::vector<int> pieces;
      for (const auto& [a, b] : edges) {
        const double length = glm::length(m.positions[size_t(b)] - m.positions[size_t(a)]);
        pieces.push_back(std::max(1, int(std::min(1e6, std::ceil(length / (kTubePiece * r))))));
        for (int i = 0; i < pieces.back(); ++i) boundary_vertices_.emplace_back(a, b);
      }
      const size_t segments = boundary_vertices_.size();
      RTCGeometry g = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                            4 * sizeof(float), 2 * segments));
      auto* idx = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), segments));
      if (!v || !idx) {
        rtcReleaseGeometry(g);
        throw std::runtime_error(fmt::format("Embree: no memory for {} boundary edges", edges.size()));
      }
      size_t k = 0;
      for (size_t j = 0; j < edges.size(); ++j) {
        const glm::dvec3 a = m.positions[size_t(edges[j].first)], b = m.positions[size_t(edges[j].second)];
        for (int i = 0; i < pieces[j]; ++i, ++k) {
          for (int e = 0; e < 2; ++e) {
            const glm::vec3 f(a + (double(i + e) / pieces[j]) * (b - a) - centre_);
            float* out = v + 4 * (2 * k + size_t(e));
            out[0] = f.x, out[1] = f.y, out[2] = f.z, out[3] = float(r);
          }
          idx[k] = unsigned(2 * k);
        }
      }
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene_->scene, g);
      rtcReleaseGeometry(g);
    }
    // Points whose normal the surface leaves undefined (poles, where a row of the grid collapses)
    // and the collapsed boundary edges there: the shells pinch to the point, and a ray through it
    // may pass between the triangles that meet there. A ball of the tubes' radius around each.
    std::vector<glm::dvec3> balls;
    for (size_t i = 0; i < m.positions.size(); ++i)
      if (i >= m.normals.size() || !(glm::length(m.normals[i]) > 0.5))
        balls.push_back(m.positions[i]), ball_vertices_.push_back(int(i));
    for (const auto& [a, b] : edges)
      if (m.positions[size_t(a)] == m.positions[size_t(b)])
        balls.push_back(m.positions[size_t(a)]), ball_vertices_.push_back(a);
    if (!balls.empty()) {
      RTCGeometry g = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                            4 * sizeof(float), balls.size()));
      if (!v) {
        rtcReleaseGeometry(g);
        throw std::runtime_error(fmt::format("Embree: no memory for {} balls", balls.size()));
      }
      for (size_t k = 0; k < balls.size(); ++k) {
        const glm::vec3 f(balls[k] - centre_);
        v[4 * k] = f.x, v[4 * k + 1] = f.y, v[4 * k + 2] = f.z, v[4 * k + 3] = float(kTubeRadius * eps);
      }
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene_->scene, g);
      rtcReleaseGeometry(g);
    }
  }
  rtcCommitScene(scene_->scene);
  if (const RTCError e = rtcGetDeviceError(scene_->device); e != RTC_ERROR_NONE)
    throw std::runtime_error(fmt::format("Embree: the scene of {} triangles failed (error {})", m.triangles.size(),
                                         int(e)));
  build_seconds_ = nurbs::seconds_since(t0);
}

MeshDistance::~MeshDistance() = default;

void MeshDistance::add_triangles(RTCScene scene, const std::vector<glm::dvec3>& positions, double offset) {
  const nurbs::TriangleMesh& m = tess_.mesh;
  if (m.triangles.empty()) return;
  RTCGeometry g = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), m.triangles.size()));
  if (!v || !idx) {
    rtcReleaseGeometry(g);
    throw std::runtime_error(fmt::format("Embree: no memory for {} triangles", m.triangles.size()));
  }
  for (size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3 n = offset != 0.0 && i < m.normals.size() ? m.normals[i] : glm::dvec3(0.0);
    const glm::vec3 f(positions[i] + offset * n - centre_);
    v[3 * i] = f.x, v[3 * i + 1] = f.y, v[3 * i + 2] = f.z;
  }
  for (size_t i = 0; i < m.triangles.size(); ++i)
    idx[3 * i] = unsigned(m.triangles[i].x), idx[3 * i + 1] = unsigned(m.triangles[i].y),
            idx[3 * i + 2] = unsigned(m.triangles[i].z);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
}

PointDistance MeshDistance::answer(int triangle, double distance, const glm::dvec3& point, const glm::dvec3& w,
                                   long long tested) const {
  PointDistance r;
  r.candidates = tested;
  if (triangle < 0) return r;
  const nurbs::TriangleMesh& m = tess_.mesh;
  const glm::ivec3 t = m.triangles[size_t(triangle)];
  r.found = true;
  r.distance = distance;
  r.point = point;
  r.face = m.triangle_face[size_t(triangle)];
  r.uv = w.x * m.uv[size_t(t.x)] + w.y * m.uv[size_t(t.y)] + w.z * m.uv[size_t(t.z)];
  r.bound = eps_;
  r.point_bound = std::sqrt(4.0 * eps_ * distance + eps_ * eps_);
  r.upper = distance + eps_;
  r.meets_tolerance = true;
  // On its face's boundary: a weight 0 on a boundary edge's opposite corner (the trim edge, or the
  // edge of the face's domain; the side test takes no normal there).
  if (!boundary_.empty())
    for (int k = 0; k < 3; ++k) r.on_trim_edge = r.on_trim_edge || ((boundary_[size_t(triangle)] >> k & 1) && w[k] <= 0.0);
  return r;
}

std::vector<PointDistance> MeshDistance::query(std::span<const glm::dvec3> points,
                                               const std::function<void(size_t, size_t)>& progress) const {
  std::vector<PointDistance> out(points.size());
  // Along a Morton curve, in runs of kRun points: each point's search starts from the previous
  // one's answer moved by their distance apart (an upper bound of its own), so Embree prunes from
  // the first node instead of after its first leaves.
  constexpr size_t kRun = 256;
  const std::vector<uint32_t> order = morton_order(points, centre_, std::max(radius_, 1e-300));
  const size_t runs = (points.size() + kRun - 1) / kRun;
  std::atomic<size_t> done{0};
  nurbs::parallel_for(runs, threads_, [&](size_t run, int thread) {
    double previous = kInf;
    glm::dvec3 previous_point(0.0);
    for (size_t i = run * kRun; i < std::min(points.size(), (run + 1) * kRun); ++i) {
      const size_t k = order[i];
      ClosestSearch s;
      s.mesh = &tess_.mesh;
      s.p = points[k];
      const glm::dvec3 q = points[k] - centre_;
      s.slack = float_slack(points[k]);
      const double start = previous + glm::length(points[k] - previous_point);
      RTCPointQuery pq;
      pq.x = float(q.x), pq.y = float(q.y), pq.z = float(q.z);
      pq.time = 0.0f;
      pq.radius = start < kInf ? float(start * (1.0 + 1e-6) + s.slack) : std::numeric_limits<float>::infinity();
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(scene_->scene, &pq, &context, closest_triangle, &s);
      out[k] = answer(s.triangle, s.best, s.point, s.weights, s.tested);
      previous = s.triangle >= 0 ? s.best : kInf, previous_point = points[k];
    }
    const size_t total = done.fetch_add(std::min(kRun, points.size() - run * kRun)) + kRun;
    if (progress && thread == 0) progress(std::min(total, points.size()), points.size());
  });
  if (progress) progress(points.size(), points.size());
  return out;
}

SlabsAt MeshDistance::slabs_at(const glm::dvec3& p) const {
  SlabsAt out;
  if (!rays_) return out;
  SlabSearch s;
  s.mesh = &tess_.mesh;
  s.tubes = &boundary_vertices_;
  s.balls = &ball_vertices_;
  s.tube_geometry = tube_geometry_;
  s.p = p;
  const double slack = float_slack(p);
  s.shell_reach = kShellOffset * eps_ + slack;
  s.tube_reach = kTubeRadius * eps_ + slack;
  const double reach = std::max(s.shell_reach, s.tube_reach) + slack;
  if (glm::any(glm::lessThan(p, lo_ - reach)) || glm::any(glm::greaterThan(p, hi_ + reach))) return out;
  s.out = &out;
  const glm::dvec3 q = p - centre_;
  RTCPointQuery pq;
  pq.x = float(q.x), pq.y = float(q.y), pq.z = float(q.z);
  pq.time = 0.0f;
  pq.radius = float(reach);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_->scene, &pq, &context, slab_holding, &s);
  return out;
}

double MeshDistance::box_exit(const glm::dvec3& origin, const glm::dvec3& direction) const {
  const double reach = (kTubeRadius + 1.0) * eps_ + 2.0 * float_slack(origin);
  double near = 0.0, far = kInf;
  for (int i = 0; i < 3; ++i) {
    const double lo = lo_[i] - reach, hi = hi_[i] + reach;
    if (direction[i] == 0.0) {
      if (origin[i] < lo || origin[i] > hi) return 0.0;
      continue;
    }
    double a = (lo - origin[i]) / direction[i], b = (hi - origin[i]) / direction[i];
    if (a > b) std::swap(a, b);
    near = std::max(near, a), far = std::min(far, b);
  }
  return near <= far ? far : 0.0;
}

MeshRayHit MeshDistance::first_hit(const glm::dvec3& origin, const glm::dvec3& direction, double t_min,
                                   double t_max) const {
  const glm::vec3 o(origin - centre_), d(direction);
  RTCRayHit rh;
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
  rh.ray.tnear = float(std::max(t_min, 0.0));
  rh.ray.tfar = t_max < 3e38 ? float(t_max) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID, rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(scene_->scene, &context, &rh);
  MeshRayHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  if (rays_ && rh.hit.geomID >= 2) {  // a tube or a ball
    h.boundary = true;
    h.t = double(rh.ray.tfar);
    std::tie(h.edge, h.face) =
        boundary_of(rh.hit.geomID, rh.hit.primID, tube_geometry_, boundary_vertices_, ball_vertices_, tess_.mesh);
    return h;
  }
  const nurbs::TriangleMesh& m = tess_.mesh;
  h.triangle = int(rh.hit.primID);
  h.t = double(rh.ray.tfar);
  h.face = m.triangle_face[size_t(h.triangle)];
  const glm::ivec3 t = m.triangles[size_t(h.triangle)];
  const double u = rh.hit.u, v = rh.hit.v;
  h.uv = (1.0 - u - v) * m.uv[size_t(t.x)] + u * m.uv[size_t(t.y)] + v * m.uv[size_t(t.z)];
  if (rays_) {
    // The shell triangle's side, in double: triangles run counter-clockwise seen from outside, and
    // the outer shell (geometry 1) is the mesh moved outwards, so the ray enters the slab through
    // it against its normal, and through the inner one along its normal.
    h.shell = int(rh.hit.geomID);
    const double offset = (h.shell == 1 ? 1.0 : -1.0) * kShellOffset * eps_;
    const auto corner = [&](int i) {
      return m.positions[size_t(i)] + (size_t(i) < m.normals.size() ? offset * m.normals[size_t(i)] : glm::dvec3(0.0));
    };
    const glm::dvec3 a = corner(t.x), n = glm::cross(corner(t.y) - a, corner(t.z) - a);
    h.entering = (glm::dot(direction, n) < 0.0) == (h.shell == 1);
  }
  return h;
}

double MeshDistance::float_slack(const glm::dvec3& p) const {
  return std::ldexp(radius_ + glm::length(p - centre_), -18);
}

PointDistance MeshDistance::brute_force(const glm::dvec3& p) const {
  const nurbs::TriangleMesh& m = tess_.mesh;
  double best = kInf;
  int triangle = -1;
  glm::dvec3 point(0.0), weights(0.0);
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const glm::ivec3 t = m.triangles[i];
    glm::dvec3 w;
    const glm::dvec3 q =
        closest_on_triangle(p, m.positions[size_t(t.x)], m.positions[size_t(t.y)], m.positions[size_t(t.z)], w);
    const double d = glm::length(q - p);
    if (d < best) best = d, triangle = int(i), point = q, weights = w;
  }
  return answer(triangle, best, point, weights, (long long)m.triangles.size());
}

}  // namespace queries
