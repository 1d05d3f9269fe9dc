#pragma once
/// \file engine.h
/// Where a query runs: the one rule that resolves "auto", and how a front door gets a GL context
/// when its caller did not give one.
#include <functional>
#include <memory>

#include "gpgpu/gpu.h"
#include "queries/distance/point_batch.h"

namespace queries {

/// Where a batched descent runs, as asked: Auto resolves by choose_engine.
enum class EngineChoice { Auto, Gpu, Cpu };

/// The engine a request runs on: Auto is the CPU twin in double where the GL renderer rasterizes
/// on the CPU (llvmpipe: the float pass runs on the same cores, slower than the twin), the GPU
/// otherwise.
[[nodiscard]] BatchEngine choose_engine(EngineChoice choice, const gpgpu::Gpu& gpu);
[[nodiscard]] const char* engine_name(BatchEngine engine);   ///< "gpu" or "cpu"
[[nodiscard]] const char* engine_name(EngineChoice choice);  ///< "auto", "gpu" or "cpu"
/// "auto", "gpu" or "cpu" as EngineChoice; std::invalid_argument for another name.
[[nodiscard]] EngineChoice engine_choice(const std::string& name);

/// Starts a GL context when a front door needs one its caller did not give (the command line's
/// backend options; a test's shared context). May throw gpgpu::NoGlError.
using GpuStart = std::function<std::unique_ptr<gpgpu::Gpu>()>;

}  // namespace queries
