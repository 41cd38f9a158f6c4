// Helpers for tests that run the style4d program: run a subcommand with its output captured in a
// log file, read the log, and make a fresh scratch directory.
#pragma once
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace s4d::test {

// S4D_STYLE4D_EXE is the built program's path, defined by tests/CMakeLists.txt.
inline int run_style4d(const std::string& command, const std::string& args, const std::filesystem::path& log) {
  const std::string cmd =
      std::string(S4D_STYLE4D_EXE) + " " + command + " " + args + " > " + log.string() + " 2>&1";
  return std::system(cmd.c_str());
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Named after the process too, so two runs of the same test at once (a developer and CI) never share one.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("s4d_cli_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace s4d::test
