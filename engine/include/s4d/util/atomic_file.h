// Atomic file replacement: write to a temporary beside the target, fsync, rename. A crash leaves
// either the old file or the new one, never half of one.
#pragma once
#include <filesystem>
#include <string_view>

namespace s4d::util {

// Throws std::runtime_error naming the path when any step fails; the temporary is removed then.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

}  // namespace s4d::util
