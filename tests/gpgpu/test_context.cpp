// Context backends: the one under test (NURBSGL_GL) starts with a 4.5 core context and float
// render targets; backend names parse; an unknown name is rejected with the valid list; a software
// renderer is recognised, and noted when the EGL device platform lists hardware.
#include <doctest/doctest.h>

#include <cstdlib>

#include "gl_fixture.h"

TEST_CASE("context: 4.5 core with float render targets") {
  const gpgpu::ContextInfo& info = test::gpu().info();
  CHECK(!info.renderer.empty());
  CHECK(info.gl_version.rfind("4.", 0) == 0);
  CHECK(info.max_texture_size >= 4096);  // GL 4.5 minimum is 16384; Mesa gives 16384
  CHECK(info.max_texture_units >= 16);   // GL 4.5 minimum
  CHECK(info.float_targets_ok);
  // The backend asked for is the one that started (no silent fallback).
  if (const char* env = std::getenv("NURBSGL_GL"); env && *env && std::string(env) != "auto")
    CHECK(info.backend == std::string(env));
}

TEST_CASE("context: backend names") {
  using gpgpu::Backend;
  for (Backend b : {Backend::Auto, Backend::Egl, Backend::EglDevice, Backend::OSMesa, Backend::Glfw})
    CHECK(gpgpu::parse_backend(gpgpu::backend_name(b)) == b);
  CHECK_THROWS_WITH_AS(gpgpu::parse_backend("vulkan"),
                       "unknown GL backend 'vulkan' (choose auto, egl, egl-device, osmesa or glfw)",
                       std::invalid_argument);
}

TEST_CASE("context: a software renderer is named as such, and says so when hardware is listed") {
  CHECK(gpgpu::software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  CHECK(gpgpu::software_renderer("softpipe"));
  CHECK(gpgpu::software_renderer("Software Rasterizer (swrast)"));
  CHECK_FALSE(gpgpu::software_renderer("NVIDIA H200/PCIe/SSE2"));
  CHECK_FALSE(gpgpu::software_renderer("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.7, DRM 3.54)"));
  // The note exists exactly when the renderer is software and the device platform lists hardware.
  const gpgpu::ContextInfo& info = test::gpu().info();
  const bool hardware_listed = !gpgpu::detail::egl_hardware_devices().empty();
  CHECK(!info.hardware_unused.empty() == (gpgpu::software_renderer(info.renderer) && hardware_listed));
}
