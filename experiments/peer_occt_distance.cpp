// OpenCASCADE peer of the distance experiments (experiments/distance_tables.py): the same
// IGES or STEP files, the same rigid motion of B, the same machine; prints JSON, asserts nothing.
//  shapes A B [--move-b DX,DY,DZ] [--rotate-b AX,AY,AZ,DEG] | [--motion FILE] [--repeat N]:
//      BRepExtrema_DistShapeShape between A and B moved (rotated by DEG degrees about the axis
//      through the origin, then moved, as `nurbsgl clearance`); per motion the median of N runs.
//      --witness FILE: how far given closest points (nurbsgl's) lie from OCCT's A and B faces.
//  points MODEL --points FILE [--repeat N] [--trimmed M [--mesh-deflection D]]: GeomAPI_ProjectPointOnSurf, one projector per face
//      initialised once on the face's surface and its UV bounds (trims ignored), min over faces (none with N = 0);
//      --trimmed M: also BRepExtrema_DistShapeShape from each of the first M points to the shape
//      (the exact distance to the trimmed faces, and the nearest point), with the shape's tolerance;
//      --mesh-deflection D: also the distance to OCCT's BRepMesh of the faces at deflection D (a second
//      opinion where the exact distance's face classification errs).
//  sides MODEL --points FILE: BRepClass3d_SolidClassifier of every point in every solid of the
//      file (its tolerance the shape's): "in" inside any solid (the part is their union), else "on"
//      on any, else "out"; the peer of `nurbsgl distance --signed`.
//  rays MODEL --rays FILE [--repeat N]: IntCurvesFace_ShapeIntersector loaded once, PerformNearest
//      per ray (ox oy oz dx dy dz per line, spaces or commas): t along the unit direction, face
//      index (TopExp_Explorer order), -1 for a miss; the ray peer of `nurbsgl raycast`.
// Reads the models with nurbs-free OCCT code only (IGESControl_Reader, STEPControl_Reader), so it is an independent peer.
#include <fmt/format.h>

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Builder.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <CLI/CLI.hpp>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <Poly_Triangulation.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopExp.hxx>
#include <gp_Lin.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <Standard_Version.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "peer_occt_read.h"

namespace {

using peer::Clock;
using peer::read_shape;
using peer::seconds_since;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Finite numbers separated by commas or spaces; throws naming `what` unless there are `count`.
std::vector<double> numbers(const std::string& text, size_t count, const std::string& what) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  std::istringstream in(spaced);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  if (v.size() != count || !in.eof())
    throw std::runtime_error(fmt::format("{}: '{}' is not {} numbers", what, text, count));
  return v;
}

/// Rotation by deg degrees about (ax, ay, az) through the origin, then the move (dx, dy, dz):
/// v = {dx, dy, dz, ax, ay, az, deg}, the line format of `nurbsgl clearance --motion`.
gp_Trsf rigid_motion(const std::vector<double>& v) {
  gp_Trsf rotation, move;
  if (v[6] != 0.0) rotation.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(v[3], v[4], v[5])), v[6] * M_PI / 180.0);
  move.SetTranslation(gp_Vec(v[0], v[1], v[2]));
  return move * rotation;  // applied right to left: rotation first
}

/// The largest vertex, edge or face tolerance of the shape: OCCT's own precision on its answer.
double shape_tolerance(const TopoDS_Shape& s) {
  double t = Precision::Confusion();
  for (TopExp_Explorer e(s, TopAbs_VERTEX); e.More(); e.Next())
    t = std::max(t, BRep_Tool::Tolerance(TopoDS::Vertex(e.Current())));
  for (TopExp_Explorer e(s, TopAbs_EDGE); e.More(); e.Next())
    t = std::max(t, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next())
    t = std::max(t, BRep_Tool::Tolerance(TopoDS::Face(e.Current())));
  return t;
}

nlohmann::json point_json(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }

