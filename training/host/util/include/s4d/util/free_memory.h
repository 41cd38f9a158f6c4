// Room to allocate: the memory a process may still take, asked before a large allocation (a huge
// image, say) so that the command refuses with what it needs instead of dying of std::bad_alloc.
#pragma once
#include <cstdint>
#include <string>

namespace s4d::util {

// The smaller of the system's available memory (/proc/meminfo MemAvailable) and what the address-
// space limit (ulimit -v) leaves beside the process's present size; UINT64_MAX when neither is known.
uint64_t available_memory();

// Throws std::runtime_error "WHO: WHAT needs about N MB of memory, M MB is available" when `bytes`
// exceed available_memory().
void require_memory(const std::string& who, uint64_t bytes, const std::string& what);

}  // namespace s4d::util
