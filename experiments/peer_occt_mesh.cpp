// OpenCASCADE peer of the tessellation experiments (experiments/tessellation_tables.py):
// BRepMesh_IncrementalMesh of an IGES model at a given linear deflection, timed, and the mesh
// written (.stl binary, .ply, .obj) for `nurbsgl deviation` to measure exactly as it measures ours.
//  peer_occt_mesh MODEL --deflection D [--angular A] [--relative] [--parallel] [--repeat N] [-o OUT]
// Prints JSON {triangles, vertices, seconds, deflection, ...}; seconds is the median of N meshings
// of the same shape (the previous mesh removed with BRepTools::Clean before each).
// Reads and meshes with OCCT only (IGESControl_Reader): the mesh owes nothing to nurbsgl; the mesh
// file is written with nurbsgl's writer so that both programs' meshes go through the same code, and
// in the file's units (OCCT works in mm; the unit flag comes from nurbsgl's IGES reader).
#include <fmt/format.h>

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <CLI/CLI.hpp>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Version.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>

#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/read_model.h"
#include "peer_occt_read.h"

namespace {

using peer::Clock;
using peer::read_iges;
using peer::seconds_since;

/// Every face's Poly_Triangulation in world coordinates (the face's location applied), one mesh;
/// triangles of reversed faces flipped so that all are counter-clockwise seen from outside.
/// `bare` counts the faces BRepMesh left without a triangulation.
nurbs::TriangleMesh collect(const TopoDS_Shape& shape, int& faces, int& bare) {
  nurbs::TriangleMesh mesh;
  faces = bare = 0;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face& face = TopoDS::Face(e.Current());
    ++faces;
    TopLoc_Location location;
    const Handle(Poly_Triangulation)& t = BRep_Tool::Triangulation(face, location);
    if (t.IsNull() || t->NbTriangles() == 0) {
      ++bare;
      continue;
    }
    const gp_Trsf to_world = location.Transformation();
    const int first = int(mesh.positions.size());
    for (int i = 1; i <= t->NbNodes(); ++i) {
      const gp_Pnt p = t->Node(i).Transformed(to_world);
      mesh.positions.emplace_back(p.X(), p.Y(), p.Z());
    }
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int k = 1; k <= t->NbTriangles(); ++k) {
      int a, b, c;
      t->Triangle(k).Get(a, b, c);
      if (reversed) std::swap(b, c);
      mesh.triangles.emplace_back(first + a - 1, first + b - 1, first + c - 1);
      mesh.triangle_face.push_back(faces - 1);
    }
  }
  return mesh;
}

int run(const std::string& model, double deflection, double angular, bool relative, bool parallel, int repeat,
        const std::string& output) {
  double read_seconds = 0;
  const TopoDS_Shape shape = read_iges(model, read_seconds);
  // OCCT reads in millimetres, nurbsgl keeps the file's units: the deflection is given and the mesh
  // written in file units, so that `nurbsgl deviation` compares like with like. Only the unit flag
  // of the IGES global section is taken from nurbsgl's reader.
  const double to_mm = nurbs::io::read_model(model).unit_scale_to_mm;
  std::vector<double> times;
  bool done = true;
  for (int k = 0; k < repeat; ++k) {
    BRepTools::Clean(shape);
    const auto t0 = Clock::now();
    BRepMesh_IncrementalMesh mesher(shape, relative ? deflection : deflection * to_mm, relative, angular, parallel);
    times.push_back(seconds_since(t0));
    done = done && mesher.IsDone();
  }
  std::sort(times.begin(), times.end());
  int faces = 0, bare = 0;
  nurbs::TriangleMesh mesh = collect(shape, faces, bare);
  for (glm::dvec3& p : mesh.positions) p /= to_mm;
  if (!output.empty()) nurbs::io::write_mesh_file(output, mesh);
  nlohmann::json out{{"occt", OCC_VERSION_COMPLETE},
                     {"model", model},
                     {"deflection", deflection},
                     {"unit_scale_to_mm", to_mm},
                     {"angular_deflection", angular},
                     {"relative", relative},
                     {"parallel", parallel},
                     {"done", done},
                     {"faces", faces},
                     {"faces_without_triangulation", bare},
                     {"triangles", mesh.triangles.size()},
                     {"vertices", mesh.positions.size()},
                     {"seconds", times[times.size() / 2]},
                     {"first_seconds", times.front()},
                     {"repeat", repeat},
                     {"read_seconds", read_seconds}};
  if (!output.empty()) out["output"] = output;
  fmt::print("{}\n", out.dump(2));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"OpenCASCADE peer of nurbsgl tessellate: BRepMesh_IncrementalMesh of an IGES model (JSON on stdout)"};
  std::string model, output;
  double deflection = 0, angular = 0.5;  // OCCT's default angular deflection, radians
  bool relative = false, parallel = false;
  int repeat = 1;
  app.add_option("MODEL", model, "IGES model")->required();
  app.add_option("--deflection", deflection, "Linear deflection (file units; a factor of edge size with --relative)")
      ->required()
      ->check(CLI::PositiveNumber);
  app.add_option("--angular", angular, "Angular deflection in radians")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_flag("--relative", relative, "BRepMesh's relative deflection (per edge, times its size)");
  app.add_flag("--parallel", parallel, "Mesh faces in parallel (OCCT's thread pool)");
  app.add_option("--repeat", repeat, "Meshings; the median time is reported")->check(CLI::PositiveNumber);
  app.add_option("-o,--output", output, "Write the mesh: .stl (binary), .ply or .obj");
  CLI11_PARSE(app, argc, argv);
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));  // the reader's chatter
  try {
    if (!output.empty()) (void)nurbs::io::mesh_format_of(output);
    return run(model, deflection, angular, relative, parallel, repeat, output);
  } catch (const std::exception& e) {
    fmt::print(stderr, "peer_occt_mesh: {}\n", e.what());
    return 2;
  }
}