/// Distance from p to the shape: how far another program's witness point lies from OCCT's faces.
double gap(const gp_Pnt& p, const TopoDS_Shape& shape, gp_Pnt* nearest = nullptr) {
  BRepExtrema_DistShapeShape d(BRepBuilderAPI_MakeVertex(p).Vertex(), shape);
  if (!(d.IsDone() && d.NbSolution() > 0)) return INFINITY;
  if (nearest) *nearest = d.PointOnShape2(1);
  return d.Value();
}

/// Distance from p to the triangle a b c (the closest point by the triangle's Voronoi regions).
double triangle_distance(const gp_XYZ& p, const gp_XYZ& a, const gp_XYZ& b, const gp_XYZ& c) {
  const gp_XYZ ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.Dot(ap), d2 = ac.Dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.Modulus();
  const gp_XYZ bp = p - b;
  const double d3 = ab.Dot(bp), d4 = ac.Dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.Modulus();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).Modulus();
  const gp_XYZ cp = p - c;
  const double d5 = ab.Dot(cp), d6 = ac.Dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.Modulus();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).Modulus();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).Modulus();
  const double den = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * den) + ac * (vc * den))).Modulus();
}

/// The triangles of BRepMesh_IncrementalMesh at `deflection` over every face of the shape, placed.
std::vector<std::array<gp_XYZ, 3>> mesh_triangles(const TopoDS_Shape& shape, double deflection) {
  BRepMesh_IncrementalMesh mesher(shape, deflection);
  std::vector<std::array<gp_XYZ, 3>> out;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    TopLoc_Location where;
    const Handle(Poly_Triangulation) t = BRep_Tool::Triangulation(TopoDS::Face(e.Current()), where);
    if (t.IsNull()) continue;
    const gp_Trsf move = where.Transformation();
    for (int k = 1; k <= t->NbTriangles(); ++k) {
      int i, j, l;
      t->Triangle(k).Get(i, j, l);
      out.push_back({t->Node(i).Transformed(move).XYZ(), t->Node(j).Transformed(move).XYZ(),
                     t->Node(l).Transformed(move).XYZ()});
    }
  }
  return out;
}

/// Per line "FRAME AX AY AZ BX BY BZ" (FRAME from 0): the distances of the witness points (the
/// closest points another program reports) to A and to B moved as in that frame.
nlohmann::json witness_gaps(const std::string& file, const TopoDS_Shape& a, const TopoDS_Shape& b,
                            const std::vector<std::vector<double>>& frames) {
  std::ifstream f(file);
  if (!f) throw std::runtime_error("--witness " + file + ": cannot open the file");
  nlohmann::json out = nlohmann::json::array();
  int n = 0;
  for (std::string line; std::getline(f, line);) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto v = numbers(line, 7, fmt::format("{}: line {}", file, n));
    const size_t k = size_t(v[0]);
    if (v[0] < 0 || k >= frames.size())
      throw std::runtime_error(fmt::format("{}: line {}: no frame {}", file, n, v[0]));
    const TopoDS_Shape moved = b.Moved(TopLoc_Location(rigid_motion(frames[k])));
    out.push_back(
        {{"frame", k}, {"gap_a", gap(gp_Pnt(v[1], v[2], v[3]), a)}, {"gap_b", gap(gp_Pnt(v[4], v[5], v[6]), moved)}});
  }
  return out;
}

