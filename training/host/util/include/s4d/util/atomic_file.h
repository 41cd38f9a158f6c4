// Atomic file replacement: write to a temporary beside the target, fsync, rename. A crash leaves
// either the old file or the new one, never half of one.
#pragma once
#include <filesystem>
#include <ostream>
#include <string_view>

namespace s4d::util {

// Throws std::runtime_error naming the path when any step fails; the temporary is removed then.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// For logs appended line by line (loss.csv): throws std::runtime_error "cannot write PATH: ..." once
// `stream` has failed (a full disk), instead of training on with a log that silently stopped.
void require_written(const std::ostream& stream, const std::filesystem::path& path);

}  // namespace s4d::util
