#include "queries/raycast/ray_caster.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <future>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "nurbs/parallel.h"
#include "nurbs/raycast/morton_bvh.h"
#include "nurbs/raycast/thickness.h"
#include "nurbs/stopwatch.h"
#include "nurbs/surface_eval.h"
#include "queries/raycast/raycast_gpu.h"

namespace queries {
namespace {

/// best becomes h where h is a hit nearer than it (or best none).
void keep_nearer(nurbs::ray::Hit& best, const nurbs::ray::Hit& h) {
  if (h.face >= 0 && (best.face < 0 || h.t < best.t)) best = h;
}

/// The indices of `rays` ordered by the Morton code of their origin's cell, 64 cells an axis across
/// the origins' box (a counting sort, in input order within a cell).
std::vector<uint32_t> morton_cells(const std::vector<nurbs::ray::Ray>& rays) {
  constexpr int kBits = 6;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const nurbs::ray::Ray& r : rays) lo = glm::min(lo, r.origin), hi = glm::max(hi, r.origin);
  const glm::dvec3 scale = double(1 << kBits) / glm::max(hi - lo, glm::dvec3(1e-300));
  std::vector<uint32_t> cell(rays.size()), start((size_t(1) << (3 * kBits)) + 1, 0);
  for (size_t i = 0; i < rays.size(); ++i) {
    const glm::uvec3 c = glm::min(glm::uvec3((rays[i].origin - lo) * scale), glm::uvec3((1u << kBits) - 1));
    cell[i] = nurbs::ray::morton3_cells(c.x, c.y, c.z);
    ++start[cell[i] + 1];
  }
  for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<uint32_t> order(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) order[start[cell[i]]++] = uint32_t(i);
  return order;
}

/// DACRT keeps no structure: each thread takes a contiguous part of the rays.
std::vector<nurbs::ray::Hit> dacrt_parallel(const nurbs::ray::Scene& scene, const std::vector<nurbs::ray::Ray>& rays,
                                            double t_min, int threads, const nurbs::ray::DacrtOptions& options,
                                            RayCasterFigures& f) {
  std::vector<std::vector<nurbs::ray::Hit>> parts(static_cast<size_t>(threads));
  std::vector<nurbs::ray::DacrtStats> stats(static_cast<size_t>(threads));
  std::vector<std::thread> pool;
  const size_t per = (rays.size() + size_t(threads) - 1) / size_t(threads);
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      const size_t a = std::min(rays.size(), size_t(t) * per), b = std::min(rays.size(), a + per);
      const std::vector<nurbs::ray::Ray> part(rays.begin() + long(a), rays.begin() + long(b));
      parts[size_t(t)] = nurbs::ray::cast_rays_dacrt(scene, part, t_min, options, &stats[size_t(t)]);
    });
  for (auto& t : pool) t.join();
  std::vector<nurbs::ray::Hit> hits;
  for (int t = 0; t < threads; ++t) {
    hits.insert(hits.end(), parts[size_t(t)].begin(), parts[size_t(t)].end());
    f.box_tests += stats[size_t(t)].box_tests;
    f.patch_tests += stats[size_t(t)].patch_tests;
  }
  return hits;
}

}  // namespace

const char* method_name(RayMethod method) {
  return method == RayMethod::Mesh ? "mesh" : method == RayMethod::Dacrt ? "dacrt" : "bvh";
}

std::string nearest_hits_doubt(RayMethod method) {
  if (method == RayMethod::Mesh) return {};
  return fmt::format(
      "the nearest hits are not certified: the {} method finds a ray's hits from the faces' bicubic approximations "
      "(Lemasson et al.), and may miss a hit where the ray grazes a face within their tolerance; the mesh method (on the "
      "CPU) certifies them",
      method_name(method));
}

