// Trim classification vs OpenCASCADE (built only with -DNURBSGL_PEER_BENCH=ON, as
// scripts/bench.sh does). For every IGES and STEP file under the shared models, each nurbsgl face is matched
// to the OCCT face nearest to a few of its material points (not by order), then an N x N grid of cell
// centres over the face's whole (u, v) domain is classified twice:
//  - nurbsgl: nurbs::flatten_trim + nurbs::is_material (the CPU twin of the trim texture,
//    queries::trim_mask_cpu), flattening tolerance a tenth of a grid step as `evaluate` uses;
//  - OCCT: S(u, v) projected onto the matched face's surface (GeomAPI_ProjectPointOnSurf, lower
//    distance; periodic parameters shifted into the face's range), then BRepClass_FaceClassifier at
//    (u', v') with Precision::PConfusion(). IN and ON are material (a face is a closed set; ON is rare
//    at cell centres and counted apart).
// Samples projecting farther than 1e-6 x model size are not compared (the surfaces differ there, e.g.
// outside the range of a trimmed periodic face) and are counted apart. Disagreements are split into
// "near" (within 2 grid steps in (u, v), in steps, of a flattened trim loop or, for faces without an
// outer loop, the domain boundary) and "far". Far ones are classified once more with OCCT's
// BRepTopAdaptor_FClass2d (column far*: how many of them it sides with nurbsgl on), and faces with
// far disagreements get both sides' loops printed. Faces are matched when a probe lies within
// 1e-4 x model size of the trimmed OCCT face (BRepExtrema_DistShapeShape); unmatched ones are named.
// Coordinates: nurbsgl keeps file units, OCCT reads in mm, so nurbsgl's are scaled by unit_scale_to_mm.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <CLI/CLI.hpp>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <memory>

#include "nurbs/curve_eval.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "peer_occt_read.h"

namespace {

namespace fs = std::filesystem;

/// An OCCT face with what the comparison needs of it, built once.
struct OcctFace {
  TopoDS_Face face;
  Handle(Geom_Surface) surface;  ///< with the face's location applied
  Bnd_Box box;
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;  ///< BRepTools::UVBounds
};

std::vector<OcctFace> occt_faces(const fs::path& path) {
  double seconds = 0.0;
  const TopoDS_Shape shape = peer::read_shape(path.string(), seconds);
  std::vector<OcctFace> faces;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    OcctFace f;
    f.face = TopoDS::Face(e.Current());
    f.surface = BRep_Tool::Surface(f.face);
    BRepBndLib::Add(f.face, f.box);
    BRepTools::UVBounds(f.face, f.u0, f.u1, f.v0, f.v1);
    faces.push_back(f);
  }
  return faces;
}

gp_Pnt to_gp(glm::dvec3 p) { return {p.x, p.y, p.z}; }

/// Distance from p to the trimmed OCCT face (BRepExtrema: the face's boundary counts).
double face_distance(const OcctFace& f, glm::dvec3 p) {
  BRepExtrema_DistShapeShape d(BRepBuilderAPI_MakeVertex(to_gp(p)).Vertex(), f.face);
  return d.IsDone() ? d.Value() : HUGE_VAL;
}

/// Distance in grid steps from (u, v) to the nearest edge of the flattened loops (and of the domain
/// rectangle when there is no outer loop, as is_material then uses it).
double steps_to_trim(const nurbs::TrimPolygons& trim, glm::dvec2 uv, glm::dvec2 step) {
  auto seg = [&](glm::dvec2 a, glm::dvec2 b) {
    a /= step, b /= step;
    const glm::dvec2 p = uv / step, ab = b - a;
    const double l2 = glm::dot(ab, ab), t = l2 > 0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
  };
  double best = HUGE_VAL;
  for (const auto& loop : trim.loops)
    for (size_t i = 0; i < loop.size(); ++i) best = std::min(best, seg(loop[i], loop[(i + 1) % loop.size()]));
  if (std::find(trim.outer.begin(), trim.outer.end(), true) == trim.outer.end()) {
    const glm::dvec2 c[4] = {{trim.domain_u.min, trim.domain_v.min},
                             {trim.domain_u.max, trim.domain_v.min},
                             {trim.domain_u.max, trim.domain_v.max},
                             {trim.domain_u.min, trim.domain_v.max}};
    for (int i = 0; i < 4; ++i) best = std::min(best, seg(c[i], c[(i + 1) % 4]));
  }
  return best;
}

