// OpenCASCADE peer of the STEP reader (experiments/step_models.py): OCCT's own STEP reader only
// (peer_occt_read.h), so the peer stays independent of nurbsgl; prints JSON, asserts nothing.
//  read FILE [--repeat N]: STEPControl_Reader read + transfer of every root (the fastest of N runs),
//      faces, solids, shells, total face area (BRepGProp) and the bounding box (BRepBndLib::AddOptimal).
//  clearance FILE --a X,Y,Z --b X,Y,Z: the solids (or shells) of the file nearest the points a and b
//      (as `nurbsgl clearance` names its closest points) and BRepExtrema_DistShapeShape between them.
#include <fmt/format.h>

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp.hxx>
#include <Bnd_Box.hxx>
#include <CLI/CLI.hpp>
#include <GProp_GProps.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shape.hxx>
#include <chrono>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "peer_occt_read.h"

namespace {

using peer::Clock;
using peer::read_step;

int count(const TopoDS_Shape& s, TopAbs_ShapeEnum type) {
  int n = 0;
  for (TopExp_Explorer e(s, type); e.More(); e.Next()) ++n;
  return n;
}

gp_Pnt parse_point(const std::string& text) {
  std::vector<double> v;
  std::string item;
  std::stringstream in(text);
  while (std::getline(in, item, ',')) v.push_back(std::stod(item));
  if (v.size() != 3) throw std::runtime_error("'" + text + "' is not X,Y,Z");
  return {v[0], v[1], v[2]};
}

// The solid (or, without solids, the shell) of `shape` nearest p.
TopoDS_Shape nearest_part(const TopoDS_Shape& shape, const gp_Pnt& p) {
  const TopAbs_ShapeEnum type = count(shape, TopAbs_SOLID) > 0 ? TopAbs_SOLID : TopAbs_SHELL;
  const TopoDS_Shape vertex = BRepBuilderAPI_MakeVertex(p).Shape();
  TopoDS_Shape best;
  double best_d = std::numeric_limits<double>::infinity();
  for (TopExp_Explorer e(shape, type); e.More(); e.Next()) {
    BRepExtrema_DistShapeShape d(vertex, e.Current());
    if (d.IsDone() && d.Value() < best_d) best_d = d.Value(), best = e.Current();
  }
  if (best.IsNull()) throw std::runtime_error("no solid or shell near the point");
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  CLI::App app{"OpenCASCADE peer of the STEP reader"};
  app.require_subcommand(1);
  std::string file, a, b;
  int repeat = 3;
  auto* read = app.add_subcommand("read", "Read + transfer time, counts, area, box");
  read->add_option("FILE", file)->required();
  read->add_option("--repeat", repeat, "Runs; the fastest is printed");
  auto* clearance = app.add_subcommand("clearance", "Distance between the parts nearest two points");
  clearance->add_option("FILE", file)->required();
  clearance->add_option("--a", a, "A point on the first part")->required();
  clearance->add_option("--b", b, "A point on the second part")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    nlohmann::json out = {{"file", file}};
    double seconds = 0.0;
    TopoDS_Shape shape = read_step(file, seconds);
    if (*read) {
      for (int k = 1; k < repeat; ++k) {
        double again = 0.0;
        shape = read_step(file, again);
        seconds = std::min(seconds, again);
      }
      GProp_GProps props;
      BRepGProp::SurfaceProperties(shape, props);
      Bnd_Box box;
      BRepBndLib::AddOptimal(shape, box, false, false);
      double x0, y0, z0, x1, y1, z1;
      box.Get(x0, y0, z0, x1, y1, z1);
      out.update({{"read_seconds", seconds},
                  {"faces", count(shape, TopAbs_FACE)},
                  {"solids", count(shape, TopAbs_SOLID)},
                  {"shells", count(shape, TopAbs_SHELL)},
                  {"area", props.Mass()},
                  {"bbox", {x0, y0, z0, x1, y1, z1}}});
    } else {
      const TopoDS_Shape pa = nearest_part(shape, parse_point(a)), pb = nearest_part(shape, parse_point(b));
      const auto t0 = Clock::now();
      BRepExtrema_DistShapeShape d(pa, pb);
      if (!d.IsDone()) throw std::runtime_error("BRepExtrema_DistShapeShape failed");
      out.update({{"distance", d.Value()},
                  {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()},
                  {"same_part", pa.IsSame(pb)}});
    }
    fmt::print("{}\n", out.dump());
  } catch (const std::exception& e) {
    fmt::print(stderr, "peer_occt_step: {}\n", e.what());
    return 1;
  }
  return 0;
}