RayCaster::RayCaster(std::vector<nurbs::TrimmedSurface> faces, const RayCasterOptions& options, gpgpu::Gpu* gpu)
    : options_(options) {
  if (gpu && options.method == RayMethod::Dacrt) throw std::invalid_argument("RayCaster: only the BVH runs on the GPU");
  const auto start = std::chrono::steady_clock::now();
  nurbs::ray::SceneOptions o;
  o.tolerance = options.tolerance;
  if (gpu) o.trim = nurbs::ray::SceneOptions::Trim::Cubics;
  // The mesh method's mesh is made beside the scene (both take every core; each has serial parts).
  std::future<std::unique_ptr<MeshDistance>> mesh;
  if (!gpu && options.method == RayMethod::Mesh)
    mesh = std::async(std::launch::async, [&faces, &options] {
      return std::make_unique<MeshDistance>(faces, options.mesh_tolerance * nurbs::ray::scene_size(faces),
                                            options.threads, nurbs::tess::TessellateOptions{}.max_cells, true);
    });
  try {
    scene_ = nurbs::ray::build_scene(faces, o);
  } catch (...) {
    if (mesh.valid()) mesh.wait();
    throw;
  }
  if (mesh.valid()) {
    mesh_ = mesh.get();
    figures_.mesh_triangles = mesh_->triangles();
  }
  if (gpu) {
    gpu_caster_ = std::make_unique<GpuRaycaster>(*gpu, scene_, options.bvh_build);
    gpu_caster_->set_threads(options.threads);  // its hits finished in double on the CPU
    figures_.bvh_gpu_seconds = gpu_caster_->build_stats().seconds;
    figures_.bvh_gpu_passes = gpu_caster_->build_stats().passes;
  } else {
    figures_.bytes_bvh = options.method != RayMethod::Dacrt ? scene_.bvh.nodes.size() * sizeof(nurbs::ray::BvhNode) : 0;
    figures_.bytes_patches = scene_.patches.size() * sizeof(nurbs::ray::BicubicPatch);
    for (const auto& t : scene_.trims)
      for (const auto& l : t.loops) figures_.bytes_trims += l.size() * sizeof(glm::dvec2);
  }
  figures_.build_seconds = nurbs::seconds_since(start);
}

RayCaster::~RayCaster() = default;

void RayCaster::rays_start_on_surfaces() {
  if (!gpu_caster_) return;
  figures_.near_guard = 4.0 * options_.tolerance * scene_.size;
  gpu_caster_->set_near_guard(figures_.near_guard);
  gpu_caster_->set_recast_misses(true);
}

std::vector<nurbs::ray::Hit> RayCaster::cast(const std::vector<nurbs::ray::Ray>& rays, double t_min,
                                             const std::function<void(long long, long long)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<nurbs::ray::Hit> out(rays.size());
  const size_t chunk_rays = gpu_caster_ ? gpu_caster_->rays_per_pass() : size_t(1) << 14;
  const int threads = nurbs::thread_count(options_.threads);
  RayCasterFigures& f = figures_;
  // The CPU's BVH and mesh methods take more than a chunk of rays along a Morton curve of their
  // origins: neighbouring rays walk the same nodes, triangles and patches, from the caches. Each
  // ray's hit does not depend on the order (DACRT sorts its rays itself; the GPU pass lays them out).
  std::vector<uint32_t> order;
  if (!gpu_caster_ && options_.method != RayMethod::Dacrt && rays.size() > chunk_rays) order = morton_cells(rays);
  for (size_t first = 0; first < rays.size(); first += chunk_rays) {
    const size_t last = std::min(rays.size(), first + chunk_rays);
    std::vector<nurbs::ray::Ray> chunk;
    chunk.reserve(last - first);
    for (size_t i = first; i < last; ++i) chunk.push_back(rays[order.empty() ? i : order[i]]);
    std::vector<nurbs::ray::Hit> hits;
    if (gpu_caster_) {
      hits = gpu_caster_->cast(chunk, t_min);
      const RaycastGpuStats& g = gpu_caster_->stats();  // of this cast
      f.box_tests += g.box_tests;
      f.patch_tests += g.patch_tests;
      f.gpu_seconds += g.gpu_seconds;
      f.finish_seconds += g.cpu_seconds;
      f.fallbacks += g.fallbacks;
      f.bytes_bvh = g.bytes_bvh, f.bytes_patches = g.bytes_patches, f.bytes_trims = g.bytes_trims;
    } else if (mesh_) {
      hits = cast_mesh(chunk, t_min, threads);
    } else if (options_.method == RayMethod::Dacrt) {
      hits = dacrt_parallel(scene_, chunk, t_min, threads, options_.dacrt, f);
    } else {
      nurbs::ray::TraversalStats stats;
      hits = nurbs::ray::cast_rays_parallel(scene_, chunk, t_min, nurbs::ray::Traversal::Stackless, threads, &stats);
      f.box_tests += stats.box_tests;
      f.patch_tests += stats.patch_tests;
    }
    for (size_t i = first; i < last; ++i) out[order.empty() ? i : order[i]] = hits[i - first];
    if (progress) progress(static_cast<long long>(last), static_cast<long long>(rays.size()));
  }
  f.rays += static_cast<long long>(rays.size());
  f.cast_seconds += nurbs::seconds_since(start);
  return out;
}

