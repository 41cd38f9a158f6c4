// Shared by the libFuzzer targets: the readers take paths, so each input is written to one temp
// file per process (reused every iteration) and the reader is called on it. A std::exception is a
// fine outcome for damaged input; crashes, sanitizer reports, leaks and hangs are what is looked for.
#pragma once
#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

namespace s4d_fuzz {

// A temp file with `suffix` (".ply", ".png", ...) that lives as long as the process.
inline const std::filesystem::path& temp_path(const char* suffix) {
  static const std::filesystem::path path = [&] {
    const char* dir = std::getenv("TMPDIR");
    std::string pattern = std::string(dir && *dir ? dir : "/tmp") + "/s4d_fuzz_XXXXXX" + suffix;
    const int fd = mkstemps(pattern.data(), static_cast<int>(std::string(suffix).size()));
    if (fd < 0) {
      std::perror("mkstemps");
      std::abort();
    }
    close(fd);
    std::atexit([] { std::remove(temp_path("").c_str()); });
    return std::filesystem::path(pattern);
  }();
  return path;
}

inline const std::filesystem::path& write_input(const uint8_t* data, size_t size, const char* suffix) {
  const std::filesystem::path& path = temp_path(suffix);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror("fopen");
    std::abort();
  }
  if (size && std::fwrite(data, 1, size, f) != size) {
    std::perror("fwrite");
    std::abort();
  }
  std::fclose(f);
  return path;
}

}  // namespace s4d_fuzz

// Defines LLVMFuzzerTestOneInput: writes the input to a temp file ending in SUFFIX and runs BODY
// with `path` bound to it; any std::exception thrown by BODY is an accepted outcome.
#define S4D_FUZZ_TARGET(SUFFIX, BODY)                                                  \
  extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {            \
    const std::filesystem::path& path = s4d_fuzz::write_input(data, size, SUFFIX);     \
    try {                                                                              \
      BODY                                                                             \
    } catch (const std::exception&) {                                                  \
    }                                                                                  \
    return 0;                                                                          \
  }
