#include "nurbs/tessellation/mesh_check.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstdint>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

#include "nurbs/curve_eval.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/project_curve.h"
#include "nurbs/surface_eval.h"
#include "nurbs/surface_project.h"
#include "nurbs/tessellation/triangle_bvh.h"
#include "nurbs/trim_classify.h"

namespace nurbs::tess {
namespace {

using Tri = std::array<glm::dvec3, 3>;

// Grid samples per direction on the smallest faces (a face's grid follows its size down to this).
constexpr int kMinGrid = 8;

// Per triangle, which of its seven mesh samples (bits 0-2: corners a, b, c; 3-5: midpoints of ab,
// bc, ca; 6: centroid) it measures: each vertex and each edge (by its vertex indices) by the
// first triangle that has it, so that a point shared by several triangles is measured once.
std::vector<std::uint8_t> distinct_samples(const TriangleMesh& mesh) {
  const size_t nt = mesh.triangles.size();
  std::vector<std::uint8_t> out(nt, 1 << 6);
  std::vector<size_t> vertex_first(mesh.positions.size(), nt);
  std::vector<std::pair<std::uint64_t, size_t>> edges;  // (vertex pair, triangle * 3 + side)
  edges.reserve(3 * nt);
  for (size_t k = 0; k < nt; ++k) {
    const glm::ivec3 t = mesh.triangles[k];
    const int v[3] = {t.x, t.y, t.z};
    for (int i = 0; i < 3; ++i) {
      size_t& first = vertex_first[size_t(v[i])];
      if (first == nt) first = k, out[k] |= std::uint8_t(1 << i);
      const auto lo = std::uint64_t(std::min(v[i], v[(i + 1) % 3])), hi = std::uint64_t(std::max(v[i], v[(i + 1) % 3]));
      edges.emplace_back(lo << 32 | hi, 3 * k + size_t(i));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (size_t e = 0; e < edges.size(); ++e)
    if (e == 0 || edges[e].first != edges[e - 1].first) out[edges[e].second / 3] |= std::uint8_t(8 << (edges[e].second % 3));
  return out;
}

struct Sample {
  glm::dvec3 p;
  glm::dvec2 uv;
  int face;
};

glm::dvec3 at(const Surface& s, glm::dvec2 uv) {
  const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
  return surface_point(s, std::clamp(uv.x, du.min, du.max), std::clamp(uv.y, dv.min, dv.max));
}

/// Points of S(c(t)) for t in [t0, t1], bisected until each chord's midpoint is within `tol` of the
/// curve (depth <= 16), appended without the first point.
void boundary_points(const Surface& s, const std::function<glm::dvec2(double)>& c, double t0, double t1, double tol,
                     int depth, std::vector<glm::dvec3>& out) {
  const glm::dvec3 a = at(s, c(t0)), b = at(s, c(t1));
  const double tm = 0.5 * (t0 + t1);
  const glm::dvec3 m = at(s, c(tm));
  if (depth >= 16 || (depth >= 2 && glm::length(m - 0.5 * (a + b)) <= tol)) {
    out.push_back(b);
    return;
  }
  boundary_points(s, c, t0, tm, tol, depth + 1, out);
  boundary_points(s, c, tm, t1, tol, depth + 1, out);
}

/// The face's boundary as 3D polylines: every trim curve, or the four domain edges when untrimmed.
std::vector<std::vector<glm::dvec3>> face_boundary(const TrimmedSurface& f, double tol) {
  std::vector<std::vector<glm::dvec3>> lines;
  const Surface& s = f.surface;
  auto trace = [&](const std::function<glm::dvec2(double)>& c, double t0, double t1) {
    std::vector<glm::dvec3> line{at(s, c(t0))};
    boundary_points(s, c, t0, t1, tol, 0, line);
    lines.push_back(std::move(line));
  };
  if (f.loops.empty()) {
    const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
    const glm::dvec2 q[4] = {{du.min, dv.min}, {du.max, dv.min}, {du.max, dv.max}, {du.min, dv.max}};
    for (int e = 0; e < 4; ++e) trace([&](double t) { return glm::mix(q[e], q[(e + 1) % 4], t); }, 0.0, 1.0);
    return lines;
  }
  for (const TrimLoop& loop : f.loops)
    for (const Curve2& c : loop.curves) {
      const Interval d = curve_domain(c);
      trace([&](double t) { return curve_point(c, t); }, d.min, d.max);
    }
  return lines;
}

}  // namespace

Deviation measure_deviation(const std::vector<TrimmedSurface>& faces, const TriangleMesh& mesh,
                            const DeviationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Deviation r;
  double size = 0.0;
  for (const auto& f : faces) {
    size = std::max(size, control_box(f.surface).diagonal());
  }
  const double tol = options.boundary_tolerance > 0 ? options.boundary_tolerance : 1e-6 * size;
  const int threads = thread_count(options.threads);

  // Face samples: the material points of a (u, v) grid and the boundary polylines' points.
  std::vector<Sample> samples;
  std::vector<TrimPolygons> trims(faces.size());
  std::vector<BandedTrim> banded(faces.size());  // the same classification, in far fewer steps
  std::vector<Tri> boundary;
  // One density of grid samples in space: the largest face (control-box diagonal) with samples x
  // samples, a smaller one with as many per length, at least kMinGrid each way (they also seed
  // Newton for the mesh samples below, where sparse seeds leave Newton's upper bounds far above the
  // distance). A model of many small faces costs as many samples as its area needs, not samples^2
  // per face.
  std::vector<char> to_mesh;  // per sample: measured from the surface to the mesh
  std::vector<double> extent(faces.size());
  double largest = 0.0;
  for (size_t fi = 0; fi < faces.size(); ++fi)
    largest = std::max(largest, extent[fi] = control_box(faces[fi].surface).diagonal());
  const int n = std::max(2, options.samples);
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    const TrimmedSurface& f = faces[fi];
    const int m = largest > 0.0 ? std::clamp(int(std::ceil(n * extent[fi] / largest)), std::min(kMinGrid, n), n) : n;
    const Interval du = surface_domain_u(f.surface), dv = surface_domain_v(f.surface);
    trims[fi] = flatten_trim(f, mesh_flatten_tolerance(f.surface));
    banded[fi] = BandedTrim(trims[fi]);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const glm::dvec2 uv(du.min + du.width() * i / (m - 1), dv.min + dv.width() * j / (m - 1));
        if (f.loops.empty() || banded[fi].is_material(uv)) {
          samples.push_back({surface_point(f.surface, uv.x, uv.y), uv, int(fi)});
          to_mesh.push_back(1);
        }
      }
    for (const auto& line : face_boundary(f, tol))
      for (size_t k = 0; k + 1 < line.size(); ++k) {
        boundary.push_back({line[k], line[k + 1], line[k + 1]});
        samples.push_back({line[k], glm::dvec2(0.0), -1 - int(fi)});  // on the face, (u, v) unknown
        to_mesh.push_back(1);
      }
  }