nurbs::ray::Hit RayCaster::first_on_way(const OnWay& way, const nurbs::ray::Ray& ray,
                                        const nurbs::ray::RayPlanes& planes, double t_min, double slack) const {
  // Newton from points along the way: from the crossings' (u, v) and between them, and from the
  // (u, v) the ray's motion along the face reaches from the anchor (its rate there); each start
  // near a root finds it. Near a grazing pair Newton converges slowly (the ray almost tangent):
  // more steps than a crossing's.
  constexpr int kStarts = 16, kSteps = 20;
  const nurbs::TrimmedSurface& face = scene_.faces[size_t(way.face)];
  const nurbs::SurfaceTangents d = nurbs::surface_tangents(face.surface, way.uv.x, way.uv.y);
  const glm::dvec2 rate = nurbs::ray::uv_rate(d.su, d.sv, ray.direction);
  std::vector<glm::dvec2> starts;
  for (int i = 0; i <= kStarts; ++i) {
    const double f = double(i) / kStarts, t = way.begin + f * (way.end - way.begin);
    if (way.to_uv) starts.push_back(way.uv + f * (*way.to_uv - way.uv));
    if (rate == rate) starts.push_back(way.uv + (t - way.at) * rate);
  }
  nurbs::ray::ExactHit first;
  for (const glm::dvec2 uv : starts) {
    const nurbs::ray::ExactHit e = scene_.refine(way.face, ray, planes, uv, kSteps);
    if (!e.ok || !(e.t > t_min) || e.t < way.begin - slack || e.t > way.end + slack || (first.ok && e.t >= first.t) ||
        !scene_.is_material_closed(way.face, e.uv))
      continue;
    first = e;
  }
  return earliest(way.face, first, ray, planes, t_min, way.begin);
}

nurbs::ray::Hit RayCaster::step_within(int face, glm::dvec2 uv, double lo, double hi, const nurbs::ray::Ray& ray,
                                       const nurbs::ray::RayPlanes& planes, double t_min, double t_crossing) const {
  const nurbs::ray::ExactHit e = scene_.refine(face, ray, planes, uv);
  if (!(e.ok && e.t > t_min && e.t >= lo && e.t <= hi && scene_.is_material_closed(face, e.uv))) return {};
  return earliest(face, e, ray, planes, t_min, t_crossing);
}

nurbs::ray::Hit RayCaster::earliest(int face, const nurbs::ray::ExactHit& found, const nurbs::ray::Ray& ray,
                                    const nurbs::ray::RayPlanes& planes, double t_min, double t_crossing) const {
  if (!found.ok) return {};
  const nurbs::ray::ExactHit back = scene_.look_back(face, ray, planes, found, t_min, scene_.material_test_closed(face));
  const nurbs::ray::ExactHit& e = back.ok ? back : found;
  return {e.t, face, e.uv, e.point, t_crossing};
}

