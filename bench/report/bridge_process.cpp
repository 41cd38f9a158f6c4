// Running the pyiqa bridge's Python process (pyiqa_bridge.h) and listing the PNG frames it reads.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "s4d/bench/pyiqa_bridge.h"
#include "s4d/data/frame_reader.h"
#include "s4d/util/atomic_file.h"

extern char** environ;

namespace s4d::bench {

namespace fs = std::filesystem;

namespace {

// The last `max_chars` of the log, where Python puts its traceback.
std::string log_tail(const fs::path& log, size_t max_chars = 1500) {
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (text.size() > max_chars) text = "..." + text.substr(text.size() - max_chars);
  return text.empty() ? "(no output)" : text;
}

// Runs argv with stdout and stderr into `log`; the reason it failed, or nullopt on exit code 0.
std::optional<std::string> run_logged(const std::vector<std::string>& argv, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int started = posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) return "cannot start " + argv[0] + ": " + std::strerror(started);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return "waiting for " + argv[0] + " failed: " + std::strerror(errno);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return std::nullopt;
  const std::string how = WIFEXITED(status) ? "exited with code " + std::to_string(WEXITSTATUS(status))
                                            : "was killed by signal " + std::to_string(WTERMSIG(status));
  return argv[0] + " " + argv[1] + " " + how + "; its output (" + log.string() + "): " + log_tail(log);
}

}  // namespace

std::vector<fs::path> frame_files(const fs::path& frames, const fs::path& decode_dir) {
  if (fs::is_directory(frames)) {
    std::vector<fs::path> pngs = data::png_frames(frames);
    for (fs::path& p : pngs) p = fs::absolute(p);
    return pngs;
  }
  data::FrameReader video(frames);
  fs::create_directories(decode_dir);
  std::vector<fs::path> pngs;
  for (int i = 0; i < video.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", i);
    pngs.push_back(fs::absolute(decode_dir / name));
    io::write_png(pngs.back(), video.next_counted());
  }
  return pngs;
}

BridgeOutcome run_bridge(const BridgeOptions& options, const std::vector<BridgeSequence>& sequences) {
  fs::create_directories(options.work_dir);
  const fs::path dir = fs::absolute(options.work_dir);
  fs::path script = dir / "pyiqa_bridge.py";
  if (options.script)
    script = fs::absolute(*options.script);
  else
    util::write_file_atomic(script, embedded_bridge_script());
  const fs::path request = dir / "request.json", response = dir / "response.json", log = dir / "bridge.log";
  fs::remove(response);
  util::write_file_atomic(request, bridge_request(sequences, response).dump(2) + "\n");
  if (auto why = run_logged({options.python.string(), script.string(), request.string()}, log))
    return bridge_failed(sequences, *why);
  std::ifstream in(response);
  if (!in) return bridge_failed(sequences, script.string() + " wrote no " + response.string() + "; its output: " + log_tail(log));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    return bridge_failed(sequences, response.string() + " is not valid JSON (" + e.what() + ")");
  }
  return parse_bridge_response(j, sequences);
}

}  // namespace s4d::bench
