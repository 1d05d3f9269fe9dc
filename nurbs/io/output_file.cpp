#include "nurbs/io/output_file.h"

#include <unistd.h>

#include <fstream>
#include <system_error>

namespace nurbs::io {
namespace {

std::filesystem::path temporary_beside(const std::filesystem::path& path) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  return folder / ("." + path.filename().string() + ".tmp-" + std::to_string(::getpid()));
}

}  // namespace

void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write) {
  const std::filesystem::path tmp = temporary_beside(path);
  std::error_code ec;
  try {
    write(tmp);
  } catch (const std::exception& e) {
    std::filesystem::remove(tmp, ec);
    throw WriteError(path, std::string("not written (") + e.what() + ")");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw WriteError(path, "cannot replace it: " + ec.message());
  }
}

void write_file(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open for writing");
    write(out);
    out.close();
    if (!out) throw std::runtime_error("write failed");
  });
}

void check_writable(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw WriteError(path, "is a folder, not a file");
  const std::filesystem::path tmp = temporary_beside(path);
  {
    std::ofstream probe(tmp, std::ios::binary);
    if (!probe) throw WriteError(path, "cannot create a file in its folder");
  }
  std::filesystem::remove(tmp, ec);
}

}  // namespace nurbs::io
