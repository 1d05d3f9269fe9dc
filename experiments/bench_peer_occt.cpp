// Peer benchmark against OpenCASCADE (built only when OCCT is installed: scripts/bench.sh installs
// it). Same machine, same run, same inputs; prints figures and the peer ratio, asserts nothing.
//  1. Surface evaluation of the paper's 100x105 bicubic surface on N x N grids: nurbsgl on the GPU
//     (points + normals, tabulated method, synchronised) vs OCCT Geom_BSplineSurface::D1 + cross
//     product on one CPU core, and nurbsgl's double CPU twin.
//  2. Reading the shared IGES models: nurbs::io::read_iges vs IGESControl_Reader (ReadFile +
//     TransferRoots), face counts side by side.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <Geom_BSplineSurface.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Standard_Version.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <chrono>
#include <filesystem>
#include <map>

#include "gpgpu/gpu.h"
#include "models/paper_surfaces.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/surface_grid.h"

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// The same surface as an OCCT Geom_BSplineSurface (knots as distinct values + multiplicities).
Handle(Geom_BSplineSurface) to_occt(const nurbs::Surface& s) {
  auto knots = [](const std::vector<double>& k, TColStd_Array1OfReal*& values, TColStd_Array1OfInteger*& mults) {
    std::vector<std::pair<double, int>> distinct;
    for (double x : k) {
      if (!distinct.empty() && distinct.back().first == x)
        ++distinct.back().second;
      else
        distinct.emplace_back(x, 1);
    }
    values = new TColStd_Array1OfReal(1, int(distinct.size()));
    mults = new TColStd_Array1OfInteger(1, int(distinct.size()));
    for (size_t i = 0; i < distinct.size(); ++i) {
      values->SetValue(int(i) + 1, distinct[i].first);
      mults->SetValue(int(i) + 1, distinct[i].second);
    }
  };
  TColStd_Array1OfReal *ku = nullptr, *kv = nullptr;
  TColStd_Array1OfInteger *mu = nullptr, *mv = nullptr;
  knots(s.knots_u, ku, mu);
  knots(s.knots_v, kv, mv);
  TColgp_Array2OfPnt poles(1, s.count_u, 1, s.count_v);
  TColStd_Array2OfReal weights(1, s.count_u, 1, s.count_v);
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i) {
      const glm::dvec3& p = s.point(i, j);
      poles.SetValue(i + 1, j + 1, gp_Pnt(p.x, p.y, p.z));
      weights.SetValue(i + 1, j + 1, s.weight(i, j));
    }
  Handle(Geom_BSplineSurface) g =
      s.rational() ? new Geom_BSplineSurface(poles, weights, *ku, *kv, *mu, *mv, s.degree_u, s.degree_v)
                   : new Geom_BSplineSurface(poles, *ku, *kv, *mu, *mv, s.degree_u, s.degree_v);
  delete ku;
  delete kv;
  delete mu;
  delete mv;
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nurbsgl vs OpenCASCADE: surface evaluation and IGES reading, same machine, same run"};
  std::string backend = "auto", shared = std::string(NURBSGL_SHARED_DIR) + "/models";
  int max_grid = 2048;
  app.add_option("--gl", backend, "GL backend")->capture_default_str();
  app.add_option("--max-grid", max_grid, "Largest grid side")->capture_default_str();
  app.add_option("--shared", shared, "Folder of the shared models")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  // OCCT's reader prints progress to stdout: keep the table readable.
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  gpgpu::Gpu gpu(gpgpu::ContextOptions{gpgpu::parse_backend(backend)});
  fmt::print("nurbsgl on {} ({}) vs OpenCASCADE {} on one CPU core\n\n", gpu.info().renderer, gpu.info().backend,
             OCC_VERSION_COMPLETE);

  const nurbs::Surface s = models::wavy_surface_100x105();
  Handle(Geom_BSplineSurface) occ = to_occt(s);
  const queries::GpuSurface g = queries::upload_surface(s, gpu.info().max_texture_size);
  (void)queries::evaluate_surface(gpu, g, 1, 1);  // compile
  fmt::print("surface evaluation, 100x105 bicubic (points + normals)\n{:>6} {:>12} {:>12} {:>12} {:>10} {:>12}\n",
             "grid", "nurbsgl GPU", "nurbsgl CPU", "OCCT D1", "OCCT/GPU", "max |diff|");
  for (int n = 256; n <= max_grid; n *= 2) {
    gpu.finish();
    auto t0 = Clock::now();
    queries::SurfaceGrid grid = queries::evaluate_surface(gpu, g, n - 1, n - 1);
    gpu.finish();
    const double gpu_ms = ms_since(t0);
    t0 = Clock::now();
    const queries::SurfaceGridCpu cpu = queries::evaluate_surface_cpu(s, n - 1, n - 1);
    const double cpu_ms = ms_since(t0);
    t0 = Clock::now();
    std::vector<gp_Pnt> occ_points(size_t(n) * n);
    std::vector<gp_Vec> occ_normals(occ_points.size());
    const double u0 = s.knots_u[3], u1 = s.knots_u[size_t(s.count_u)], v0 = s.knots_v[3],
                 v1 = s.knots_v[size_t(s.count_v)];
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        gp_Vec du, dv;
        const size_t k = size_t(j) * n + i;
        occ->D1(u0 + (u1 - u0) * i / (n - 1), v0 + (v1 - v0) * j / (n - 1), occ_points[k], du, dv);
        occ_normals[k] = du.Crossed(dv);
      }
    const double occ_ms = ms_since(t0);
    double diff = 0;
    for (size_t k = 0; k < cpu.points.size(); ++k)
      diff = std::max(diff, occ_points[k].Distance(gp_Pnt(cpu.points[k].x, cpu.points[k].y, cpu.points[k].z)));
    fmt::print("{:>6} {:>9.1f} ms {:>9.1f} ms {:>9.1f} ms {:>9.2f}x {:>12.2e}\n", n, gpu_ms, cpu_ms, occ_ms,
               occ_ms / gpu_ms, diff);
  }

  fmt::print("\nIGES reading (faces / ms)\n{:<38} {:>16} {:>16} {:>10}\n", "model", "nurbsgl", "OCCT", "OCCT/ours");
  for (const char* f :
       {"iges/occt_bearing.iges", "iges/occt_hammer.iges", "iges/pythonocc_example_45_faces.iges",
        "iges/pythonocc_sunglasses_lens.igs", "generated/teapot_bezier32.igs", "generated/vase_shell_t2.igs"}) {
    const std::filesystem::path path = std::filesystem::path(shared) / f;
    if (!std::filesystem::exists(path)) {
      fmt::print("{:<38} (absent)\n", f);
      continue;
    }
    auto t0 = Clock::now();
    const nurbs::Model m = nurbs::io::read_iges(path);
    const double ours_ms = ms_since(t0);
    size_t ours_faces = 0;
    for (const auto& b : m.bodies) ours_faces += b.faces.size();
    t0 = Clock::now();
    IGESControl_Reader reader;
    reader.ReadFile(path.c_str());
    reader.TransferRoots();
    const TopoDS_Shape shape = reader.OneShape();
    const double occ_ms = ms_since(t0);
    int occ_faces = 0;
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) ++occ_faces;
    fmt::print("{:<38} {:>5} / {:>7.1f} {:>5} / {:>7.1f} {:>9.1f}x\n", f, ours_faces, ours_ms, occ_faces, occ_ms,
               occ_ms / ours_ms);
  }
  return 0;
}
