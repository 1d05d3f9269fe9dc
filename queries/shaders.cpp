#include "queries/shaders.h"

namespace queries {

gpgpu::Program& program(gpgpu::Gpu& gpu, std::string_view name, const gpgpu::Defines& defines) {
  if (!gpu.shaders().contains("raycast.frag")) {
    gpu.shaders().add(gpgpu::distance_glsl(), "glsl/distance/");
    gpu.shaders().add(gpgpu::raycast_glsl(), "glsl/raycast/");
  }
  return gpu.program(std::string(name), defines);
}

}  // namespace queries
