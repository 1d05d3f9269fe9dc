// Benchmark of the gpgpu/ layer (not a test: it prints figures, asserts nothing about speed).
// Per backend: per-pass overhead, min-reduction and compaction throughput at 256^2..4096^2,
// upload and read-back bandwidth. Run once per backend: `bench_gpgpu --gl egl`, `--gl osmesa`.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <random>

#include "gpgpu/compact.h"
#include "gpgpu/gpu.h"
#include "gpgpu/reduce.h"

namespace {

using Clock = std::chrono::steady_clock;

/// Median wall time in ms of `reps` runs of f (each ends synchronised).
template <class F>
double median_ms(int reps, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmark of nurbsgl's GPU co-processor layer (passes, reductions, compaction, transfers)"};
  std::string backend = "auto";
  int max_size = 4096, reps = 5;
  bool json = false;
  app.add_option("--gl", backend, "GL backend: auto, egl, egl-device, osmesa, glfw")->capture_default_str();
  app.add_option("--max-size", max_size, "Largest square size")->capture_default_str();
  app.add_option("--reps", reps, "Repetitions per figure (median)")->capture_default_str();
  app.add_flag("--json", json, "Print JSON");
  CLI11_PARSE(app, argc, argv);

  gpgpu::Gpu gpu(gpgpu::ContextOptions{gpgpu::parse_backend(backend)});
  nlohmann::json out{
      {"backend", gpu.info().backend}, {"renderer", gpu.info().renderer}, {"context", gpu.info().detail}};
  auto say = [&](const std::string& s) {
    if (!json) fmt::print("{}\n", s);
  };
  say(fmt::format("backend {} ({}) on {}", gpu.info().backend, gpu.info().detail, gpu.info().renderer));

  // Per-pass overhead: many 1x1 passes, one finish.
  {
    gpgpu::Texture a(1, 1, gpgpu::Format::RGBA32F), b(1, 1, gpgpu::Format::RGBA32F);
    a.upload(std::vector<float>{0, 0, 0, 0});
    gpgpu::Program& add = gpu.program("add_constant.frag");
    add.set("u_value", 1.0f, 1.0f, 1.0f, 1.0f);
    const gpgpu::Input in[] = {{"u_src", &a}};
    gpgpu::Texture* o[] = {&b};
    const int passes = 2000;
    const double ms = median_ms(reps, [&] {
      for (int i = 0; i < passes; ++i) gpu.run("tiny", add, in, o);
      gpu.finish();
    });
    out["pass_overhead_us"] = ms * 1e3 / passes;
    say(fmt::format("per-pass overhead (1x1 pass)        {:8.1f} us", ms * 1e3 / passes));
  }

  std::mt19937_64 rng(3);
  say(fmt::format("{:>6} {:>12} {:>12} {:>14} {:>14} {:>12} {:>12}", "size", "min ms", "min Mtex/s", "compact1% ms",
                  "compact50% ms", "upload GB/s", "read GB/s"));
  for (int n = 256; n <= max_size; n *= 2) {
    const size_t count = size_t(n) * n;
    std::vector<float> v(count * 4);
    for (float& x : v) x = float(double(rng() >> 11) * 0x1.0p-53);
    gpgpu::Texture data(n, n, gpgpu::Format::R32F), rgba(n, n, gpgpu::Format::RGBA32F);
    data.upload(std::span<const float>(v.data(), count));
    const double up_ms = median_ms(reps, [&] {
      rgba.upload(v);
      gpu.finish();
    });
    const double read_ms = median_ms(reps, [&] { (void)rgba.read(); });
    (void)gpgpu::reduce_min(gpu, data);  // compile
    const double min_ms = median_ms(reps, [&] { (void)gpgpu::reduce_min(gpu, data); });
    double compact_ms[2];
    int k = 0;
    for (double density : {0.01, 0.5}) {
      gpgpu::Texture mask(n, n, gpgpu::Format::R32F);
      std::vector<float> m(count);
      for (size_t i = 0; i < count; ++i) m[i] = v[i] < density ? 1.0f : 0.0f;
      mask.upload(m);
      (void)gpgpu::compact(gpu, mask, rgba);
      compact_ms[k++] = median_ms(reps, [&] {
        (void)gpgpu::compact(gpu, mask, rgba);
        gpu.finish();
      });
    }
    const double bytes = double(count) * 16;
    out["sizes"].push_back({{"size", n},
                            {"min_ms", min_ms},
                            {"min_mtexel_s", double(count) / min_ms * 1e-3},
                            {"compact_1pct_ms", compact_ms[0]},
                            {"compact_50pct_ms", compact_ms[1]},
                            {"upload_gb_s", bytes / up_ms * 1e-6},
                            {"readback_gb_s", bytes / read_ms * 1e-6}});
    say(fmt::format("{:>6} {:>12.2f} {:>12.1f} {:>14.2f} {:>14.2f} {:>12.2f} {:>12.2f}", n, min_ms,
                    double(count) / min_ms * 1e-3, compact_ms[0], compact_ms[1], bytes / up_ms * 1e-6,
                    bytes / read_ms * 1e-6));
  }
  if (json) fmt::print("{}\n", out.dump(2));
  return 0;
}
