#include "gpgpu/exr_dump.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>

#include <stdexcept>
#include <system_error>

namespace gpgpu {
namespace {

/// Writes through `write` into a temporary file beside `path`, renamed to `path` once complete:
/// a failed dump leaves no partial file and keeps an older one.
template <class Write>
void write_via_temporary(const std::filesystem::path& path, Write write) {
  const std::filesystem::path tmp = path.parent_path() / ("." + path.filename().string() + ".tmp");
  std::error_code ec;
  try {
    write(tmp);
  } catch (const std::exception& e) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), e.what()));
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), ec.message()));
}

}  // namespace

void write_exr(const std::filesystem::path& path, const Texture& texture) {
  const int w = texture.width(), h = texture.height();
  if (!is_integer(texture.format())) {
    static const char* names[4] = {"R", "G", "B", "A"};
    ExrImage img{w, h, {}, texture.read()};
    img.channels.assign(names, names + channels(texture.format()));
    return write_exr(path, img);
  }
  std::vector<uint32_t> u = texture.read_u32();
  write_via_temporary(path, [&](const std::filesystem::path& tmp) {
    Imf::Header header(w, h);
    header.lineOrder() = Imf::INCREASING_Y;
    header.channels().insert("R", Imf::Channel(Imf::UINT));
    Imf::FrameBuffer fb;
    fb.insert("R",
              Imf::Slice(Imf::UINT, reinterpret_cast<char*>(u.data()), sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
    Imf::OutputFile file(tmp.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
  });
}

void write_exr(const std::filesystem::path& path, const ExrImage& image) {
  const size_t n = image.channels.size(), w = size_t(image.width);
  if (n == 0 || image.values.size() != w * size_t(image.height) * n)
    throw std::invalid_argument(fmt::format("write_exr {}: {} values for {} x {} x {} channels", path.string(),
                                            image.values.size(), image.width, image.height, n));
  write_via_temporary(path, [&](const std::filesystem::path& tmp) {
    Imf::Header header(image.width, image.height);
    header.lineOrder() = Imf::INCREASING_Y;
    Imf::FrameBuffer fb;
    auto* base = const_cast<float*>(image.values.data());  // Imf::Slice takes char*; writing only reads it
    for (size_t c = 0; c < n; ++c) {
      header.channels().insert(image.channels[c], Imf::Channel(Imf::FLOAT));
      fb.insert(image.channels[c],
                Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + c), sizeof(float) * n, sizeof(float) * n * w));
    }
    Imf::OutputFile file(tmp.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  });
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
