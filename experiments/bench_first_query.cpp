// Benchmark of the first clearance query with evaluation (Table 1 configuration), not a
// test: it prints figures. The paper pair (models/paper_surfaces.h: 199 x 33 against 100 x 105,
// B at the "above" position of experiments/distance_tables.py) at a tolerance relative to the larger
// model (default 1e-5), coarse-to-fine or faithful:
//  - cold: the first pair of the process, as `nurbsgl clearance` runs it (every GL program compiled
//    or loaded from Mesa's shader cache and run for the first time inside the figure);
//  - warm: then `--repeat` fresh pairs in the same process, as in a process that has run a query
//    before: each one prepared from scratch (Filip bounds, certified grids, evaluation, trim masks,
//    growth) with a fresh cache of A's hierarchy, then its first query and a second one;
//  - with --compile-beside, the cold pair through the library's front door (queries::ClearancePair,
//    as `nurbsgl clearance` runs it: its programs compile while its geometry threads work; without,
//    each compiles at its first pass);
//  - with --prime, a pair of two 8 x 8 surfaces before the cold one: what the cold pair then still
//    loses against the warm ones is not the programs' first use.
// Per stage: bounds (wall of the two threads), grids, atlases; the first and second query.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench_machine.h"
#include "models/paper_surfaces.h"
#include "nurbs/model_ops.h"
#include "queries/distance/clearance.h"
#include "queries/distance/clearance_pair.h"
#include "queries/distance/prepared_model.h"

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct Run {
  double prepare = 0, bounds = 0, grids = 0, atlas = 0, first = 0, second = 0, distance = 0, bound = 0;
  [[nodiscard]] double total() const { return prepare + first; }
};

std::vector<nurbs::TrimmedSurface> face(nurbs::Surface s) {
  nurbs::TrimmedSurface f;
  f.surface = std::move(s);
  return {f};
}

Run run_pair(gpgpu::Gpu& gpu, double tolerance, queries::Search search, const glm::dmat4& motion,
             const queries::ClearanceLimits& limits, bool tiny = false) {
  Run r;
  const auto t0 = Clock::now();
  queries::PreparedPair p =
      tiny ? queries::prepare_pair(gpu, face(models::wavy_surface(8, 8, 200.0, 40.0, 5.0, 50.0, 40.0, 0.0, 0.0)),
                                   face(models::wavy_surface(8, 8, 100.0, 100.0, 4.0, 40.0, 30.0, 1.0, 20.0)),
                                   tolerance, search)
           : queries::prepare_pair(gpu, face(models::wavy_surface_199x33()), face(models::wavy_surface_100x105()),
                                   tolerance, search);
  gpu.finish();
  r.prepare = ms_since(t0);
  // Per-thread stage times: the two models' geometry runs side by side, so the larger one is the wall.
  r.bounds = 1e3 * std::max(p.a.bounds_seconds, p.b.bounds_seconds);
  r.grids = 1e3 * std::max(p.a.grids_seconds, p.b.grids_seconds);
  r.atlas = 1e3 * (p.a.atlas_seconds + p.b.atlas_seconds);
  queries::ClearanceCache cache;
  for (double* out : {&r.first, &r.second}) {
    const auto t1 = Clock::now();
    const queries::Clearance c = queries::clearance(gpu, p.a, p.b, motion, nullptr, nullptr, limits, &cache);
    *out = ms_since(t1);
    r.distance = c.distance;
    r.bound = c.bound;
  }
  return r;
}

nurbs::LoadedModel loaded(nurbs::Surface s) {
  nurbs::LoadedModel m;
  m.model.bodies.push_back({"", face(std::move(s)), glm::dmat4(1.0), ""});
  m.report = nurbs::model_report(m.model);
  return m;
}

/// The pair as `nurbsgl clearance` prepares and queries it: the library's front door
/// queries::ClearancePair on the GPU (the programs compiled while the geometry threads work, A's
/// hierarchy kept for the second query), each model at K_e = `tolerance` as the other rows (the
/// front door's tolerance is the answer's bound, the sum of the two).
Run run_front_door(gpgpu::Gpu& gpu, double tolerance, double size, queries::Search search, const glm::dmat4& motion,
                   const queries::ClearanceLimits& limits) {
  Run r;
  const auto t0 = Clock::now();
  const nurbs::LoadedModel a = loaded(models::wavy_surface_199x33()), b = loaded(models::wavy_surface_100x105());
  queries::ClearanceOptions o;
  o.tolerance = 2.0 * tolerance / size;
  o.search = search;
  o.limits = limits;
  o.engine = queries::EngineChoice::Gpu;
  queries::ClearancePair pair(a, &b, o, &gpu);
  pair.prepare({&motion, 1});
  r.prepare = ms_since(t0);
  const queries::PreparedModel &pa = pair.prepared_a(), &pb = pair.prepared_b();
  r.bounds = 1e3 * std::max(pa.bounds_seconds, pb.bounds_seconds);
  r.grids = 1e3 * std::max(pa.grids_seconds, pb.grids_seconds);
  r.atlas = 1e3 * (pa.atlas_seconds + pb.atlas_seconds);
  for (double* out : {&r.first, &r.second}) {
    const auto t1 = Clock::now();
    const queries::ClearanceAnswer c = pair.query(motion);
    *out = ms_since(t1);
    r.distance = c.clearance.distance;
    r.bound = c.clearance.bound;
  }
  return r;
}