  // Surface to mesh.
  std::vector<Tri> tris;
  tris.reserve(mesh.triangles.size());
  for (const glm::ivec3& t : mesh.triangles)
    tris.push_back({mesh.positions[size_t(t.x)], mesh.positions[size_t(t.y)], mesh.positions[size_t(t.z)]});
  const TriangleBvh mesh_bvh(std::move(tris));
  std::vector<double> worst(size_t(threads), 0.0);
  std::vector<int> worst_face(size_t(threads), -1);
  // Per thread and face, the face's worst sample (reduced below).
  std::vector<std::vector<double>> face_worst(size_t(threads), std::vector<double>(faces.size(), 0.0));
  parallel_for((long long)samples.size(), threads,
               [&](long long k, int t) {
                 if (!to_mesh[size_t(k)]) return;
                 const int f = samples[size_t(k)].face >= 0 ? samples[size_t(k)].face : -1 - samples[size_t(k)].face;
                 // A sample within the face's worst so far changes no maximum: the exact distance
                 // only for the others.
                 double& face_max = face_worst[size_t(t)][size_t(f)];
                 if (face_max > 0.0 && mesh_bvh.any_within(samples[size_t(k)].p, face_max)) return;
                 const double d = mesh_bvh.closest(samples[size_t(k)].p).distance;
                 face_max = std::max(face_max, d);
                 if (d > worst[size_t(t)]) worst[size_t(t)] = d, worst_face[size_t(t)] = f;
               },
               256);
  for (int t = 0; t < threads; ++t)
    if (worst[size_t(t)] >= r.surface_to_mesh)
      r.surface_to_mesh = worst[size_t(t)], r.worst_face = worst_face[size_t(t)];
  const auto reduce = [&](std::vector<double>& out) {
    out.assign(faces.size(), 0.0);
    for (const auto& per_thread : face_worst)
      for (size_t f = 0; f < faces.size(); ++f) out[f] = std::max(out[f], per_thread[f]);
    for (auto& per_thread : face_worst) std::fill(per_thread.begin(), per_thread.end(), 0.0);
  };
  reduce(r.face_surface_to_mesh);
  r.surface_samples = (long long)std::count(to_mesh.begin(), to_mesh.end(), 1);

