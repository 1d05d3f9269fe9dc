#include "gpgpu/exr_dump.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>

#include <stdexcept>

namespace gpgpu {

void write_exr(const std::filesystem::path& path, const Texture& texture) {
  const int w = texture.width(), h = texture.height();
  Imf::Header header(w, h);
  header.lineOrder() = Imf::INCREASING_Y;
  Imf::FrameBuffer fb;
  std::vector<float> f;
  std::vector<uint32_t> u;
  static const char* names[4] = {"R", "G", "B", "A"};
  try {
    if (is_integer(texture.format())) {
      u = texture.read_u32();
      header.channels().insert("R", Imf::Channel(Imf::UINT));
      fb.insert("R", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(u.data()), sizeof(uint32_t),
                                sizeof(uint32_t) * size_t(w)));
    } else {
      f = texture.read();
      const int n = channels(texture.format());
      for (int c = 0; c < n; ++c) {
        header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(f.data() + c), sizeof(float) * n,
                                       sizeof(float) * n * size_t(w)));
      }
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), e.what()));
  }
}

ExrImage read_exr(const std::filesystem::path& path) {
  ExrImage img;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
      img.channels.emplace_back(it.name());
    const size_t n = img.channels.size();
    img.values.resize(size_t(img.width) * img.height * n);
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < n; ++c) {
      char* base = reinterpret_cast<char*>(img.values.data() + c) -
                   (dw.min.x + size_t(dw.min.y) * img.width) * n * sizeof(float);
      fb.insert(img.channels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float) * n, sizeof(float) * n * img.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("cannot read {}: {}", path.string(), e.what()));
  }
  return img;
}

}  // namespace gpgpu
