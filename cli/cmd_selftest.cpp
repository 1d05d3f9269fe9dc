// `nurbsgl selftest`: the GPU co-processor end to end on random data — one min reduction, one
// argmin and one stream compaction, each against its CPU twin, with wall-clock timings.
#include <fmt/format.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <random>

#include "cli/commands.h"
#include "cli/validators.h"
#include "gpgpu/compact.h"
#include "gpgpu/reduce.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace cmd_selftest_impl {

struct Options {
  int size = 1024;
  double density = 0.5;
  bool json = false;
};

template <class F>
double time_ms(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void run(const GlobalOptions& global, const Options& o) {
  auto gpu = start_gpu(global);
  const int n = o.size;
  std::mt19937_64 rng(1);
  std::vector<float> values(size_t(n) * n);
  std::vector<uint8_t> keep(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    values[i] = static_cast<float>(double(rng() >> 11) * 0x1.0p-53 * 2000.0 - 1000.0);
    keep[i] = double(rng() >> 11) * 0x1.0p-53 < o.density ? 255 : 0;
  }
  gpgpu::Texture data(n, n, gpgpu::Format::R32F), mask(n, n, gpgpu::Format::R8);
  data.upload(values);
  mask.upload(keep);

  // Warm-up compiles the programs; the timed runs below include the read-back of the results.
  (void)gpgpu::reduce_min(*gpu, data);
  (void)gpgpu::argmin(*gpu, data);
  (void)gpgpu::compact(*gpu, mask, data);
  gpu->finish();
  gpu->profiler().reset();

  float gmin = 0;
  gpgpu::ArgMin garg;
  gpgpu::Compacted comp;
  std::vector<float> kept;
  const double t_min = time_ms([&] { gmin = gpgpu::reduce_min(*gpu, data); });
  const double t_arg = time_ms([&] { garg = gpgpu::argmin(*gpu, data); });
  const double t_cmp = time_ms([&] {
    comp = gpgpu::compact(*gpu, mask, data);
    kept = comp.read_records();
  });
  gpu->dump("selftest_data", data);

  const auto cmin = gpgpu::reduce_cpu(
      values, 1, {gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min, gpgpu::ReduceOp::Min});
  const gpgpu::ArgMin carg = gpgpu::argmin_cpu(values, n, 1, 0);
  std::vector<float> expect;
  for (size_t i = 0; i < values.size(); ++i)
    if (keep[i]) expect.push_back(values[i]);
  const bool ok_min = double(gmin) == cmin[0];
  const bool ok_arg = garg.found && garg.index == carg.index && garg.value == carg.value;
  const bool ok_cmp = kept == expect;
  const double mtex = double(n) * n * 1e-3;  // texels / ms -> Mtexel/s

  if (o.json) {
    nlohmann::json j{{"backend", gpu->info().backend},
                     {"renderer", gpu->info().renderer},
                     {"size", n},
                     {"min", {{"ok", ok_min}, {"ms", t_min}, {"value", gmin}}},
                     {"argmin", {{"ok", ok_arg}, {"ms", t_arg}, {"index", garg.index}}},
                     {"compaction", {{"ok", ok_cmp}, {"ms", t_cmp}, {"kept", comp.count}, {"levels", comp.levels}}}};
    print_json(j);
  } else {
    fmt::print("GPU self-check on {} ({}, {})\n", gpu->info().renderer, gpu->info().backend, gpu->info().detail);
    fmt::print("  min reduction   {}x{}  {:8.2f} ms  {:8.1f} Mtexel/s  {}\n", n, n, t_min, mtex / t_min,
               ok_min ? "OK (= CPU twin)" : "MISMATCH");
    fmt::print("  argmin          {}x{}  {:8.2f} ms  {:8.1f} Mtexel/s  {}\n", n, n, t_arg, mtex / t_arg,
               ok_arg ? "OK (= CPU twin)" : "MISMATCH");
    fmt::print("  compaction      {}x{}  {:8.2f} ms  {:8.1f} Mtexel/s  {} ({} kept, {} levels, incl. read-back)\n", n,
               n, t_cmp, mtex / t_cmp, ok_cmp ? "OK (= std::copy_if)" : "MISMATCH", comp.count, comp.levels);
  }
  report_profile(*gpu, global);
  if (!ok_min || !ok_arg || !ok_cmp) throw CommandFailed("GPU results differ from the CPU twins");
}

}  // namespace cmd_selftest_impl

void add_selftest(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_selftest_impl;
  auto* cmd = app.add_subcommand(
      "selftest", "Run a min reduction, an argmin and a stream compaction on the GPU against their CPU twins");
  auto o = std::make_shared<Options>();
  cmd->add_option("--size", o->size, "Side of the square test texture")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--density", o->density, "Fraction of texels the compaction keeps")
      ->check(finite_range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([&global, o] { run(global, *o); });
}

}  // namespace cli
