// Private helpers shared by the readers: opening a file with an error that names it and says why
// (errno), and the "<file>: <problem>" message convention every reader follows.
#pragma once
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace s4d::io::detail {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Throws std::runtime_error("<path>: cannot open: <reason>").
FilePtr open_for_reading(const std::filesystem::path& path);

// The whole file as bytes; same errors as open_for_reading plus read failures.
std::string read_whole_file(const std::filesystem::path& path);

// Throws std::runtime_error("<path>: <what>").
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what);

}  // namespace s4d::io::detail
