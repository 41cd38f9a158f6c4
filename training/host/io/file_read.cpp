#include "file_read.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace s4d::io::detail {

void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

FilePtr open_for_reading(const std::filesystem::path& path) {
  // fopen succeeds on a directory on Linux and only the first read fails; say so up front.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(path, "cannot open: is a directory");
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) fail(path, std::string("cannot open: ") + std::strerror(errno));
  return f;
}

std::string read_whole_file(const std::filesystem::path& path) {
  const FilePtr f = open_for_reading(path);
  std::string bytes;
  char chunk[1 << 16];
  size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof(chunk), f.get())) > 0) bytes.append(chunk, got);
  if (std::ferror(f.get())) fail(path, std::string("read error: ") + std::strerror(errno));
  return bytes;
}

}  // namespace s4d::io::detail