/// Up to 5 material parameters spread over the face to match it by: cell centres 2+ steps from the
/// trim if any, else any material centre, else (slivers) material points of a 16x finer grid, else
/// the domain centre.
std::vector<glm::dvec2> probe_params(const nurbs::TrimPolygons& trim, const std::vector<glm::dvec2>& uv,
                                     const std::vector<uint8_t>& ours, glm::dvec2 step) {
  std::vector<glm::dvec2> material, interior;
  for (size_t k = 0; k < uv.size(); ++k)
    if (ours[k]) material.push_back(uv[k]);
  for (size_t k = 0; k < material.size() && interior.size() < 64; k += std::max<size_t>(1, material.size() / 64))
    if (steps_to_trim(trim, material[k], step) > 2) interior.push_back(material[k]);
  const glm::dvec2 lo(trim.domain_u.min, trim.domain_v.min), hi(trim.domain_u.max, trim.domain_v.max);
  for (double j = 0.5 / 16; material.empty() && j < (hi.y - lo.y) / step.y; j += 1.0 / 16)
    for (double i = 0.5 / 16; i < (hi.x - lo.x) / step.x && material.size() < 64; i += 1.0 / 16)
      if (nurbs::is_material(trim, lo + glm::dvec2(i, j) * step)) material.push_back(lo + glm::dvec2(i, j) * step);
  const std::vector<glm::dvec2>& pick = interior.empty() ? material : interior;
  if (pick.empty()) return {(lo + hi) / 2.0};
  std::vector<glm::dvec2> out;
  for (size_t k = 0; k < 5; ++k) out.push_back(pick[k * (pick.size() - 1) / 4]);
  return out;
}

/// Counts for one face (or summed over a model).
struct Tally {
  int faces = 0, matched = 0;
  long samples = 0, skipped = 0, compared = 0, on = 0, near = 0, far = 0, far_fclass = 0, ours_only = 0, occt_only = 0;
  void add(const Tally& t) {
    faces += t.faces, matched += t.matched, samples += t.samples, skipped += t.skipped, compared += t.compared;
    on += t.on, near += t.near, far += t.far, far_fclass += t.far_fclass, ours_only += t.ours_only,
        occt_only += t.occt_only;
  }
  [[nodiscard]] double rate() const { return compared ? double(near + far) / double(compared) : 0.0; }
};

/// One compared sample that disagrees far from the trim curves, for the explanation.
struct FarSample {
  glm::dvec2 uv, occt_uv;
  bool ours;
};

