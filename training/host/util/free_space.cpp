#include "s4d/util/free_space.h"

#include <sys/resource.h>
#include <sys/statvfs.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace s4d::util {

uint64_t free_bytes(const std::filesystem::path& dir) {
  std::filesystem::path p = std::filesystem::absolute(dir);
  std::error_code ec;
  while (!std::filesystem::exists(p, ec) && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  struct statvfs s {};
  if (::statvfs(p.c_str(), &s) != 0)
    throw std::runtime_error(dir.string() + ": cannot ask the file system for free space: " + std::strerror(errno));
  return static_cast<uint64_t>(s.f_bavail) * s.f_frsize;
}

uint64_t file_size_limit() {
  struct rlimit r {};
  if (::getrlimit(RLIMIT_FSIZE, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return std::numeric_limits<uint64_t>::max();
  return static_cast<uint64_t>(r.rlim_cur);
}

std::string byte_size(uint64_t bytes) {
  char text[32];
  if (bytes < 1000000)
    std::snprintf(text, sizeof text, "%.1f KB", static_cast<double>(bytes) / 1e3);
  else
    std::snprintf(text, sizeof text, "%.1f MB", static_cast<double>(bytes) / 1e6);
  return text;
}

uint64_t require_room(const std::filesystem::path& dir, uint64_t total_bytes, uint64_t largest_file_bytes,
                  const std::string& what) {
  const uint64_t limit = file_size_limit();
  if (largest_file_bytes > limit)
    throw std::runtime_error(dir.string() + ": the file size limit (ulimit -f) is " + byte_size(limit) + ", " + what +
                             " writes files of about " + byte_size(largest_file_bytes));
  const uint64_t free = free_bytes(dir);
  if (total_bytes > free)
    throw std::runtime_error(dir.string() + ": " + byte_size(free) + " free, " + what + " needs about " +
                             byte_size(total_bytes));
  return free;
}

}  // namespace s4d::util
