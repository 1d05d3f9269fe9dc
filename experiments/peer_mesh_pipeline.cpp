// The mesh pipeline peer of experiments/mesh_pipeline.py: what practitioners run for bulk queries on
// a B-rep. OCCT reads the file (STEPControl_Reader / IGESControl_Reader) and meshes it with
// BRepMesh_IncrementalMesh at an absolute linear deflection D (in parallel); then
//  - points: CGAL's AABB_tree over the triangles (accelerated distance queries), the closest point
//    of every point, on every hardware thread (cloud-to-mesh distance, as CloudCompare computes it);
//  - rays: an Embree 3 scene of the triangles, the nearest hit of every ray (rtcIntersect1), on
//    every hardware thread;
//  - thickness: N samples over the mesh's area (seeded, area-weighted), from each a ray along the
//    inward triangle normal (faces oriented as OCCT orients them) cast by Embree from 1e-7 of the
//    size off the surface (as AnalysisSitus' ray thickness): the hit's t, -1 for none;
//  - clearance: the mesh against a copy of itself moved by (DX, DY, DZ), FCL's BVH-to-BVH distance
//    (OBBRSS, fcl::distance), as robotics and assembly tools compute mesh clearance.
// No nurbsgl code touches the geometry: the peer stays independent.
//  peer_mesh_pipeline MODEL --deflection D (--points FILE | --rays FILE | --thickness N |
//      --clearance DX,DY,DZ) [--out FILE] [--threads N]
// Prints JSON {triangles, read_seconds, mesh_seconds, build_seconds, query_seconds, queries,
// deflection} (clearance adds distance); --out writes one line per query: the distance (points),
// t (rays, thickness; -1: none).
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <fcl/fcl.h>
#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "peer_occt_read.h"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Point = Kernel::Point_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

struct Mesh {
  std::vector<double> xyz;       ///< vertices
  std::vector<unsigned> corners;  ///< three per triangle
};

/// Every face's triangulation in world coordinates, one mesh; triangles counter-clockwise seen
/// from the face's outside.
Mesh collect(const TopoDS_Shape& shape) {
  Mesh m;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face& face = TopoDS::Face(e.Current());
    TopLoc_Location location;
    const Handle(Poly_Triangulation)& t = BRep_Tool::Triangulation(face, location);
    if (t.IsNull()) continue;
    const gp_Trsf to_world = location.Transformation();
    const auto first = unsigned(m.xyz.size() / 3);
    for (int i = 1; i <= t->NbNodes(); ++i) {
      const gp_Pnt p = t->Node(i).Transformed(to_world);
      m.xyz.insert(m.xyz.end(), {p.X(), p.Y(), p.Z()});
    }
    for (int i = 1; i <= t->NbTriangles(); ++i) {
      int a = 0, b = 0, c = 0;
      t->Triangle(i).Get(a, b, c);
      if (face.Orientation() == TopAbs_REVERSED) std::swap(b, c);  // outward normals on a solid
      m.corners.insert(m.corners.end(), {first + unsigned(a - 1), first + unsigned(b - 1), first + unsigned(c - 1)});
    }
  }
  return m;
}

/// The numbers of one line (spaces or commas).
std::vector<double> numbers(std::string line) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::istringstream s(line);
  std::vector<double> out;
  double v = 0.0;
  while (s >> v) out.push_back(v);
  return out;
}

/// Rows of `per_row` numbers from a text file.
std::vector<double> read_rows(const std::string& path, size_t per_row) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::vector<double> out;
  std::string line;
  while (std::getline(in, line)) {
    const std::vector<double> row = numbers(line);
    if (!row.empty() && row.size() != per_row)
      throw std::runtime_error(path + ": a line of " + std::to_string(row.size()) + " numbers");
    out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

template <class F>
void parallel(size_t n, unsigned threads, F f) {
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (size_t i = t; i < n; i += threads) f(i);
    });
  for (std::thread& th : pool) th.join();
}