nurbs::ray::Hit RayCaster::near_boundaries(MeshRayHit b, const nurbs::ray::Ray& ray,
                                           const nurbs::ray::RayPlanes& planes, double t_min, double step,
                                           const std::vector<OnWay>& from_start) const {
  // A ray grazing a face along its edge meets the face where its bicubic patches may not show it,
  // and may enter the face's slab there, past its rim, or run inside a narrow face's slab from one
  // of its tubes to another. From the first tube on, every crossing up to the nearest hit found
  // (at most 32): Newton on each face whose edge the ray passes, from the edge's ends and middle;
  // on the way through each slab the ray enters; and on the way from a face's first tube to the
  // crossing after its last one, or to where the ray leaves a slab it entered by a neighbour's tube.
  // `from_start`: the slabs that hold the ray's start, each searched from there to the face's
  // first crossing (or the nearest hit found).
  const nurbs::TriangleMesh& mesh = mesh_->tessellation().mesh;
  constexpr int kSteps = 20, kCrossings = 32;
  const double window = 64.0 * mesh_->eps();
  nurbs::ray::Hit h;
  std::vector<OnWay> tubes = from_start;  // per face, from its first tube to the crossing after its last
  std::vector<char> ended(from_start.size(), 0);  // of from_start: its face's crossing met
  std::vector<int> entered;  // faces whose slab the ray entered through a shell on the walk
  const double walk_start = b.t;  // the ray enters the tubes here: a slab inside them, unseen, from here on
  for (int k = 0; k < kCrossings && (b.boundary || b.triangle >= 0) && !(h.face >= 0 && b.t > h.t); ++k) {
    const MeshRayHit n = mesh_->first_hit(ray.origin, ray.direction, b.t + step, 3.4e38);
    const double next = n.boundary || n.triangle >= 0 ? n.t : b.t + window;
    if (b.boundary && b.face >= 0 && b.edge.x >= 0 && size_t(std::max(b.edge.x, b.edge.y)) < mesh.uv.size()) {
      const glm::dvec2 a = mesh.uv[size_t(b.edge.x)], c = mesh.uv[size_t(b.edge.y)];
      nurbs::ray::ExactHit first;
      for (const glm::dvec2 start : {a, c, 0.5 * (a + c)}) {
        const nurbs::ray::ExactHit e = scene_.refine(b.face, ray, planes, start, kSteps);
        if (e.ok && e.t > t_min && (!first.ok || e.t < first.t) && scene_.is_material_closed(b.face, e.uv)) first = e;
      }
      keep_nearer(h, earliest(b.face, first, ray, planes, t_min, b.t));
      const auto open = std::find_if(tubes.begin(), tubes.end(), [&](const OnWay& w) { return w.face == b.face; });
      if (open == tubes.end()) {
        tubes.push_back({b.face, b.t, next, 0.5 * (a + c), b.t, nullptr});
        ended.push_back(1);
      } else {
        open->end = next;
        ended[size_t(open - tubes.begin())] = 1;
      }
    } else if (b.triangle >= 0) {
      for (size_t i = 0; i < from_start.size(); ++i)
        if (!ended[i] && tubes[i].face == b.face) tubes[i].end = b.t, ended[i] = 1;
      if (b.entering) {
        entered.push_back(b.face);
        // Through the slab to its other side: Newton from the entry, where it stays on the way.
        const bool through = n.triangle >= 0 && !n.boundary && n.face == b.face && !n.entering;
        const nurbs::ray::Hit e = through && n.shell != b.shell
                                      ? step_within(b.face, b.uv, b.t - step, next + step, ray, planes, t_min, b.t)
                                      : nurbs::ray::Hit{};
        keep_nearer(h, e.face >= 0 ? e
                                   : first_on_way({b.face, b.t, next, b.uv, b.t, through ? &n.uv : nullptr}, ray,
                                                  planes, t_min, step));
      } else if (std::find(entered.begin(), entered.end(), b.face) == entered.end()) {
        // Leaving a slab the ray never entered through a shell: it came in by a tube (its own, or
        // a neighbour's that holds the slab's rim).
        const auto open = std::find_if(tubes.begin(), tubes.end(), [&](const OnWay& w) { return w.face == b.face; });
        const double from = open != tubes.end() ? open->begin : walk_start;
        keep_nearer(h, first_on_way({b.face, from, b.t, b.uv, b.t, nullptr}, ray, planes, t_min, step));
      }
    }
    b = n;
  }
  // A slab the ray started in and whose face it met no more: to the nearest hit, the next crossing
  // not walked, or where the ray leaves the mesh's box.
  const double last = h.face >= 0                       ? h.t
                      : b.boundary || b.triangle >= 0 ? b.t
                                                      : mesh_->box_exit(ray.origin, ray.direction);
  for (size_t i = 0; i < tubes.size(); ++i) {
    if (!ended[i]) tubes[i].end = last;
    keep_nearer(h, first_on_way(tubes[i], ray, planes, t_min, step));
  }
  return h;
}

