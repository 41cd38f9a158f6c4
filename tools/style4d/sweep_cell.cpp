// One cell of a sweep, run idempotently: `style4d sweep cell SWEEP ID` (what each Slurm task and
// each process of the local pool runs). Done cells are skipped; a cell whose checkpoint exists
// resumes from it; a failure is recorded with its reason (the last line of the command's output).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>

#include "sweep.h"

namespace s4d::cli::sweep {

namespace fs = std::filesystem;

namespace {

volatile std::sig_atomic_t g_signalled = 0;
extern "C" void note_signal(int sig) { g_signalled = sig; }

std::string now_text() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", std::localtime(&t));
  return buf;
}

std::string host_name() {
  char buf[256] = {};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

// The last non-empty line of `log` after byte `from` (a progress line's last \r part).
std::string last_line(const fs::path& log, std::streamoff from) {
  std::ifstream in(log);
  in.seekg(from);
  std::string line, last;
  while (std::getline(in, line)) {
    const size_t cr = line.find_last_of('\r', line.size() > 1 ? line.size() - 2 : 0);
    if (cr != std::string::npos && cr + 1 < line.size()) line = line.substr(cr + 1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) last = line;
  }
  return last;
}

}  // namespace

pid_t spawn_process(const fs::path& program, const std::vector<std::string>& args, const std::map<std::string, std::string>& env,
                    int out_fd, const fs::path& cwd) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid > 0) return pid;
  // The child: default signal handling (the parent's handlers would be reset by exec anyway, but not
  // an ignored signal), the sweep's environment, output into out_fd.
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) std::signal(sig, SIG_DFL);
  for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
  if (out_fd >= 0) {
    dup2(out_fd, STDOUT_FILENO);
    dup2(out_fd, STDERR_FILENO);
  }
  if (!cwd.empty() && chdir(cwd.c_str()) != 0) {
    std::fprintf(stderr, "sweep: cannot enter %s: %s\n", cwd.c_str(), std::strerror(errno));
    _exit(127);
  }
  std::vector<std::string> all = {program.string()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(program.c_str(), argv.data());
  std::fprintf(stderr, "sweep: cannot run %s: %s\n", program.c_str(), std::strerror(errno));
  _exit(127);
}

int run_cell(const Manifest& m, const std::string& id) {
  const Cell& c = m.cell(id);
  if (cell_done(m, c)) {
    std::cerr << "sweep: " << id << " is done; skipped\n";
    return 0;
  }
  const fs::path dir = cell_dir(m, id);
  fs::create_directories(dir);
  // One runner per cell at a time (a resubmission while the first still runs).
  const int lock = open((dir / "lock").c_str(), O_CREAT | O_RDWR, 0644);
  if (lock < 0 || flock(lock, LOCK_EX | LOCK_NB) != 0) {
    std::cerr << "sweep: " << id << " is being run by another process (" << (dir / "lock").string() << " is locked)\n";
    return 1;
  }
  const nlohmann::json previous = read_state(m, id);
  nlohmann::json state = {{"state", "running"}, {"attempts", (previous.is_null() ? 0 : previous.value("attempts", 0)) + 1},
                          {"host", host_name()}, {"started", now_text()}, {"pid", getpid()}};
  if (const char* job = std::getenv("SLURM_ARRAY_JOB_ID"))
    state["slurm_job"] = std::string(job) + "_" + (std::getenv("SLURM_ARRAY_TASK_ID") ? std::getenv("SLURM_ARRAY_TASK_ID") : "");
  for (const std::string& dep : c.after) {
    if (cell_done(m, m.cell(dep))) continue;
    state["state"] = "failed";
    state["error"] = "needs " + dep + ", which is " + cell_state(m, m.cell(dep)) + " (" + (cell_dir(m, dep) / "log.txt").string() + ")";
    write_state(m, id, state);
    std::cerr << "sweep: " << id << ": " << state["error"].get<std::string>() << "\n";
    return 1;
  }
  const bool resume = !c.resume_when.empty() && fs::exists(c.resume_when);
  if (!resume)
    for (const std::string& p : c.clean) fs::remove_all(p);
  const std::vector<std::string>& args = resume ? c.resume_command : c.command;
  state["resumed"] = resume;
  write_state(m, id, state);

  const fs::path log = dir / "log.txt";
  std::streamoff from = 0;
  {
    std::ofstream header(log, std::ios::app);
    header << "=== " << id << " attempt " << state["attempts"] << (resume ? " (resumed from " + c.resume_when + ")" : " (fresh)")
           << " on " << state["host"].get<std::string>() << " at " << state["started"].get<std::string>() << ":\n" << m.program.string();
    for (const std::string& a : args) header << " " << a;
    header << "\n";
    header.flush();
    from = header.tellp();
  }
  std::cerr << "sweep: " << id << (resume ? ": resuming" : ": starting") << " (log " << log.string() << ")\n";
  const int out = open(log.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644);
  if (out < 0) throw std::runtime_error(log.string() + ": cannot be written");
  // A SIGTERM (scancel, Slurm's time limit) or SIGINT reaches the command too, which writes its
  // checkpoint and exits 130: this process waits for it and records the outcome.
  std::signal(SIGTERM, note_signal);
  std::signal(SIGINT, note_signal);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = spawn_process(m.program, args, m.env, out, m.root);  // in SWEEP, as a Slurm task (--chdir)
  close(out);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
  state["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state["finished"] = now_text();
  int code = 1;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    std::string missing;
    for (const std::string& o : c.outputs)
      if (!fs::exists(o)) missing += (missing.empty() ? "" : ", ") + o;
    state["state"] = missing.empty() ? "done" : "failed";
    state["exit_code"] = 0;
    if (!missing.empty()) state["error"] = "exited 0 but did not write " + missing;
    code = missing.empty() ? 0 : 1;
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == 130) {
    state["state"] = "interrupted";
    state["exit_code"] = 130;
    state["error"] = "interrupted (checkpoint written); run the cell again to continue";
    code = 130;
  } else if (WIFSIGNALED(status)) {
    state["state"] = "interrupted";
    state["exit_code"] = 128 + WTERMSIG(status);
    state["error"] = std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
                     "); run the cell again to continue from its last checkpoint";
    code = 130;
  } else {
    state["state"] = "failed";
    state["exit_code"] = WEXITSTATUS(status);
    const std::string last = last_line(log, from);
    state["error"] = last.empty() ? "exited " + std::to_string(WEXITSTATUS(status)) + " with no output" : last;
  }
  write_state(m, id, state);
  std::cerr << "sweep: " << id << ": " << state["state"].get<std::string>()
            << (state.contains("error") ? ": " + state["error"].get<std::string>() : std::string()) << "\n";
  return code;
}

}  // namespace s4d::cli::sweep