double diagonal(const Mesh& m) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t i = 0; i < m.xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], m.xyz[i]), hi[i % 3] = std::max(hi[i % 3], m.xyz[i]);
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/// `n` rays (ox oy oz dx dy dz): origins uniform over the mesh's area (seed 3), directions the
/// inward unit normals of their triangles.
std::vector<double> inward_rays(const Mesh& m, long n) {
  const size_t triangles = m.corners.size() / 3;
  auto corner = [&](size_t k, int c) {
    const unsigned i = m.corners[3 * k + size_t(c)];
    return std::array<double, 3>{m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]};
  };
  std::vector<double> area(triangles), normal(3 * triangles);
  for (size_t k = 0; k < triangles; ++k) {
    const auto a = corner(k, 0), b = corner(k, 1), c = corner(k, 2);
    const double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, f[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double x[3] = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0]};
    const double len = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    area[k] = 0.5 * len;
    for (int i = 0; i < 3; ++i) normal[3 * k + size_t(i)] = len > 0.0 ? -x[i] / len : 0.0;
  }
  std::discrete_distribution<size_t> pick(area.begin(), area.end());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> rays;
  rays.reserve(6 * size_t(n));
  for (long i = 0; i < n; ++i) {
    const size_t k = pick(rng);
    double s = unit(rng), t = unit(rng);
    if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
    const auto a = corner(k, 0), b = corner(k, 1), c = corner(k, 2);
    for (int d = 0; d < 3; ++d) rays.push_back(a[size_t(d)] + s * (b[size_t(d)] - a[size_t(d)]) + t * (c[size_t(d)] - a[size_t(d)]));
    for (int d = 0; d < 3; ++d) rays.push_back(normal[3 * k + size_t(d)]);
  }
  return rays;
}

