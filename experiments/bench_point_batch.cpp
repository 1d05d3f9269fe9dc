// Benchmark of the batched point projection (queries/distance/point_batch.h), not a test: it prints
// figures. On the generated 100 x 105 surface (models/paper_surfaces.h), untrimmed and trimmed, at a
// tolerance relative to the model size (default 1e-5): the one-time preparation (certified grid,
// atlas, box pyramid), then N random points (fixed seed) in one batch, in the model's box grown by a
// quarter and in the surface's z band, over the axis-aligned pyramid (the paper's boxes) and the
// oriented one: points per second, the GPU and CPU parts, cells tested, CPU fallbacks, bound / size;
// beside it the faithful per-point path (PointDistanceQuery::query) on a few of the same points,
// the cost of recomputing the winning cell's corners in double (4 surface_point per point), and,
// in the opt-in peer build (NURBSGL_PEER_BENCH), OpenCASCADE's GeomAPI_ProjectPointOnSurf.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <string>
#include <thread>

#include "bench_machine.h"
#include "models/paper_surfaces.h"
#include "models/random_surfaces.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/point_distance.h"

#ifdef NURBSGL_OCCT_PEER
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#endif

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

#ifdef NURBSGL_OCCT_PEER
/// Distinct knot values and their multiplicities (OCCT's form of a knot vector).
void occt_knots(const std::vector<double>& knots, std::vector<double>& values, std::vector<int>& mults) {
  for (double k : knots)
    if (values.empty() || k != values.back())
      values.push_back(k), mults.push_back(1);
    else
      ++mults.back();
}

/// Seconds per GeomAPI_ProjectPointOnSurf::Perform (initialised once on the surface) over
/// `points`, and the largest |d_occt - d_batch| over the points whose batched closest point is
/// inside the domain (OCCT returns orthogonal projections only, none for a closest point on the
/// boundary), with their count.
struct OcctFigures {
  double seconds = 0.0, worst = 0.0;
  int interior = 0;
};
OcctFigures occt_projection(const nurbs::Surface& s, const std::vector<glm::dvec3>& points,
                            const std::vector<queries::PointDistance>& batch) {
  std::vector<double> ku, kv;
  std::vector<int> mu, mv;
  occt_knots(s.knots_u, ku, mu);
  occt_knots(s.knots_v, kv, mv);
  TColStd_Array1OfReal aku(1, int(ku.size())), akv(1, int(kv.size()));
  TColStd_Array1OfInteger amu(1, int(mu.size())), amv(1, int(mv.size()));
  for (size_t i = 0; i < ku.size(); ++i) aku(int(i) + 1) = ku[i], amu(int(i) + 1) = mu[i];
  for (size_t i = 0; i < kv.size(); ++i) akv(int(i) + 1) = kv[i], amv(int(i) + 1) = mv[i];
  TColgp_Array2OfPnt poles(1, s.count_u, 1, s.count_v);
  TColStd_Array2OfReal weights(1, s.count_u, 1, s.count_v);
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i) {
      const size_t k = size_t(j) * size_t(s.count_u) + size_t(i);  // points row-major in v
      poles(i + 1, j + 1) = gp_Pnt(s.points[k].x, s.points[k].y, s.points[k].z);
      weights(i + 1, j + 1) = s.weights.empty() ? 1.0 : s.weights[k];
    }
  Handle(Geom_BSplineSurface) g = new Geom_BSplineSurface(poles, weights, aku, akv, amu, amv, s.degree_u, s.degree_v);
  const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
  OcctFigures f;
  const auto t0 = Clock::now();
  GeomAPI_ProjectPointOnSurf proj;
  proj.Init(g, du.min, du.max, dv.min, dv.max);
  std::vector<double> d(points.size(), -1.0);
  for (size_t i = 0; i < points.size(); ++i) {
    proj.Perform(gp_Pnt(points[i].x, points[i].y, points[i].z));
    if (proj.NbPoints() > 0) d[i] = proj.LowerDistance();
  }
  f.seconds = seconds_since(t0) / double(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec2 uv = batch[i].uv;
    const double margin = 1e-3 * std::min(du.width(), dv.width());
    if (d[i] < 0 || uv.x < du.min + margin || uv.x > du.max - margin || uv.y < dv.min + margin ||
        uv.y > dv.max - margin)
      continue;
    ++f.interior;
    f.worst = std::max(f.worst, std::abs(d[i] - batch[i].distance));
  }
  return f;
}
#endif

