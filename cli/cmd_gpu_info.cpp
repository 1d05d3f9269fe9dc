// `nurbsgl gpu-info`: which backend started and what the GPU offers.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"

namespace cli {

void add_gpu_info(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand("gpu-info", "Print the GL backend, version, renderer and limits");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print one JSON object instead of text");
  cmd->callback([&global, json] {
    auto gpu = start_gpu(global);
    const gpgpu::ContextInfo& i = gpu->info();
    if (*json) {
      nlohmann::json j{{"backend", i.backend},
                       {"context", i.detail},
                       {"gl_version", i.gl_version},
                       {"glsl_version", i.glsl_version},
                       {"renderer", i.renderer},
                       {"vendor", i.vendor},
                       {"max_texture_size", i.max_texture_size},
                       {"memory_bytes", i.memory_bytes},
                       {"max_texture_units", i.max_texture_units},
                       {"float_targets_ok", i.float_targets_ok},
                       {"timer_queries", i.timer_queries},
                       {"software_threads", i.software_threads},
                       {"software_renderer", gpgpu::software_renderer(i.renderer)},
                       {"hardware_unused", i.hardware_unused}};
      print_json(j);
      return;
    }
    fmt::print("backend            {}\n", i.backend);
    fmt::print("context            {}\n", i.detail);
    fmt::print("GL version         {}\n", i.gl_version);
    fmt::print("GLSL version       {}\n", i.glsl_version);
    fmt::print("renderer           {}\n", i.renderer);
    fmt::print("vendor             {}\n", i.vendor);
    fmt::print("max texture size   {}\n", i.max_texture_size);
    fmt::print("memory             {}\n", i.memory_bytes > 0 ? fmt::format("{:.1f} GB", double(i.memory_bytes) / 1e9)
                                                             : std::string("not stated by the GL"));
    fmt::print("texture units      {}\n", i.max_texture_units);
    fmt::print("float targets      {}\n", i.float_targets_ok ? "OK (R32F, RG32F, RGBA32F unclamped)" : "NOT OK");
    fmt::print("timer queries      {}\n", i.timer_queries ? "yes" : "no");
    fmt::print("LP_NUM_THREADS     {}\n",
               i.software_threads.empty() ? "(not set: llvmpipe's default)" : i.software_threads);
    if (!i.hardware_unused.empty()) fmt::print("hardware unused    {}\n", i.hardware_unused);
    report_profile(*gpu, global);
    if (!i.float_targets_ok) throw CommandFailed("float render targets do not work on this GL");
  });
}

}  // namespace cli