int shapes(const std::string& a_path, const std::string& b_path, const std::string& move, const std::string& rotate,
           const std::string& motion, const std::string& witness, int repeat) {
  std::vector<std::vector<double>> frames;
  if (motion.empty()) {
    std::vector<double> v{0, 0, 0, 0, 0, 1, 0};
    if (!move.empty()) std::copy_n(numbers(move, 3, "--move-b").begin(), 3, v.begin());
    if (!rotate.empty()) std::copy_n(numbers(rotate, 4, "--rotate-b").begin(), 4, v.begin() + 3);
    frames.push_back(v);
  } else {
    std::ifstream f(motion);
    if (!f) throw std::runtime_error("--motion " + motion + ": cannot open the file");
    int n = 0;
    for (std::string line; std::getline(f, line);) {
      ++n;
      if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t\r")] == '#')
        continue;
      frames.push_back(numbers(line, 7, fmt::format("{}: line {}", motion, n)));
    }
  }
  double read_a = 0, read_b = 0;
  const TopoDS_Shape a = read_shape(a_path, read_a), b = read_shape(b_path, read_b);
  const double tolerance = shape_tolerance(a) + shape_tolerance(b);
  nlohmann::json results = nlohmann::json::array();
  for (const auto& frame : frames) {
    const TopoDS_Shape moved = b.Moved(TopLoc_Location(rigid_motion(frame)));
    std::vector<double> times;
    nlohmann::json r;
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = Clock::now();
      BRepExtrema_DistShapeShape d(a, moved);
      times.push_back(seconds_since(t0));
      if (!d.IsDone() || d.NbSolution() < 1) {
        r = {{"done", false}};
        continue;
      }
      r = {{"done", true},
           {"distance", d.Value()},
           {"point_a", point_json(d.PointOnShape1(1))},
           {"point_b", point_json(d.PointOnShape2(1))},
           {"solutions", d.NbSolution()}};
    }
    r["seconds"] = median(times);
    r["first_seconds"] = times.front();
    results.push_back(r);
  }
  nlohmann::json out{
      {"occt", OCC_VERSION_COMPLETE}, {"read_seconds", read_a + read_b}, {"tolerance", tolerance}, {"repeat", repeat}};
  if (motion.empty()) {
    out.update(results.front());
  } else {
    out["frames"] = frames.size();
    out["results"] = results;
  }
  if (!witness.empty()) out["witnesses"] = witness_gaps(witness, a, b, frames);
  fmt::print("{}\n", out.dump(2));
  return 0;
}

/// The points of a file, x y z per line.
std::vector<gp_Pnt> read_points(const std::string& file) {
  std::vector<gp_Pnt> input;
  std::ifstream f(file);
  if (!f) throw std::runtime_error("--points " + file + ": cannot open the file");
  int n = 0;
  for (std::string line; std::getline(f, line);) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto v = numbers(line, 3, fmt::format("{}: line {}", file, n));
    input.emplace_back(v[0], v[1], v[2]);
  }
  return input;
}

int sides(const std::string& model, const std::string& file) {
  const std::vector<gp_Pnt> input = read_points(file);
  double read_s = 0;
  const TopoDS_Shape shape = read_shape(model, read_s);
  const double tolerance = shape_tolerance(shape);
  std::vector<TopoDS_Shape> solids;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) solids.push_back(e.Current());
  const auto t0 = Clock::now();
  nlohmann::json results = nlohmann::json::array();
  for (const gp_Pnt& p : input) {
    bool in = false, on = false;
    for (const TopoDS_Shape& solid : solids) {
      BRepClass3d_SolidClassifier c(solid, p, tolerance);
      in = in || c.State() == TopAbs_IN;
      on = on || c.State() == TopAbs_ON;
      if (in) break;
    }
    results.push_back(in ? "in" : on ? "on" : "out");
  }
  const nlohmann::json out{{"occt", OCC_VERSION_COMPLETE}, {"read_seconds", read_s}, {"solids", solids.size()},
                           {"tolerance", tolerance},       {"points", input.size()},  {"seconds", seconds_since(t0)},
                           {"results", results}};
  fmt::print("{}\n", out.dump(1));
  return 0;
}

