#include "queries/distance/mesh_distance.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>

#include "nurbs/parallel.h"
#include "nurbs/stopwatch.h"

namespace queries {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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
  if (!(d < s.best)) return false;
  s.best = d, s.triangle = int(args->primID), s.point = q, s.weights = w;
  args->query->radius = float(d * (1.0 + 1e-6) + s.slack);
  return true;
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

MeshDistance::MeshDistance(const std::vector<nurbs::TrimmedSurface>& faces, double eps, int threads,
                           long long max_cells)
    : eps_(eps), threads_(threads), scene_(std::make_unique<Scene>()) {
  nurbs::tess::TessellateOptions o;
  o.eps = eps;
  o.mode = nurbs::tess::TessMode::Guaranteed;
  o.subdivision = nurbs::tess::Subdivision::Grid;
  o.threads = threads;
  o.max_cells = max_cells;
  auto t0 = std::chrono::steady_clock::now();
  tess_ = nurbs::tess::tessellate(faces, o);
  tess_seconds_ = nurbs::seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const nurbs::TriangleMesh& m = tess_.mesh;
  if (m.triangles.size() >= size_t(std::numeric_limits<unsigned>::max()))
    throw std::length_error(fmt::format("MeshDistance: {} triangles", m.triangles.size()));
  glm::dvec3 lo(kInf), hi(-kInf);
  for (const glm::dvec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (!m.positions.empty()) centre_ = 0.5 * (lo + hi);
  for (const glm::dvec3& p : m.positions) radius_ = std::max(radius_, glm::length(p - centre_));

  const std::string config = threads > 0 ? fmt::format("threads={}", threads) : std::string();
  scene_->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!scene_->device) throw std::runtime_error(fmt::format("Embree: no device ({})", int(rtcGetDeviceError(nullptr))));
  scene_->scene = rtcNewScene(scene_->device);
  if (!m.triangles.empty()) {
    RTCGeometry g = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.positions.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(unsigned), m.triangles.size()));
    if (!v || !idx) {
      rtcReleaseGeometry(g);
      throw std::runtime_error(fmt::format("Embree: no memory for {} triangles", m.triangles.size()));
    }
    for (size_t i = 0; i < m.positions.size(); ++i) {
      const glm::vec3 f(m.positions[i] - centre_);
      v[3 * i] = f.x, v[3 * i + 1] = f.y, v[3 * i + 2] = f.z;
    }
    for (size_t i = 0; i < m.triangles.size(); ++i)
      idx[3 * i] = unsigned(m.triangles[i].x), idx[3 * i + 1] = unsigned(m.triangles[i].y),
              idx[3 * i + 2] = unsigned(m.triangles[i].z);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_->scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(scene_->scene);
  if (const RTCError e = rtcGetDeviceError(scene_->device); e != RTC_ERROR_NONE)
    throw std::runtime_error(fmt::format("Embree: the scene of {} triangles failed (error {})", m.triangles.size(),
                                         int(e)));
  build_seconds_ = nurbs::seconds_since(t0);
}

MeshDistance::~MeshDistance() = default;

PointDistance MeshDistance::answer(const glm::dvec3& p, int triangle, double distance, const glm::dvec3& point,
                                   const glm::dvec3& w, long long tested) const {
  PointDistance r;
  r.candidates = tested;
  if (triangle < 0) return r;
  (void)p;
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
  return r;
}

std::vector<PointDistance> MeshDistance::query(std::span<const glm::dvec3> points,
                                               const std::function<void(size_t, size_t)>& progress) const {
  std::vector<PointDistance> out(points.size());
  constexpr size_t kChunk = 256;
  std::atomic<size_t> done{0};
  nurbs::parallel_for(
      points.size(), threads_,
      [&](size_t k, int thread) {
        ClosestSearch s;
        s.mesh = &tess_.mesh;
        s.p = points[k];
        const glm::dvec3 q = points[k] - centre_;
        s.slack = std::ldexp(radius_ + glm::length(q), -18);
        RTCPointQuery pq;
        pq.x = float(q.x), pq.y = float(q.y), pq.z = float(q.z);
        pq.time = 0.0f;
        pq.radius = std::numeric_limits<float>::infinity();
        RTCPointQueryContext context;
        rtcInitPointQueryContext(&context);
        rtcPointQuery(scene_->scene, &pq, &context, closest_triangle, &s);
        out[k] = answer(s.p, s.triangle, s.best, s.point, s.weights, s.tested);
        if (progress && thread == 0 && (k % kChunk) == kChunk - 1) progress(done.load(), points.size());
        done.fetch_add(1, std::memory_order_relaxed);
      },
      kChunk);
  if (progress) progress(points.size(), points.size());
  return out;
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
  return answer(p, triangle, best, point, weights, (long long)m.triangles.size());
}

}  // namespace queries
