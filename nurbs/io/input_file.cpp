#include "nurbs/io/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

#include "nurbs/io/read_error.h"

namespace nurbs::io {

std::ifstream open_input_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw ReadError(name, "", "cannot be read (" + ec.message() + ")");
  if (!std::filesystem::exists(status)) throw ReadError(name, "", "no such file");
  if (std::filesystem::is_directory(status)) throw ReadError(name, "", "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReadError(name, "", std::string("cannot be read (") + std::strerror(errno) + ")");
  return in;
}

std::string read_input_file(const std::filesystem::path& path) {
  std::ifstream in = open_input_file(path);
  return read_input_stream(in, path.string());
}

std::string read_input_stream(std::istream& in, const std::string& name) {
  std::string data;
  try {
    data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::ios_base::failure&) {  // libstdc++'s filebuf throws on a read error (errno set)
    throw ReadError(name, "", std::string("cannot be read (") + std::strerror(errno) + ")");
  }
  if (in.bad()) throw ReadError(name, "", "cannot be read (read failed)");
  return data;
}

}  // namespace nurbs::io