int points(const std::string& model, const std::string& file, int repeat, int trimmed, double deflection) {
  const std::vector<gp_Pnt> input = read_points(file);
  double read_s = 0;
  const TopoDS_Shape shape = read_shape(model, read_s);
  const auto t0 = Clock::now();
  std::deque<GeomAPI_ProjectPointOnSurf> projectors;  // not movable: a deque never relocates
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face& face = TopoDS::Face(e.Current());
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    projectors.emplace_back();
    projectors.back().Init(BRep_Tool::Surface(face), u0, u1, v0, v1);
  }
  const double init_s = seconds_since(t0);
  std::vector<double> times;
  nlohmann::json results = nlohmann::json::array();
  for (int k = 0; k < repeat; ++k) {
    results = nlohmann::json::array();
    const auto t1 = Clock::now();
    for (const gp_Pnt& p : input) {
      double best = INFINITY;
      gp_Pnt closest;
      for (auto& proj : projectors) {
        proj.Perform(p);
        if (proj.NbPoints() > 0 && proj.LowerDistance() < best) {
          best = proj.LowerDistance();
          closest = proj.NearestPoint();
        }
      }
      results.push_back(std::isfinite(best) ? nlohmann::json{{"distance", best}, {"point", point_json(closest)}}
                                            : nlohmann::json{{"distance", nullptr}});
    }
    times.push_back(seconds_since(t1));
  }
  nlohmann::json out{
      {"occt", OCC_VERSION_COMPLETE}, {"read_seconds", read_s},   {"init_seconds", init_s}, {"points", input.size()},
      {"faces", projectors.size()},   {"seconds", median(times)}, {"repeat", repeat},       {"results", results}};
  if (trimmed > 0) {  // the exact distance to the trimmed faces (BRepExtrema), first points only
    // To the faces, not to the solids they bound (a point inside a solid is at 0 from it).
    TopoDS_Compound faces;
    BRep_Builder builder;
    builder.MakeCompound(faces);
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) builder.Add(faces, e.Current());
    nlohmann::json d = nlohmann::json::array(), nearest = nlohmann::json::array();
    const auto t2 = Clock::now();
    for (size_t i = 0; i < input.size() && i < size_t(trimmed); ++i) {
      gp_Pnt q;
      const double g = gap(input[i], faces, &q);
      d.push_back(std::isfinite(g) ? nlohmann::json(g) : nlohmann::json(nullptr));
      nearest.push_back(std::isfinite(g) ? nlohmann::json{q.X(), q.Y(), q.Z()} : nlohmann::json(nullptr));
    }
    out["trimmed"] = {{"points", d.size()},   {"seconds", seconds_since(t2)},      {"distances", d},
                      {"nearest", nearest}, {"tolerance", shape_tolerance(shape)}};
    if (deflection > 0) {  // a second opinion: the distance to OCCT's own mesh of the faces
      const auto triangles = mesh_triangles(shape, deflection);
      nlohmann::json m = nlohmann::json::array();
      for (size_t i = 0; i < input.size() && i < size_t(trimmed); ++i) {
        double best = INFINITY;
        for (const auto& t : triangles) best = std::min(best, triangle_distance(input[i].XYZ(), t[0], t[1], t[2]));
        m.push_back(std::isfinite(best) ? nlohmann::json(best) : nlohmann::json(nullptr));
      }
      out["trimmed"]["mesh"] = {{"deflection", deflection}, {"triangles", triangles.size()}, {"distances", m}};
    }
  }
  fmt::print("{}\n", out.dump(1));
  return 0;
}

