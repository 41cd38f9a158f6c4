#include "s4d/util/free_memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "s4d/util/free_space.h"

namespace s4d::util {

namespace {

constexpr uint64_t kUnknown = std::numeric_limits<uint64_t>::max();

// MemAvailable in bytes (the kernel's estimate of what can be allocated without swapping).
uint64_t system_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return kUnknown;
}

// RLIMIT_AS less the process's present virtual size (/proc/self/statm's first field, in pages).
uint64_t address_space_left() {
  struct rlimit r {};
  if (::getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return kUnknown;
  uint64_t pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  const uint64_t used = pages * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  return used >= r.rlim_cur ? 0 : r.rlim_cur - used;
}

}  // namespace

uint64_t available_memory() { return std::min(system_available(), address_space_left()); }

void require_memory(const std::string& who, uint64_t bytes, const std::string& what) {
  const uint64_t available = available_memory();
  if (bytes > available)
    throw std::runtime_error(who + ": " + what + " needs about " + byte_size(bytes) + " of memory, " + byte_size(available) +
                             " is available");
}

}  // namespace s4d::util
