#include "cli/common.h"

#include <fmt/format.h>

namespace cli {

std::unique_ptr<gpgpu::Gpu> start_gpu(const GlobalOptions& options) {
  gpgpu::ContextOptions ctx;
  ctx.backend = options.gl.empty() ? gpgpu::backend_from_env() : gpgpu::parse_backend(options.gl);
  auto gpu = std::make_unique<gpgpu::Gpu>(ctx);
  if (!options.dump_dir.empty()) gpu->set_dump_dir(options.dump_dir);
  gpu->profiler().set_enabled(options.profile);
  gpu->profiler().set_sync(options.profile);
  return gpu;
}

void report_profile(gpgpu::Gpu& gpu, const GlobalOptions& options) {
  if (options.profile) fmt::print(stderr, "\n{}", gpu.profiler().table());
}

}  // namespace cli
