// The mesh pipeline peer of experiments/mesh_pipeline.py: what practitioners run for bulk queries on
// a B-rep. OCCT reads the file (STEPControl_Reader / IGESControl_Reader) and meshes it with
// BRepMesh_IncrementalMesh at an absolute linear deflection D (in parallel); then
//  - points: CGAL's AABB_tree over the triangles (accelerated distance queries), the closest point
//    of every point, on every hardware thread (cloud-to-mesh distance, as CloudCompare computes it);
//  - rays: an Embree 3 scene of the triangles, the nearest hit of every ray (rtcIntersect1), on
//    every hardware thread.
// No nurbsgl code touches the geometry: the peer stays independent.
//  peer_mesh_pipeline MODEL --deflection D (--points FILE | --rays FILE) [--out FILE] [--threads N]
// Prints JSON {triangles, read_seconds, mesh_seconds, build_seconds, query_seconds, queries,
// deflection}; --out writes one line per query: the distance (points) or t (rays; -1: miss).
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

/// Every face's triangulation in world coordinates, one mesh.
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
      m.corners.insert(m.corners.end(), {first + unsigned(a - 1), first + unsigned(b - 1), first + unsigned(c - 1)});
    }
  }
  return m;
}

/// Rows of `per_row` numbers from a text file (spaces or commas).
std::vector<double> read_rows(const std::string& path, size_t per_row) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::vector<double> out;
  std::string line;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    double v = 0.0;
    size_t n = 0;
    while (s >> v) out.push_back(v), ++n;
    if (n != 0 && n != per_row) throw std::runtime_error(path + ": a line of " + std::to_string(n) + " numbers");
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Mesh pipeline peer: OCCT BRepMesh, then CGAL AABB_tree (points) or Embree (rays)"};
  std::string model, points, rays, out;
  double deflection = 0.0;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  app.add_option("MODEL", model)->required();
  app.add_option("--deflection", deflection, "BRepMesh linear deflection, model units")->required();
  app.add_option("--points", points, "x y z per line");
  app.add_option("--rays", rays, "ox oy oz dx dy dz per line");
  app.add_option("--out", out, "one distance (or t, -1 for a miss) per line");
  app.add_option("--threads", threads);
  CLI11_PARSE(app, argc, argv);
  if (points.empty() == rays.empty()) return std::fprintf(stderr, "give one of --points and --rays\n"), 2;
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
    } else {
      const std::vector<double> r = read_rows(rays, 6);
      t0 = peer::Clock::now();
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
      answers.resize(r.size() / 6);
      t0 = peer::Clock::now();
      parallel(answers.size(), threads, [&](size_t i) {
        const double* q = &r[6 * i];
        const double len = std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5]);
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit h{};
        h.ray.org_x = float(q[0]), h.ray.org_y = float(q[1]), h.ray.org_z = float(q[2]);
        h.ray.dir_x = float(q[3] / len), h.ray.dir_y = float(q[4] / len), h.ray.dir_z = float(q[5] / len);
        h.ray.tnear = 0.0f, h.ray.tfar = std::numeric_limits<float>::infinity();
        h.ray.mask = ~0u;
        h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &h);
        answers[i] = h.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0 : double(h.ray.tfar);
      });
      query_seconds = peer::seconds_since(t0);
      rtcReleaseScene(scene);
      rtcReleaseDevice(device);
    }
    if (!out.empty()) {
      std::ofstream o(out);
      for (const double a : answers) o << fmt::format("{:.17g}\n", a);
    }
    j = {{"triangles", triangles},     {"read_seconds", read_seconds},   {"mesh_seconds", mesh_seconds},
         {"build_seconds", build_seconds}, {"query_seconds", query_seconds}, {"queries", answers.size()},
         {"deflection", deflection},   {"threads", threads}};
    std::printf("%s\n", j.dump(2).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_mesh_pipeline: %s\n", e.what());
    return 2;
  }
  return 0;
}
