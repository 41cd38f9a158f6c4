// style4d sweep local: the sweep's cells on this machine, a plain process pool (no scheduler of our
// own beyond "start a cell when the cells it needs are done"). Each cell runs as
// `style4d sweep cell SWEEP ID`, the same runner a Slurm task uses.
#include <sys/wait.h>

#include <csignal>
#include <cstring>
#include <iostream>
#include <set>

#include "args.h"
#include "sweep.h"

namespace s4d::cli::sweep {

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void stop_pool(int) { g_stop = 1; }

}  // namespace

int run_local(const Manifest& m, int jobs) {
  if (jobs < 1) throw UsageError("--jobs: must be at least 1");
  std::vector<const Cell*> pending;
  for (const Cell& c : m.cells)
    if (!cell_done(m, c)) pending.push_back(&c);
  std::cerr << "sweep: " << m.cells.size() - pending.size() << " of " << m.cells.size() << " cells done; running "
            << pending.size() << " with " << jobs << " at a time\n";
  std::map<pid_t, const Cell*> running;
  std::set<std::string> blocked;  // failed, interrupted or not startable this time
  std::signal(SIGINT, stop_pool);
  std::signal(SIGTERM, stop_pool);
  while (true) {
    for (auto it = pending.begin(); it != pending.end() && !g_stop && static_cast<int>(running.size()) < jobs;) {
      const Cell& c = **it;
      bool ready = true, hopeless = false;
      for (const std::string& dep : c.after) {
        if (cell_done(m, m.cell(dep))) continue;
        ready = false;
        hopeless = hopeless || blocked.count(dep) > 0;
      }
      if (hopeless) {
        std::cerr << "sweep: " << c.id << ": not started, a cell it needs did not finish\n";
        blocked.insert(c.id);
        it = pending.erase(it);
        continue;
      }
      if (!ready) {
        ++it;
        continue;
      }
      running[spawn_process(m.program, {"sweep", "cell", m.root.string(), c.id}, {}, -1)] = &c;
      it = pending.erase(it);
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    if (!cell_done(m, *it->second)) blocked.insert(it->second->id);
    running.erase(it);
  }
  int not_done = 0;
  for (const Cell& c : m.cells) not_done += cell_done(m, c) ? 0 : 1;
  std::cerr << "sweep: " << m.cells.size() - not_done << " of " << m.cells.size() << " cells done"
            << (not_done ? "; style4d sweep status " + m.root.string() + " shows the others" : std::string()) << "\n";
  return not_done;
}

}  // namespace s4d::cli::sweep