  // Mesh to surface: vertices, edge midpoints and centroids.
  std::vector<Sample> grid_samples;
  std::vector<Tri> points;
  for (const Sample& s : samples)
    if (s.face >= 0) grid_samples.push_back(s), points.push_back({s.p, s.p, s.p});
  // The nearest grid sample seeds Newton for mesh samples without a face of their own (another
  // tool's mesh); with one, the loop over the faces within reach below seeds every face alike.
  const bool own_faces = !mesh.uv.empty() && !mesh.triangle_face.empty() &&
                         std::all_of(mesh.triangle_face.begin(), mesh.triangle_face.end(), [&](int f) {
                           return f >= 0 && size_t(f) < faces.size();
                         });
  const TriangleBvh sample_bvh(own_faces ? std::vector<Tri>{} : std::move(points)), boundary_bvh(std::move(boundary));
  // Per face: its grid samples (to seed Newton on every face near a mesh sample, not only on the
  // face of the nearest sample, which near an edge is often the wrong one) and its box.
  std::vector<TriangleBvh> face_samples;
  std::vector<std::vector<const Sample*>> face_sample_of(faces.size());
  std::vector<std::array<glm::dvec3, 2>> face_box(faces.size(), {glm::dvec3(1e300), glm::dvec3(-1e300)});
  {
    std::vector<std::vector<Tri>> pts(faces.size());
    for (const Sample& s : grid_samples) {
      pts[size_t(s.face)].push_back({s.p, s.p, s.p});
      face_sample_of[size_t(s.face)].push_back(&s);
    }
    for (size_t f = 0; f < faces.size(); ++f) {
      for (const glm::dvec3& p : faces[f].surface.points)
        face_box[f][0] = glm::min(face_box[f][0], p), face_box[f][1] = glm::max(face_box[f][1], p);
      face_samples.emplace_back(std::move(pts[f]));
    }
  }
  // The faces' boxes in a hierarchy of their own (a box as the segment between its corners).
  std::vector<Tri> box_segments;
  for (const auto& b : face_box) box_segments.push_back({b[0], b[1], b[1]});
  const TriangleBvh face_boxes(std::move(box_segments));
  const long long nt = (long long)mesh.triangles.size();
  const std::vector<std::uint8_t> measured = distinct_samples(mesh);
  std::fill(worst.begin(), worst.end(), 0.0);
  parallel_for(
      nt, threads,
      [&](long long k, int t) {
        const glm::ivec3 tri = mesh.triangles[size_t(k)];
        const glm::dvec3 a = mesh.positions[size_t(tri.x)], b = mesh.positions[size_t(tri.y)],
                         c = mesh.positions[size_t(tri.z)];
        const glm::dvec3 q[7] = {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (a + b + c) / 3.0};
        // The mesh's own (u, v) first: Newton from there gives a near-final distance, so the
        // boundary, the nearest sample and the other faces are searched only within it.
        // A corner welded to another face's vertex (T-junctions closed) carries that face's (u, v):
        // the triangle's own (u, v) then stands only for the corners of its own face.
        const int corner[3] = {tri.x, tri.y, tri.z};
        const auto corner_face = [&](int c) {
          return mesh.vertex_face.size() == mesh.positions.size() ? mesh.vertex_face[size_t(corner[c])]
                                                                   : mesh.triangle_face[size_t(k)];
        };
        const bool own_uv = !mesh.uv.empty() && !mesh.triangle_face.empty() && mesh.triangle_face[size_t(k)] >= 0 &&
                            corner_face(0) == mesh.triangle_face[size_t(k)] &&
                            corner_face(1) == mesh.triangle_face[size_t(k)] &&
                            corner_face(2) == mesh.triangle_face[size_t(k)];
        glm::dvec2 uvs[7];
        if (own_uv) {
          const glm::dvec2 ua = mesh.uv[size_t(tri.x)], ub = mesh.uv[size_t(tri.y)], uc = mesh.uv[size_t(tri.z)];
          const glm::dvec2 own[7] = {ua, ub, uc, 0.5 * (ua + ub), 0.5 * (ub + uc), 0.5 * (uc + ua), (ua + ub + uc) / 3.0};
          std::copy(own, own + 7, uvs);
        }
        for (int i = 0; i < 7; ++i) {
          if (!(measured[size_t(k)] & (1 << i))) continue;
          double d = std::numeric_limits<double>::infinity();
          auto newton = [&](int face, glm::dvec2 uv) {
            const TrimmedSurface& f = faces[size_t(face)];
            const Interval du = surface_domain_u(f.surface), dv = surface_domain_v(f.surface);
            auto attempt = [&](glm::dvec2 seed) {
              const glm::dvec2 foot = project_point(f.surface, q[i], seed, 12);
              const double e = glm::length(surface_point(f.surface, foot.x, foot.y) - q[i]);
              if (e < d && (f.loops.empty() || banded[size_t(face)].is_material(foot))) d = e;
              return foot;
            };
            // A seed on the far side of a periodic face's seam walks into the domain edge: the seed
            // mirrored in u (and in v) starts on the near side.
            const glm::dvec2 foot = attempt(uv);
            if (foot.x <= du.min || foot.x >= du.max || foot.y <= dv.min || foot.y >= dv.max) {
              attempt({du.min + du.max - uv.x, uv.y});
              attempt({uv.x, dv.min + dv.max - uv.y});
            }
          };
          const int own = mesh.triangle_face.empty() ? -1 : mesh.triangle_face[size_t(k)];
          if (own_uv) {
            newton(own, uvs[i]);
            // The searches below only lower d: a sample already within its face's worst so far
            // (this thread's, at most the reduced one) changes no maximum.
            if (d <= face_worst[size_t(t)][size_t(own)]) continue;
            // Newton from the triangle's corners too: near a pole or an apex the corners' angles
            // differ by up to a half turn, and their mean lands far from the sample.
            for (int c = 0; c < 3 && d > face_worst[size_t(t)][size_t(own)]; ++c) newton(own, uvs[c]);
            if (d <= face_worst[size_t(t)][size_t(own)]) continue;
          } else if (own >= 0 && size_t(own) < faces.size()) {
            // Corners welded to other faces' vertices: their (u, v) belong to those faces. Newton
            // on the own face from its own corners, its nearest grid sample, and last from a search
            // of the whole surface.
            const double& worst_here = face_worst[size_t(t)][size_t(own)];
            for (int c = 0; c < 3 && d > worst_here; ++c)
              if (corner_face(c) == own) newton(own, mesh.uv[size_t(corner[c])]);
            if (d > worst_here) {
              const TriangleBvh::Hit h = face_samples[size_t(own)].closest(q[i]);
              if (h.triangle >= 0) newton(own, face_sample_of[size_t(own)][size_t(h.triangle)]->uv);
            }
            if (d > worst_here) newton(own, closest_parameter(faces[size_t(own)].surface, q[i]));
            if (d <= worst_here) continue;
          }
          d = std::min(d, boundary_bvh.closest(q[i], d).distance);
          const TriangleBvh::Hit near = sample_bvh.closest(q[i], d);
          if (near.triangle >= 0) {
            const Sample& s = grid_samples[size_t(near.triangle)];
            d = std::min(d, near.distance);
            newton(s.face, s.uv);
          }
          // Every other face whose control box (it holds the face) is nearer than the best so far.
          face_boxes.for_each_near(q[i], d, [&](int f) {
            if (TriangleBvh::box_distance(q[i], face_box[size_t(f)][0], face_box[size_t(f)][1]) >= d ||
                face_samples[size_t(f)].size() == 0)
              return;
            const TriangleBvh::Hit h = face_samples[size_t(f)].closest(q[i]);
            if (h.triangle < 0) return;
            d = std::min(d, h.distance);  // a material point of the face
            newton(f, face_sample_of[size_t(f)][size_t(h.triangle)]->uv);
          });
          worst[size_t(t)] = std::max(worst[size_t(t)], d);
          if (own >= 0 && size_t(own) < faces.size())
            face_worst[size_t(t)][size_t(own)] = std::max(face_worst[size_t(t)][size_t(own)], d);
        }
      },
      256);
  for (double w : worst) r.mesh_to_surface = std::max(r.mesh_to_surface, w);
  reduce(r.face_mesh_to_surface);
  for (std::uint8_t m : measured) r.mesh_samples += std::popcount(m);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

namespace {

/// The triangles of each face (by triangle_face); faces without trim loops left out when
/// `trimmed_only`. Empty when the mesh carries no (u, v) or faces.
std::vector<std::vector<size_t>> triangles_by_face(const std::vector<TrimmedSurface>& faces, const TriangleMesh& mesh,
                                                   bool trimmed_only) {
  std::vector<std::vector<size_t>> of_face(faces.size());
  if (mesh.uv.empty() || mesh.triangle_face.empty() || mesh.vertex_face.empty()) return of_face;
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    const int f = mesh.triangle_face[k];
    if (f >= 0 && size_t(f) < faces.size() && (!trimmed_only || !faces[size_t(f)].loops.empty()))
      of_face[size_t(f)].push_back(k);
  }
  return of_face;
}

/// Over the triangles of face f whose three corners are its own (a shared corner's (u, v) is another
/// face's): sample(p, x, corners) at the centroid and the edge midpoints ((u, v) p, point x); the
/// largest value into out.distance, the triangles where it passes `distance` counted.
template <class Sample>
void measure_triangles(const TriangleMesh& mesh, const std::vector<size_t>& triangles, size_t f, double distance,
                       OutsideTrim& out, Sample&& sample, bool centroids_only = false) {
  for (const size_t k : triangles) {
    const glm::ivec3 t = mesh.triangles[k];
    if (mesh.vertex_face[size_t(t.x)] != int(f) || mesh.vertex_face[size_t(t.y)] != int(f) ||
        mesh.vertex_face[size_t(t.z)] != int(f))
      continue;
    const std::array<glm::dvec2, 3> c = {mesh.uv[size_t(t.x)], mesh.uv[size_t(t.y)], mesh.uv[size_t(t.z)]};
    const glm::dvec3 pa = mesh.positions[size_t(t.x)], pb = mesh.positions[size_t(t.y)],
                     pc = mesh.positions[size_t(t.z)];
    const double centroid = sample((c[0] + c[1] + c[2]) / 3.0, (pa + pb + pc) / 3.0, c);
    const double d = centroids_only ? centroid
                                    : std::max({centroid, sample(0.5 * (c[0] + c[1]), 0.5 * (pa + pb), c),
                                                sample(0.5 * (c[1] + c[2]), 0.5 * (pb + pc), c),
                                                sample(0.5 * (c[2] + c[0]), 0.5 * (pc + pa), c)});
    out.distance = std::max(out.distance, d);
    out.triangles += d > distance;
  }
}

}  // namespace

std::vector<OutsideTrim> triangles_outside_trim(const std::vector<TrimmedSurface>& faces, const TriangleMesh& mesh,
                                                double distance, bool centroids_only) {
  std::vector<OutsideTrim> out(faces.size());
  const std::vector<std::vector<size_t>> of_face = triangles_by_face(faces, mesh, true);
  // One face at a time on every hardware thread (each writes its own out[f]).
  parallel_for(
      faces.size(), 0,
      [&](long long face, int) {
        const auto f = size_t(face);
        if (of_face[f].empty()) return;
        const Surface& s = faces[f].surface;
        const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
        // Flattened within 1e-5 of the domain: a sample misjudged by it lies that close to a loop, far
        // below the estimate's threshold.
        const TrimPolygons trim = flatten_trim(faces[f], 1e-5 * std::max(du.width(), dv.width()));
        const BandedTrim banded(trim);
        std::vector<std::vector<glm::dvec3>> boundary;  // the face's boundary in space, built when first needed
        // A sample's distance outside the material: 0 when material; else, when its (u, v) distance to
        // the loops times the larger first derivative there (a cheap estimate) passes a quarter of
        // `distance`, the distance of its point in space to the face's boundary.
        const auto outside = [&](glm::dvec2 p, const glm::dvec3& x, const std::array<glm::dvec2, 3>&) {
          if (banded.is_material(p)) return 0.0;
          const double near = distance_to_loops(trim, p);
          const SurfaceDerivatives sd =
              surface_derivatives(s, std::clamp(p.x, du.min, du.max), std::clamp(p.y, dv.min, dv.max));
          if (near * std::max(glm::length(sd.su), glm::length(sd.sv)) <= 0.25 * distance) return 0.0;
          if (boundary.empty()) boundary = face_boundary(faces[f], 1e-3 * distance);
          double best = 1e300;
          for (const auto& line : boundary)
            for (size_t k = 0; k + 1 < line.size(); ++k) {
              const glm::dvec3 a = line[k], d = line[k + 1] - a;
              const double len2 = glm::dot(d, d);
              const double t = len2 > 0.0 ? std::clamp(glm::dot(x - a, d) / len2, 0.0, 1.0) : 0.0;
              best = std::min(best, glm::distance(a + t * d, x));
            }
          return best;
        };
        measure_triangles(mesh, of_face[f], f, distance, out[f], outside, centroids_only);
      },
      1);
  return out;
}

std::vector<OutsideTrim> triangles_off_surface(const std::vector<TrimmedSurface>& faces, const TriangleMesh& mesh,
                                               double face_distance, const std::vector<double>& extra) {
  std::vector<OutsideTrim> out(faces.size());
  const std::vector<std::vector<size_t>> of_face = triangles_by_face(faces, mesh, false);
  parallel_for(
      faces.size(), 0,
      [&](long long face, int) {
        const auto f = size_t(face);
        const double distance = face_distance + (f < extra.size() ? extra[f] : 0.0);
        const Surface& s = faces[f].surface;
        const Interval du = surface_domain_u(s), dv = surface_domain_v(s);
        // Newton starts from the sample's (u, v) and the triangle's corners'.
        const auto off = [&](glm::dvec2 p, const glm::dvec3& x, const std::array<glm::dvec2, 3>& corner) {
          p = {std::clamp(p.x, du.min, du.max), std::clamp(p.y, dv.min, dv.max)};
          double d = glm::distance(surface_point(s, p.x, p.y), x);
          // Over: Newton from there and from each corner (a welded vertex on a periodic seam carries
          // one side's (u, v), and the interpolated one then lies across the surface).
          for (int k = -1; k < 3 && d > distance; ++k) {
            const glm::dvec2 q = project_point(s, x, k < 0 ? p : corner[k], 20);
            d = std::min(d, glm::distance(surface_point(s, q.x, q.y), x));
          }
          return d;
        };
        measure_triangles(mesh, of_face[f], f, distance, out[f], off);
      },
      1);
  return out;
}

TriangleMesh face_submesh(const TriangleMesh& mesh, int face) {
  TriangleMesh out;
  std::vector<int> index(mesh.positions.size(), -1);
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    if (mesh.triangle_face.empty() || mesh.triangle_face[k] != face) continue;
    glm::ivec3 t = mesh.triangles[k];
    for (int c = 0; c < 3; ++c) {
      int& v = index[size_t(t[c])];
      if (v < 0) {
        v = int(out.positions.size());
        out.positions.push_back(mesh.positions[size_t(t[c])]);
        if (!mesh.uv.empty()) out.uv.push_back(mesh.uv[size_t(t[c])]);
        if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[size_t(t[c])]);
        out.vertex_face.push_back(0);
      }
      t[c] = v;
    }
    out.triangles.push_back(t);
    out.triangle_face.push_back(0);
  }
  return out;
}

}  // namespace nurbs::tess