int rays(const std::string& model, const std::string& file, int repeat) {
  std::vector<gp_Lin> input;
  std::ifstream f(file);
  if (!f) throw std::runtime_error("--rays " + file + ": cannot open the file");
  int n = 0;
  for (std::string line; std::getline(f, line);) {
    ++n;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto v = numbers(line, 6, fmt::format("{}: line {}", file, n));
    input.emplace_back(gp_Pnt(v[0], v[1], v[2]), gp_Dir(v[3], v[4], v[5]));
  }
  double read_s = 0;
  const TopoDS_Shape shape = read_shape(model, read_s);
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  const auto t0 = Clock::now();
  IntCurvesFace_ShapeIntersector intersector;
  intersector.Load(shape, Precision::Confusion());
  const double init_s = seconds_since(t0);
  std::vector<double> times;
  nlohmann::json t = nlohmann::json::array(), face = nlohmann::json::array();
  for (int k = 0; k < repeat; ++k) {
    t = nlohmann::json::array();
    face = nlohmann::json::array();
    const auto t1 = Clock::now();
    for (const gp_Lin& ray : input) {
      intersector.PerformNearest(ray, 0.0, RealLast());
      if (intersector.IsDone() && intersector.NbPnt() > 0) {
        t.push_back(intersector.WParameter(1));
        face.push_back(faces.FindIndex(intersector.Face(1)) - 1);
      } else {
        t.push_back(-1.0);
        face.push_back(-1);
      }
    }
    times.push_back(seconds_since(t1));
  }
  const double sec = median(times);
  const nlohmann::json out{{"occt", OCC_VERSION_COMPLETE},
                           {"read_seconds", read_s},
                           {"init_seconds", init_s},
                           {"rays", input.size()},
                           {"faces", faces.Extent()},
                           {"seconds", sec},
                           {"rays_per_second", sec > 0 ? double(input.size()) / sec : 0.0},
                           {"repeat", repeat},
                           {"t", t},
                           {"face", face}};
  fmt::print("{}\n", out.dump(1));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"OpenCASCADE peer of nurbsgl distance, clearance and ray casting (JSON on stdout)"};
  app.require_subcommand(1);
  std::string a, b, move, rotate, motion, witness, model, file;
  int repeat = 5, trimmed = 0;
  double deflection = 0.0;
  auto* s = app.add_subcommand("shapes", "BRepExtrema_DistShapeShape between A and B moved");
  s->add_option("A", a, "First IGES or STEP model")->required();
  s->add_option("B", b, "Second IGES or STEP model")->required();
  s->add_option("--move-b", move, "Translate B by DX,DY,DZ (after the rotation)");
  s->add_option("--rotate-b", rotate, "Rotate B by DEG degrees about AX,AY,AZ through the origin");
  s->add_option("--motion", motion, "One query per line: DX DY DZ AX AY AZ DEG");
  s->add_option("--witness", witness,
                "Lines FRAME AX AY AZ BX BY BZ: distance of these points to A and to B moved as in FRAME (from 0)");
  s->add_option("--repeat", repeat, "Runs per query; the median is reported")->check(CLI::PositiveNumber);
  auto* p = app.add_subcommand("points", "GeomAPI_ProjectPointOnSurf of every point, projectors initialised once");
  p->add_option("MODEL", model, "IGES or STEP model")->required();
  p->add_option("--points", file, "x y z per line")->required();
  p->add_option("--repeat", repeat, "Runs over all points; the median is reported (0: no projection, --trimmed only)")
      ->check(CLI::NonNegativeNumber);
  p->add_option("--trimmed", trimmed,
                "Also the exact distance to the trimmed faces (BRepExtrema_DistShapeShape) of the first N points")
      ->check(CLI::NonNegativeNumber);
  p->add_option("--mesh-deflection", deflection,
                "With --trimmed: also the distance to OCCT's mesh of the faces (BRepMesh at this deflection)")
      ->check(CLI::NonNegativeNumber);
  auto* c = app.add_subcommand("sides", "BRepClass3d_SolidClassifier of every point: inside any solid, on, or out");
  c->add_option("MODEL", model, "IGES or STEP model")->required();
  c->add_option("--points", file, "x y z per line (mm)")->required();
  auto* r = app.add_subcommand("rays", "IntCurvesFace_ShapeIntersector: nearest hit of every ray");
  r->add_option("MODEL", model, "IGES or STEP model")->required();
  r->add_option("--rays", file, "ox oy oz dx dy dz per line")->required();
  r->add_option("--repeat", repeat, "Runs over all rays; the median is reported")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));  // the reader's chatter
  try {
    if (r->parsed()) return rays(model, file, repeat);
    if (c->parsed()) return sides(model, file);
    return s->parsed() ? shapes(a, b, move, rotate, motion, witness, repeat) : points(model, file, repeat, trimmed, deflection);
  } catch (const std::exception& e) {
    fmt::print(stderr, "peer_occt_distance: {}\n", e.what());
    return 2;
  }
}
