// Helpers for tests that run the style4d program: run a subcommand with its output captured in a
// log file, read the log, and make a fresh scratch directory.
#pragma once
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace s4d::test {

// S4D_STYLE4D_EXE is the built program's path, defined by tests/CMakeLists.txt.
inline int run_style4d(const std::string& command, const std::string& args, const std::filesystem::path& log) {
  const std::string cmd =
      std::string(S4D_STYLE4D_EXE) + " " + command + " " + args + " > " + log.string() + " 2>&1";
  return std::system(cmd.c_str());
}

// The exit code in a std::system status (run_style4d's); -1 when the program did not exit (a signal).
inline int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

// While alive, style4d runs started by this process use one lavapipe thread, so float atomics add
// in one order and runs are bit for bit reproducible (for the resume tests). Nests: the value before
// it comes back, so an inner one's end leaves an outer one in force.
struct SingleThreadedLavapipe {
  SingleThreadedLavapipe() {
    if (const char* v = std::getenv("LP_NUM_THREADS")) before_ = v;
    setenv("LP_NUM_THREADS", "1", 1);
  }
  ~SingleThreadedLavapipe() { before_ ? setenv("LP_NUM_THREADS", before_->c_str(), 1) : unsetenv("LP_NUM_THREADS"); }
  SingleThreadedLavapipe(const SingleThreadedLavapipe&) = delete;
  SingleThreadedLavapipe& operator=(const SingleThreadedLavapipe&) = delete;

 private:
  std::optional<std::string> before_;
};

// Starts style4d ARGS... in the background with stdout and stderr in `log`; returns its pid (for
// kill and waitpid).
extern "C" char** environ;
inline pid_t spawn_style4d(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<std::string> all = {S4D_STYLE4D_EXE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + all[0]);
  return pid;
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