std::vector<nurbs::ray::Hit> RayCaster::cast_mesh(const std::vector<nurbs::ray::Ray>& chunk, double t_min,
                                                  int threads) {
  std::vector<nurbs::ray::Hit> hits(chunk.size());
  std::vector<nurbs::ray::Hit> near_edge(chunk.size());  // hits beside the faces' edges that rays cast again may miss
  std::vector<char> again(chunk.size(), 0);
  const double eps = mesh_->eps(), window = 64.0 * eps;
  nurbs::parallel_for(
      chunk.size(), threads,
      [&](size_t k, int) {
        const nurbs::ray::Ray& ray = chunk[k];
        const nurbs::ray::RayPlanes planes = nurbs::ray::ray_planes(ray);
        const double step = 4.0 * mesh_->float_slack(ray.origin);
        nurbs::ray::Hit best;  // the nearest exact hit so far
        MeshRayHit m = mesh_->first_hit(ray.origin, ray.direction, t_min, 3.4e38);
        MeshRayHit edge;  // the first tube or ball on the way
        std::pair<MeshRayHit, double> way;  // the last slab entered, and the next crossing after it
        // A ray that starts inside slabs or tubes may meet their faces before it crosses any shell:
        // each such face is searched from the start to its first crossing (or the nearest hit).
        const SlabsAt start = mesh_->slabs_at(ray.origin + t_min * ray.direction);
        std::array<char, 8> open{};
        for (int i = 0; i < start.count; ++i) open[size_t(i)] = 1;
        std::array<char, 8> deferred{};  // a short way left to the step at the face's own crossing
        const auto step_from_start = [&](int i, double end) {
          deferred[size_t(i)] = 0;
          const MeshRayHit& s = start.faces[size_t(i)];
          keep_nearer(best, step_within(s.face, s.uv, t_min, end + step, ray, planes, t_min, t_min));
        };
        // `crossing`: end is the face's own crossing, where the step from it finds a hit that close
        // (else step_from_start does, below).
        const auto close = [&](int i, double end, bool crossing) {
          open[size_t(i)] = 0;
          const MeshRayHit& s = start.faces[size_t(i)];
          if (end - t_min > 8.0 * eps) {
            keep_nearer(best, first_on_way({s.face, t_min, end, s.uv, t_min, nullptr}, ray, planes, t_min, step));
          } else if (crossing) {
            deferred[size_t(i)] = 1;
          } else {
            step_from_start(i, end);
          }
        };
        const auto close_all = [&](double end) {
          for (int i = 0; i < start.count; ++i) {
            if (open[size_t(i)]) close(i, end, false);
            if (deferred[size_t(i)]) step_from_start(i, end);
          }
        };
        for (int tries = 0; tries < 8 && !start.more; ++tries) {
          if (m.triangle >= 0)
            for (int i = 0; i < start.count; ++i)
              if (open[size_t(i)] && start.faces[size_t(i)].face == m.face) close(i, m.t, true);
          // Near a face's edge before the next crossing (and before the best hit), the face may
          // reach the ray where its mesh does not (the mesh's boundary lies within eps inside the
          // face's): the BVH decides.
          if (m.boundary && !edge.boundary) edge = m;
          if (m.boundary && !(best.face >= 0 && m.t >= best.t)) break;
          // Every hit lies inside the slab, after a crossing: a crossing beyond the best hit ends
          // the search, and no crossing at all leaves no hit. But a ray that left a crossing behind
          // (its own face, a trimmed part) and finds none after it may have slipped along an edge
          // of the triangles in float, or the slab may be thinner than eps where the vertex normals
          // of a long triangle part: the BVH decides.
          if (best.face >= 0 && (m.boundary || m.triangle < 0 || m.t >= best.t)) {
            close_all(best.t);
            hits[k] = best;
            return;
          }
          // No crossing at all: no hit, unless the ray starts inside a slab (the BVH decides).
          if (m.triangle < 0 && tries == 0 && std::find(open.begin(), open.end(), 1) == open.end()) return;
          if (m.triangle < 0) break;
          const MeshRayHit n = mesh_->first_hit(ray.origin, ray.direction, m.t + step, 3.4e38);
          if (n.boundary && !edge.boundary) edge = n;
          // Through one face's slab, from m to n: the ray meets the face there an odd number of
          // times when it leaves on the other side, else an even number (none, or a grazing pair,
          // whose second Newton from m may find).
          const bool through = m.entering && n.triangle >= 0 && !n.boundary && n.face == m.face && !n.entering;
          if (through && n.shell == m.shell) {
            keep_nearer(best, first_on_way({m.face, m.t, n.t, m.uv, m.t, &n.uv}, ray, planes, t_min, step));
            m = mesh_->first_hit(ray.origin, ray.direction, n.t + step, 3.4e38);
            continue;
          }
          if (m.entering) way = {m, n.triangle >= 0 || n.boundary ? n.t : m.t + window};
          nurbs::ray::ExactHit e = scene_.refine(m.face, ray, planes, m.uv);
          const double next = n.triangle >= 0 || n.boundary ? n.t : m.t + window;
          const bool inside = e.ok && e.t >= m.t - step && e.t <= next + step;
          const bool near = e.ok && std::abs(e.t - m.t) <= window;
          bool searched = false;
          if ((through && !inside) || (m.entering && !near && next - m.t > window)) {
            // A hit lies on the way through, and Newton from m left it; or the ray runs a long way
            // inside the slab (grazing it) to the next crossing: the first hit there.
            const nurbs::ray::Hit h =
                first_on_way({m.face, m.t, next, m.uv, m.t, through ? &n.uv : nullptr}, ray, planes, t_min, step);
            if (h.face < 0) break;
            e = {true, h.uv, h.point, h.t};
            searched = true;
          } else if (!m.entering && !near &&
                     std::any_of(start.faces.begin(), start.faces.begin() + start.count,
                                 [&](const MeshRayHit& f) { return f.face == m.face; })) {
            // Leaving the slab the ray started in, searched up to here (or, a short way, by the step
            // from the start).
            for (int i = 0; i < start.count; ++i)
              if (deferred[size_t(i)] && start.faces[size_t(i)].face == m.face) step_from_start(i, m.t);
            m = n;
            continue;
          }
          // No exact hit near the crossing (a step that does not converge, or lands far away): the
          // face may still meet the ray inside the slab (grazing it): the BVH decides.
          if (!e.ok || (std::abs(e.t - m.t) > window && !searched)) break;
          if (e.t > t_min && (best.face < 0 || e.t < best.t) && scene_.is_material_closed(m.face, e.uv))
            best = {e.t, m.face, e.uv, e.point, m.t};
          m = n;  // the next crossing (the face behind t_min, or trimmed away here)
        }
        // The BVH casts the ray again, and may miss a grazing hit its patches do not show: the hits
        // Newton finds beside the edges it passes and on the way through the last slab it entered.
        for (int i = 0; i < start.count; ++i)
          if (deferred[size_t(i)]) step_from_start(i, t_min + window);
        std::vector<OnWay> from_start;
        for (int i = 0; i < start.count; ++i)
          if (open[size_t(i)]) from_start.push_back({start.faces[size_t(i)].face, t_min, 0.0, start.faces[size_t(i)].uv, t_min, nullptr});
        if (edge.boundary) {
          near_edge[k] = near_boundaries(edge, ray, planes, t_min, step, from_start);
        } else {
          for (OnWay& w : from_start) {
            w.end = m.triangle >= 0 ? m.t + window : mesh_->box_exit(ray.origin, ray.direction);
            keep_nearer(near_edge[k], first_on_way(w, ray, planes, t_min, step));
          }
        }
        keep_nearer(near_edge[k], best);
        if (way.first.triangle >= 0)
          keep_nearer(near_edge[k],
                      first_on_way({way.first.face, way.first.t, way.second, way.first.uv, way.first.t, nullptr}, ray,
                                   planes, t_min, step));
        again[k] = 1;
      },
      256);
  std::vector<nurbs::ray::Ray> rest;
  std::vector<size_t> where;
  for (size_t k = 0; k < chunk.size(); ++k)
    if (again[k]) rest.push_back(chunk[k]), where.push_back(k);
  if (!rest.empty()) {
    nurbs::ray::TraversalStats stats;
    const std::vector<nurbs::ray::Hit> h =
        nurbs::ray::cast_rays_parallel(scene_, rest, t_min, nurbs::ray::Traversal::Stackless, threads, &stats);
    for (size_t i = 0; i < rest.size(); ++i) {
      hits[where[i]] = h[i];
      keep_nearer(hits[where[i]], near_edge[where[i]]);
    }
    figures_.box_tests += stats.box_tests;
    figures_.patch_tests += stats.patch_tests;
    figures_.fallbacks += (long long)rest.size();
  }
  return hits;
}

}  // namespace queries
