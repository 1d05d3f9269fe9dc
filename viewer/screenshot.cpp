#include "viewer/screenshot.h"

#include <stb_image_write.h>

#include <cstring>
#include <stdexcept>
#include <vector>

#include "gpgpu/gl_api.h"
#include "viewer/gl_extra.h"

namespace viewer {

void write_screenshot(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) throw std::runtime_error(path + ": the window has no pixels");
  std::vector<unsigned char> pixels(static_cast<size_t>(width) * height * 3);
  gpgpu::gl::BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glx::ReadBuffer(GL_BACK);
  gpgpu::gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  glx::ReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  gpgpu::gl::check_error("viewer screenshot read-back");
  // GL's rows run bottom to top, PNG's top to bottom.
  const size_t row = static_cast<size_t>(width) * 3;
  std::vector<unsigned char> flipped(pixels.size());
  for (int y = 0; y < height; ++y)
    std::memcpy(&flipped[static_cast<size_t>(height - 1 - y) * row], &pixels[static_cast<size_t>(y) * row], row);
  if (stbi_write_png(path.c_str(), width, height, 3, flipped.data(), static_cast<int>(row)) == 0)
    throw std::runtime_error(path + ": cannot write the PNG");
}

}  // namespace viewer