void print(const char* what, const Run& r) {
  fmt::print("{:<8} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f}   {:.6f} +- {:.2g}\n", what,
             r.prepare, r.bounds, r.grids, r.atlas, r.first, r.total(), r.second, r.distance, r.bound);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"First clearance query with evaluation on the paper pair (Table 1), cold and warm"};
  std::string backend = "auto", search = "coarse-to-fine";
  double rel = 1e-5;
  int repeat = 9, threads = -1;
  bool prime = false, passes = false, beside = false;
  queries::ClearanceLimits limits;
  app.add_option("--gl", backend, "GL backend: auto, egl, egl-device, osmesa, glfw")->capture_default_str();
  app.add_option("--gl-threads", threads, "llvmpipe's rasterizer threads (LP_NUM_THREADS; -1: one per core)")
      ->capture_default_str();
  app.add_option("--tol", rel, "Tolerance relative to the larger model's size")->capture_default_str();
  app.add_option("--repeat", repeat, "Warm pairs after the cold one")->capture_default_str();
  app.add_option("--search", search, "coarse-to-fine or faithful")
      ->check(CLI::IsMember({"coarse-to-fine", "faithful"}))
      ->capture_default_str();
  app.add_option("--host-pairs", limits.host_pairs,
                 "Descent levels of at most this many child pairs pruned on the CPU (0: all on the GPU; -1: auto)")
      ->capture_default_str();
  app.add_flag("--prime", prime,
               "Before the cold pair, one on two 8 x 8 surfaces: every program's first use without the paper "
               "pair's sizes");
  app.add_flag("--compile-beside", beside,
               "The cold pair through the library's front door, as `nurbsgl clearance` runs it: the programs "
               "compiled while its geometry threads work");
  app.add_flag("--passes", passes,
               "Time every pass (synchronised) and print them for the cold pair and for the warm ones: what "
               "each program's first use costs");
  CLI11_PARSE(app, argc, argv);
  gpgpu::ContextOptions context{gpgpu::parse_backend(backend)};
  context.software_threads = threads;
  gpgpu::Gpu gpu(context);
  print_machine(gpu);
  auto size = [](nurbs::Surface s) {
    nurbs::Model m;
    m.bodies.push_back({"", face(std::move(s)), glm::dmat4(1.0), ""});
    return nurbs::model_size(m);
  };
  const double tolerance = rel * std::max(size(models::wavy_surface_199x33()), size(models::wavy_surface_100x105()));
  const auto s = search == "faithful" ? queries::Search::Faithful : queries::Search::CoarseToFine;
  const glm::dmat4 above(1.0);  // B as generated: 11.1 above A's crest
  fmt::print("paper pair, {}, tolerance {:.3g} (ms)\n", search, tolerance);
  fmt::print("{:<8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}   distance\n", "", "prepare", "bounds", "grids", "atlas",
             "1st", "prep+1st", "2nd");
  if (prime) print("8 x 8", run_pair(gpu, tolerance, s, above, limits, true));
  gpu.profiler().set_enabled(passes);
  gpu.profiler().set_sync(passes);
  print("cold", beside ? run_front_door(gpu, tolerance, tolerance / rel, s, above, limits) : run_pair(gpu, tolerance, s, above, limits));
  std::string cold_passes = gpu.profiler().table();
  gpu.profiler().reset();
  if (repeat <= 0) {
    if (passes) fmt::print("\npasses of the cold pair:\n{}", cold_passes);
    return 0;
  }
  std::vector<Run> warm;
  for (int k = 0; k < repeat; ++k) warm.push_back(run_pair(gpu, tolerance, s, above, limits));
  auto med = [&](double Run::*f) {
    std::vector<double> v;
    for (const Run& r : warm) v.push_back(r.*f);
    return median(v);
  };
  Run m{med(&Run::prepare), med(&Run::bounds), med(&Run::grids),    med(&Run::atlas),
        med(&Run::first),   med(&Run::second), med(&Run::distance), med(&Run::bound)};
  print("warm", m);
  if (passes)
    fmt::print("\npasses of the cold pair:\n{}\npasses of the {} warm pairs:\n{}", cold_passes, warm.size(),
               gpu.profiler().table());
  std::vector<double> totals;
  for (const Run& r : warm) totals.push_back(r.total());
  fmt::print(
      "warm prepare + first query: median {:.1f} ms (each column its own median), range {:.1f}-{:.1f} ms "
      "over {} pairs\n",
      median(totals), *std::min_element(totals.begin(), totals.end()), *std::max_element(totals.begin(), totals.end()),
      totals.size());
  return 0;
}