/// The nearest hit t (> tnear; -1 for none) of every ray (ox oy oz dx dy dz) on an Embree scene of
/// the mesh, on `threads` threads.
std::vector<double> cast(const Mesh& mesh, const std::vector<double>& r, double tnear, unsigned threads,
                         double& build_seconds, double& query_seconds) {
  const size_t triangles = mesh.corners.size() / 3;
  auto t0 = peer::Clock::now();
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.xyz.size() / 3));
  for (size_t i = 0; i < mesh.xyz.size(); ++i) v[i] = float(mesh.xyz[i]);
  auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), triangles));
  std::copy(mesh.corners.begin(), mesh.corners.end(), ix);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  build_seconds = peer::seconds_since(t0);
  std::vector<double> answers(r.size() / 6);
  t0 = peer::Clock::now();
  parallel(answers.size(), threads, [&](size_t i) {
    const double* q = &r[6 * i];
    const double len = std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5]);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit h{};
    h.ray.org_x = float(q[0]), h.ray.org_y = float(q[1]), h.ray.org_z = float(q[2]);
    h.ray.dir_x = float(q[3] / len), h.ray.dir_y = float(q[4] / len), h.ray.dir_z = float(q[5] / len);
    h.ray.tnear = float(tnear), h.ray.tfar = std::numeric_limits<float>::infinity();
    h.ray.mask = ~0u;
    h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &h);
    answers[i] = h.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0 : double(h.ray.tfar);
  });
  query_seconds = peer::seconds_since(t0);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return answers;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Mesh pipeline peer: OCCT BRepMesh, then CGAL AABB_tree (points) or Embree (rays)"};
  std::string model, points, rays, out, clearance;
  long samples = 0;
  double deflection = 0.0;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  app.add_option("MODEL", model)->required();
  app.add_option("--deflection", deflection, "BRepMesh linear deflection, model units")->required();
  app.add_option("--points", points, "x y z per line");
  app.add_option("--rays", rays, "ox oy oz dx dy dz per line");
  app.add_option("--thickness", samples, "samples over the mesh's area, a ray inward from each");
  app.add_option("--clearance", clearance, "DX,DY,DZ: the distance to a copy moved by this");
  app.add_option("--out", out, "one distance (or t, -1 for a miss) per line");
  app.add_option("--threads", threads);
  CLI11_PARSE(app, argc, argv);
  if (int(!points.empty()) + int(!rays.empty()) + int(samples > 0) + int(!clearance.empty()) != 1)
    return std::fprintf(stderr, "give one of --points, --rays, --thickness and --clearance\n"), 2;
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));  // the readers' chatter
  try {
    nlohmann::json j;
    double read_seconds = 0.0;
    const TopoDS_Shape shape = peer::read_shape(model, read_seconds);
    auto t0 = peer::Clock::now();
    BRepMesh_IncrementalMesh mesher(shape, deflection, false, 0.5, true);
    const Mesh mesh = collect(shape);
    const double mesh_seconds = peer::seconds_since(t0);
    const size_t triangles = mesh.corners.size() / 3;
    std::vector<double> answers;
    double build_seconds = 0.0, query_seconds = 0.0;
    if (!points.empty()) {
      const std::vector<double> p = read_rows(points, 3);
      t0 = peer::Clock::now();
      std::vector<Triangle> tri;
      tri.reserve(triangles);
      const auto vertex = [&](unsigned i) { return Point(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]); };
      for (size_t k = 0; k < triangles; ++k)
        tri.emplace_back(vertex(mesh.corners[3 * k]), vertex(mesh.corners[3 * k + 1]), vertex(mesh.corners[3 * k + 2]));
      Tree tree(tri.begin(), tri.end());
      tree.accelerate_distance_queries();
      build_seconds = peer::seconds_since(t0);
      answers.resize(p.size() / 3);
      t0 = peer::Clock::now();
      parallel(answers.size(), threads, [&](size_t i) {
        const Point q(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        answers[i] = std::sqrt(tree.squared_distance(q));
      });
      query_seconds = peer::seconds_since(t0);
    } else if (!rays.empty()) {
      answers = cast(mesh, read_rows(rays, 6), 0.0, threads, build_seconds, query_seconds);
    } else if (samples > 0) {
      t0 = peer::Clock::now();
      const std::vector<double> r = inward_rays(mesh, samples);
      const double sample_seconds = peer::seconds_since(t0);
      answers = cast(mesh, r, 1e-7 * diagonal(mesh), threads, build_seconds, query_seconds);
      build_seconds += sample_seconds;
    } else {
      t0 = peer::Clock::now();
      const std::vector<double> m = numbers(clearance);
      if (m.size() != 3) throw std::runtime_error("--clearance '" + clearance + "': not three numbers");
      auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Vector3d> vertices;
      for (size_t i = 0; i < mesh.xyz.size(); i += 3) vertices.emplace_back(mesh.xyz[i], mesh.xyz[i + 1], mesh.xyz[i + 2]);
      std::vector<fcl::Triangle> tris;
      for (size_t k = 0; k < triangles; ++k)
        tris.emplace_back(mesh.corners[3 * k], mesh.corners[3 * k + 1], mesh.corners[3 * k + 2]);
      model->beginModel();
      model->addSubModel(vertices, tris);
      model->endModel();
      fcl::Transform3d moved = fcl::Transform3d::Identity();
      moved.translation() = fcl::Vector3d(m[0], m[1], m[2]);
      const fcl::CollisionObjectd a(model, fcl::Transform3d::Identity()), b(model, moved);
      build_seconds = peer::seconds_since(t0);
      t0 = peer::Clock::now();
      fcl::DistanceRequestd request;
      fcl::DistanceResultd result;
      fcl::distance(&a, &b, request, result);
      query_seconds = peer::seconds_since(t0);
      answers = {result.min_distance};
      j["distance"] = result.min_distance;
    }
    if (!out.empty()) {
      std::ofstream o(out);
      for (const double a : answers) o << fmt::format("{:.17g}\n", a);
    }
    j.update({{"triangles", triangles},     {"read_seconds", read_seconds},   {"mesh_seconds", mesh_seconds},
         {"build_seconds", build_seconds}, {"query_seconds", query_seconds}, {"queries", answers.size()},
         {"deflection", deflection},   {"threads", threads}});
    std::printf("%s\n", j.dump(2).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_mesh_pipeline: %s\n", e.what());
    return 2;
  }
  return 0;
}
