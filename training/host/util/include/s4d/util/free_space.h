// Room to write: the free bytes of the file system holding a folder and the process's file-size
// limit (ulimit -f), checked before long work starts so that a full disk refuses the command at
// once instead of failing hours later (a write that fails later still leaves the old file:
// atomic_file.h).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

namespace s4d::util {

// Bytes an unprivileged process may still write on the file system holding `dir` (or its nearest
// existing ancestor). Throws std::runtime_error naming the path when it cannot be asked.
uint64_t free_bytes(const std::filesystem::path& dir);

// The soft RLIMIT_FSIZE in bytes, UINT64_MAX when unlimited.
uint64_t file_size_limit();

// Throws std::runtime_error "DIR: N MB free, WHAT needs about M MB" when `total_bytes` do not fit on
// `dir`'s file system, or "... the file size limit (ulimit -f) is N MB, WHAT writes files of about
// M MB" when `largest_file_bytes` exceeds the limit. Returns the free bytes it found.
uint64_t require_room(const std::filesystem::path& dir, uint64_t total_bytes, uint64_t largest_file_bytes,
                  const std::string& what);

// "12.3 MB", "16.0 KB": bytes for messages.
std::string byte_size(uint64_t bytes);

}  // namespace s4d::util