/// Prints the face's nurbsgl loops and the matched OCCT face's wires (pcurve ends in its (u, v)).
void explain(const nurbs::TrimmedSurface& face, const nurbs::TrimPolygons& trim, const OcctFace* of,
             const std::vector<FarSample>& far) {
  const auto du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
  fmt::print("    nurbsgl: degree ({}, {}), {} x {} points, domain u [{:.6g}, {:.6g}] v [{:.6g}, {:.6g}], {} loops\n",
             face.surface.degree_u, face.surface.degree_v, face.surface.count_u, face.surface.count_v, du.min, du.max,
             dv.min, dv.max, face.loops.size());
  for (size_t l = 0; l < face.loops.size(); ++l) {
    fmt::print("      loop {} ({}, {} curves, polygon area {:.6g}):\n", l, face.loops[l].outer ? "outer" : "inner",
               face.loops[l].curves.size(), nurbs::signed_area(trim.loops[l]));
    for (const auto& c : face.loops[l].curves) {
      const auto d = nurbs::curve_domain(c);
      const glm::dvec2 a = nurbs::curve_point(c, d.min), b = nurbs::curve_point(c, d.max);
      fmt::print("        deg {} ({:.6g}, {:.6g}) -> ({:.6g}, {:.6g})\n", c.degree, a.x, a.y, b.x, b.y);
    }
  }
  if (!of) return;
  fmt::print("    OCCT: {}, uv box u [{:.6g}, {:.6g}] v [{:.6g}, {:.6g}], orientation {}\n",
             of->surface->DynamicType()->Name(), of->u0, of->u1, of->v0, of->v1,
             of->face.Orientation() == TopAbs_REVERSED ? "reversed" : "forward");
  for (TopExp_Explorer w(of->face, TopAbs_WIRE); w.More(); w.Next()) {
    fmt::print("      wire{}:\n", TopoDS::Wire(w.Current()).IsSame(BRepTools::OuterWire(of->face)) ? " (outer)" : "");
    int edges = 0;
    for (TopExp_Explorer e(w.Current(), TopAbs_EDGE); e.More(); e.Next()) ++edges;
    fmt::print("        {} edges; in connection order (BRepTools_WireExplorer):\n", edges);
    for (BRepTools_WireExplorer e(TopoDS::Wire(w.Current()), of->face); e.More(); e.Next()) {
      double f = 0, l = 0;
      const auto pc = BRep_Tool::CurveOnSurface(e.Current(), of->face, f, l);
      if (pc.IsNull()) {
        fmt::print("        (no pcurve) tolerance {:.3g}\n", BRep_Tool::Tolerance(e.Current()));
        continue;
      }
      gp_Pnt2d a = pc->Value(f), b = pc->Value(l);
      if (e.Current().Orientation() == TopAbs_REVERSED) std::swap(a, b);
      fmt::print("        ({:.6g}, {:.6g}) -> ({:.6g}, {:.6g}) tolerance {:.3g}\n", a.X(), a.Y(), b.X(), b.Y(),
                 BRep_Tool::Tolerance(e.Current()));
    }
  }
  // Second opinion: OCCT's other 2D classifier (polygonised wires, as its mesher uses).
  const BRepTopAdaptor_FClass2d fclass(of->face, Precision::PConfusion());
  for (size_t k = 0; k < std::min<size_t>(far.size(), 5); ++k) {
    const TopAbs_State s = fclass.Perform(gp_Pnt2d(far[k].occt_uv.x, far[k].occt_uv.y));
    fmt::print(
        "      far sample (u, v) = ({:.6g}, {:.6g}) -> OCCT ({:.6g}, {:.6g}): nurbsgl {}, OCCT {} (FClass2d {})\n",
        far[k].uv.x, far[k].uv.y, far[k].occt_uv.x, far[k].occt_uv.y, far[k].ours ? "material" : "void",
        far[k].ours ? "void" : "material",
        s == TopAbs_IN   ? "in"
        : s == TopAbs_ON ? "on"
                         : "out");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nurbsgl trim classification vs OpenCASCADE's BRepClass_FaceClassifier, per shared IGES and STEP model"};
  std::string shared = std::string(NURBSGL_SHARED_DIR) + "/models", csv = "experiments/out/peer_occt_classify.csv";
  std::string only;
  int grid = 64, explain_max = 20;
  app.add_option("--shared", shared, "Folder of the shared models")->capture_default_str();
  app.add_option("--grid", grid, "Samples per face along u and v (cell centres)")->capture_default_str();
  app.add_option("--csv", csv, "Per-model CSV (per-face rows go beside it, *_faces.csv)")->capture_default_str();
  app.add_option("--explain", explain_max, "Faces with far disagreements whose loops are printed")
      ->capture_default_str();
  app.add_option("--only", only, "Only models whose path contains this");
  CLI11_PARSE(app, argc, argv);
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));

  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(shared)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".igs" || ext == ".iges" || ext == ".stp" || ext == ".step") &&
        e.path().string().find(only) != std::string::npos)
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  fs::create_directories(fs::absolute(csv).parent_path());
  std::ofstream out(csv), out_faces(fs::path(csv).replace_extension().string() + "_faces.csv");
  out << "model,faces,occt_faces,matched,samples,skipped,compared,on,near,far,far_fclass2d_agrees,nurbsgl_only,occt_"
         "only,rate\n";
  out_faces << "model,face,face_id,occt_face,match_distance,samples,skipped,compared,on,near,far,far_fclass2d_agrees,"
               "nurbsgl_only,occt_only\n";

  fmt::print("{:<40} {:>5} {:>5} {:>5} {:>8} {:>7} {:>4} {:>5} {:>4} {:>6} {:>9}\n", "model", "faces", "match", "occt",
             "compared", "skipped", "ON", "near", "far", "far*", "rate");
  fmt::print("  (far*: far disagreements where OCCT's BRepTopAdaptor_FClass2d sides with nurbsgl)\n");
  int explained = 0;
  for (const fs::path& path : files) {
    const std::string name = fs::relative(path, shared).string();
    const nurbs::Model model = nurbs::io::read_model(path);
    std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
    for (auto& f : faces)  // OCCT reads in millimetres; nurbsgl keeps file units
      for (auto& q : f.surface.points) q *= model.unit_scale_to_mm;
    const double size = nurbs::model_size(model) * model.unit_scale_to_mm;
    const double project_tol = 1e-6 * size, match_tol = 1e-4 * size;
    const std::vector<OcctFace> occ = occt_faces(path);
    Tally total;
    std::vector<std::string> unmatched, far_faces;
    std::vector<int> uses(occ.size(), 0);  // nurbsgl faces matched to each OCCT face
    for (size_t fi = 0; fi < faces.size(); ++fi) {
      const nurbs::TrimmedSurface& face = faces[fi];
      const auto du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
      const glm::dvec2 step(du.width() / grid, dv.width() / grid);
      const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, 0.1 * std::min(step.x, step.y));
      std::vector<glm::dvec2> uv;
      std::vector<uint8_t> ours;
      for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
          uv.emplace_back(du.min + (i + 0.5) * step.x, dv.min + (j + 0.5) * step.y);
          ours.push_back(nurbs::is_material(trim, uv.back()) ? 1 : 0);
        }

      // Match: the OCCT face within match_tol of most probes, then the smallest summed distance.
      std::vector<glm::dvec3> probes;
      for (glm::dvec2 p : probe_params(trim, uv, ours, step))
        probes.push_back(nurbs::surface_point(face.surface, p.x, p.y));
      int best = -1, best_hits = 0;
      double best_sum = HUGE_VAL;
      for (size_t o = 0; o < occ.size(); ++o) {
        Bnd_Box box = occ[o].box;
        box.Enlarge(match_tol);
        if (std::all_of(probes.begin(), probes.end(), [&](glm::dvec3 p) { return box.IsOut(to_gp(p)); })) continue;
        int hits = 0;
        double sum = 0;
        for (glm::dvec3 p : probes) {
          const double d = face_distance(occ[o], p);
          hits += d <= match_tol;
          sum += std::min(d, 1e300);
        }
        if (hits > best_hits || (hits == best_hits && hits > 0 && sum < best_sum))
          best = int(o), best_hits = hits, best_sum = sum;
      }
      Tally t;
      t.faces = 1;
      t.samples = long(uv.size());
      std::vector<FarSample> far;
      if (best < 0) {
        double nearest = HUGE_VAL;  // how far off: the nearest OCCT face to the first probe
        for (const OcctFace& o : occ) nearest = std::min(nearest, face_distance(o, probes.front()));
        unmatched.push_back(fmt::format("{} (id {}, {} material samples, nearest OCCT face {:.2e} x size)", fi,
                                        face.face_id, std::count(ours.begin(), ours.end(), 1), nearest / size));
      } else {
        t.matched = 1;
        ++uses[size_t(best)];
        const OcctFace& of = occ[size_t(best)];
        GeomAPI_ProjectPointOnSurf proj;
        std::unique_ptr<BRepTopAdaptor_FClass2d> fclass;  // second opinion, on far disagreements only
        double su0 = 0, su1 = 0, sv0 = 0, sv1 = 0;        // infinite bounds (planes): the face's box, widened
        of.surface->Bounds(su0, su1, sv0, sv1);
        const double wu = 10 * (of.u1 - of.u0) + 1, wv = 10 * (of.v1 - of.v0) + 1;
        if (Precision::IsInfinite(su0)) su0 = of.u0 - wu;
        if (Precision::IsInfinite(su1)) su1 = of.u1 + wu;
        if (Precision::IsInfinite(sv0)) sv0 = of.v0 - wv;
        if (Precision::IsInfinite(sv1)) sv1 = of.v1 + wv;
        proj.Init(of.surface, su0, su1, sv0, sv1, Precision::Confusion());
        for (size_t k = 0; k < uv.size(); ++k) {
          proj.Perform(to_gp(nurbs::surface_point(face.surface, uv[k].x, uv[k].y)));
          if (proj.NbPoints() == 0 || proj.LowerDistance() > project_tol) {
            ++t.skipped;
            continue;
          }
          double u = 0, v = 0;
          proj.LowerDistanceParameters(u, v);
          // Periodic surfaces: the projection returns the base period; the face's pcurves may sit in
          // another one.
          if (of.surface->IsUPeriodic()) {
            const double p = of.surface->UPeriod(), lo = of.u0 - 1e-9 * p;
            u -= std::floor((u - lo) / p) * p;
          }
          if (of.surface->IsVPeriodic()) {
            const double p = of.surface->VPeriod(), lo = of.v0 - 1e-9 * p;
            v -= std::floor((v - lo) / p) * p;
          }
          const TopAbs_State s = BRepClass_FaceClassifier(of.face, gp_Pnt2d(u, v), Precision::PConfusion()).State();
          ++t.compared;
          t.on += s == TopAbs_ON;
          const bool theirs = s == TopAbs_IN || s == TopAbs_ON;
          if (theirs == bool(ours[k])) continue;
          (ours[k] ? t.ours_only : t.occt_only)++;
          if (steps_to_trim(trim, uv[k], step) <= 2) {
            ++t.near;
          } else {
            ++t.far;
            if (!fclass) fclass = std::make_unique<BRepTopAdaptor_FClass2d>(of.face, Precision::PConfusion());
            const TopAbs_State s2 = fclass->Perform(gp_Pnt2d(u, v));
            t.far_fclass += (s2 == TopAbs_IN || s2 == TopAbs_ON) == bool(ours[k]);
            far.push_back({uv[k], {u, v}, bool(ours[k])});
          }
        }
      }
      out_faces << fmt::format("{},{},{},{},{:.3e},{},{},{},{},{},{},{},{},{}\n", name, fi, face.face_id, best,
                               best < 0 ? HUGE_VAL : best_sum / double(probes.size()), t.samples, t.skipped, t.compared,
                               t.on, t.near, t.far, t.far_fclass, t.ours_only, t.occt_only);
      if (t.far) {
        far_faces.push_back(fmt::format("{} (id {}): {} far, {} far*", fi, face.face_id, t.far, t.far_fclass));
        if (explained++ < explain_max) {
          fmt::print("  {} face {} (id {}, OCCT face {}): {} far, {} near of {} compared\n", name, fi, face.face_id,
                     best, t.far, t.near, t.compared);
          explain(face, trim, best < 0 ? nullptr : &occ[size_t(best)], far);
        }
      }
      total.add(t);
    }
    fmt::print("{:<40} {:>5} {:>5} {:>5} {:>8} {:>7} {:>4} {:>5} {:>4} {:>6} {:>8.4f}%\n", name, total.faces,
               total.matched, occ.size(), total.compared, total.skipped, total.on, total.near, total.far,
               total.far_fclass, 100 * total.rate());
    if (const auto twice = std::count_if(uses.begin(), uses.end(), [](int n) { return n > 1; }))
      fmt::print("  OCCT faces matched by more than one nurbsgl face: {}\n", twice);
    if (!unmatched.empty()) fmt::print("  unmatched faces: {}\n", fmt::join(unmatched, ", "));
    if (!far_faces.empty()) fmt::print("  faces with far disagreements: {}\n", fmt::join(far_faces, "; "));
    std::fflush(stdout);
    out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6e}\n", name, total.faces, occ.size(), total.matched,
                       total.samples, total.skipped, total.compared, total.on, total.near, total.far, total.far_fclass,
                       total.ours_only, total.occt_only, total.rate());
  }
  fmt::print("\nCSV: {}\n", csv);
  return 0;
}