void run(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, const char* name, double rel, int count, int faithful) {
  const std::vector<nurbs::TrimmedSurface> faces{face};
  const nurbs::Box box = nurbs::control_box(face.surface);
  const double size = box.diagonal(), tol = rel * size;
  auto t0 = Clock::now();
  const queries::PreparedModel m = queries::prepare_model(gpu, faces, tol);
  gpu.finish();
  const double prepare_s = seconds_since(t0);
  t0 = Clock::now();
  queries::PointBatch aabb(gpu, m, queries::PointBoxes::Aabb);
  gpu.finish();
  const double aabb_s = seconds_since(t0);
  t0 = Clock::now();
  queries::PointBatch batch(gpu, m, queries::PointBoxes::Oriented);
  gpu.finish();
  const double pyramid_s = seconds_since(t0);
  const nurbs::ParamGrid& g = m.grids[0].grid;
  fmt::print(
      "{}: size {:.4g} mm, T = {:.3g} mm, grid {} x {} samples, prepared in {:.3f} s + pyramid {:.3f} s (oriented "
      "boxes; axis-aligned {:.3f} s, {} levels)\n",
      name, size, tol, g.u.size(), g.v.size(), prepare_s, pyramid_s, aabb_s, batch.levels(0));

  // Two distributions: the box grown by a quarter, and the surface's own z band (the wave band of the
  // paper surfaces: the points nearest to many cells at once).
  models::Random rng(2024);
  const glm::dvec3 pad = 0.25 * (box.max - box.min);
  std::vector<glm::dvec3> points, band;
  for (int i = 0; i < count; ++i) {
    points.emplace_back(rng.uniform(box.min.x - pad.x, box.max.x + pad.x),
                        rng.uniform(box.min.y - pad.y, box.max.y + pad.y),
                        rng.uniform(box.min.z - pad.z, box.max.z + pad.z));
    band.emplace_back(rng.uniform(box.min.x, box.max.x), rng.uniform(box.min.y, box.max.y),
                      rng.uniform(box.min.z, box.max.z));
  }
  std::vector<queries::PointDistance> res;
  double batch_s = 0.0;  // the oriented pyramid on the grown box: the figure compared with the peers below
  for (const auto* set : {&points, &band})
    for (queries::PointBatch* b : {&aabb, &batch}) {
      (void)b->query(std::span(*set).first(std::min<size_t>(set->size(), 64)));  // compile the kernel
      t0 = Clock::now();
      std::vector<queries::PointDistance> r = b->query(*set);
      const double seconds = seconds_since(t0);
      const queries::PointBatchStats st = b->stats();
      double worst_bound = 0.0;
      for (const auto& x : r) worst_bound = std::max(worst_bound, x.bound);
      fmt::print(
          "  batched, {}, {}: {} points in {:.3f} s = {:.0f} points/s (GPU pass + transfers {:.3f} s, CPU finishing "
          "{:.3f} s); {:.1f} cells tested per point, {} CPU fallbacks; bound <= {:.3g} = {:.3g} x size\n",
          set == &points ? "box grown by a quarter" : "z band", b == &aabb ? "axis-aligned boxes" : "oriented boxes",
          count, seconds, double(count) / seconds, st.gpu_seconds, st.cpu_seconds,
          double(st.cells_tested) / double(count), st.fallbacks, worst_bound, worst_bound / size);
      if (set == &points && b == &batch) res = std::move(r), batch_s = seconds;
    }

  // The corners of each winning cell recomputed in double on the surface (the option not taken).
  t0 = Clock::now();
  volatile double sink = 0.0;  // keeps the evaluations
  for (const auto& r : res) {
    const double du = 1e-3, dv = 1e-3;
    for (int k = 0; k < 4; ++k)
      sink = sink + nurbs::surface_point(face.surface, std::min(r.uv.x + du * (k & 1), 1.0),
                                         std::min(r.uv.y + dv * (k >> 1), 1.0))
                        .x;
  }
  const double recompute_s = seconds_since(t0);
  fmt::print("  recomputing 4 corners per point in double: {:.2f} us per point ({:.0f} points/s alone)\n",
             1e6 * recompute_s / double(count), double(count) / recompute_s);

  // The faithful per-point path on the first points.
  queries::PointDistanceQuery q(gpu, faces, tol);
  (void)q.query(points[0]);
  double worst = 0.0;
  t0 = Clock::now();
  for (int i = 0; i < faithful; ++i) {
    const queries::PointDistance r = q.query(points[size_t(i)]);
    worst = std::max(worst, std::abs(r.distance - res[size_t(i)].distance) / (r.bound + res[size_t(i)].bound));
  }
  const double per_point = seconds_since(t0) / double(faithful);
  fmt::print(
      "  faithful per point: {:.2f} ms per point = {:.0f} points/s; batched / faithful = {:.0f}x; "
      "|d - d_faithful| / (K + K_faithful) max {:.3g}\n",
      1e3 * per_point, 1.0 / per_point, double(count) / batch_s * per_point, worst);
#ifdef NURBSGL_OCCT_PEER
  if (!face.loops.empty()) return;  // a surface projection knows no trims
  const size_t n_occt = std::min<size_t>(points.size(), 500);
  const OcctFigures f =
      occt_projection(face.surface, std::vector(points.begin(), points.begin() + ptrdiff_t(n_occt)), res);
  fmt::print(
      "  OCCT GeomAPI_ProjectPointOnSurf::Perform: {:.3f} ms per point = {:.0f} points/s; batched / OCCT = "
      "{:.0f}x; |d_occt - d| max {:.3g} over the {} of {} points with an interior closest point\n",
      1e3 * f.seconds, 1.0 / f.seconds, double(count) / batch_s * f.seconds, f.worst, f.interior, n_occt);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Batched point projection on the generated 100 x 105 surface, untrimmed and trimmed"};
  std::string backend = "auto";
  double rel = 1e-5;
  int count = 200000, faithful = 20;
  std::string which = "both";
  app.add_option("--gl", backend, "GL backend: auto, egl, egl-device, osmesa, glfw")->capture_default_str();
  app.add_option("--tol", rel, "Tolerance relative to the model size")->capture_default_str();
  app.add_option("--points", count, "Points in the batch")->capture_default_str();
  app.add_option("--faithful", faithful, "Points for the faithful per-point path")->capture_default_str();
  app.add_option("--model", which, "plain, trimmed or both")->check(CLI::IsMember({"plain", "trimmed", "both"}));
  CLI11_PARSE(app, argc, argv);
  faithful = std::clamp(faithful, 1, count);
  gpgpu::Gpu gpu(gpgpu::ContextOptions{gpgpu::parse_backend(backend)});
  print_machine(gpu);
  nurbs::TrimmedSurface plain;
  plain.surface = models::wavy_surface_100x105();
  if (which != "trimmed") run(gpu, plain, "100x105", rel, count, faithful);
  if (which != "plain") run(gpu, models::trimmed_wavy_surface_100x105(), "100x105 trimmed", rel, count, faithful);
  return 0;
}
