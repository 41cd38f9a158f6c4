// kill -9 anywhere in `style4d stylize` (stage 3's frames, stage 4's steps and its checkpoint
// writes, the spiral renders): running the same command again continues from what was complete,
// and the end is the uninterrupted style's, byte for byte.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run4d_fixture.h"
#include "s4d/run/checkpoint.h"
#include "style_fixture.h"

using namespace s4d;
namespace fs = std::filesystem;

TEST_CASE("stylize killed anywhere, over and over, continues and ends exactly where an uninterrupted one ends") {
  const test::SingleThreadedLavapipe one_thread;
  const test::Run4d& r = test::run4d();
  // A copy of the shared run without its styles, so the styles made here list nowhere else.
  const fs::path logs = r.root / "stylize_kill", run = logs / "run";
  fs::remove_all(logs);
  fs::create_directories(run);
  for (const fs::directory_entry& e : fs::directory_iterator(r.run))
    if (e.path().filename() != "style" && e.path().filename() != ".lock")
      fs::copy(e.path(), run / e.path().filename(), fs::copy_options::recursive);
  auto command = [&](const std::string& name) {
    return std::vector<std::string>{"stylize", "--run", run.string(), "--style", test::kBuiltinStyle, "--name", name,
                                    "--iters", "60", "--mlp-iters", "20", "--spiral-frames", "2", "--checkpoint-every", "4"};
  };
  const pid_t whole_pid = test::spawn_style4d(command("kill_whole"), logs / "whole.log");
  int status = 0;
  REQUIRE(waitpid(whole_pid, &status, 0) == whole_pid);
  INFO(test::read_text(logs / "whole.log"));
  REQUIRE((WIFEXITED(status) && WEXITSTATUS(status) == 0));

  const fs::path style = run / "style" / "kill_killed";
  int kills = 0;
  // Milliseconds after each start (primes, so they do not line up): the first kills fall in stage 3
  // or early stage 4, later ones in steps, checkpoint writes and the spiral.
  // Kills stay inside stages 3 and 4 (a quiet machine finishes stage 4 in about 5 s). Once, in a
  // loaded CI-style run, the rerun after a kill that landed as the process exited aborted with
  // "free(): invalid size" in its consistency step. Not reproduced since: 160 reruns on that very
  // folder (plain, under the validation layer, and after the whole kill sequence with the ASan+UBSan
  // build), a valgrind run clean, truncated validation-layer caches harmless (docs/tests.md).
  for (const int delay_ms : {700, 1301, 1999, 2707, 3607, 4801}) {
    const fs::path log = logs / ("segment" + std::to_string(kills) + ".log");
    const pid_t pid = test::spawn_style4d(command("kill_killed"), log);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    REQUIRE(waitpid(pid, &status, 0) == pid);
    if (WIFEXITED(status)) {
      INFO(test::read_text(log));
      REQUIRE(WEXITSTATUS(status) == 0);  // finished before the kill
      break;
    }
    ++kills;
    if (fs::exists(style / "checkpoint.s4dckpt")) CHECK_NOTHROW(run::read_checkpoint(style / "checkpoint.s4dckpt"));
  }
  MESSAGE(kills << " kills before stylize finished");
  CHECK(kills >= 3);
  const pid_t last = test::spawn_style4d(command("kill_killed"), logs / "last.log");
  REQUIRE(waitpid(last, &status, 0) == last);
  INFO(test::read_text(logs / "last.log"));
  REQUIRE((WIFEXITED(status) && WEXITSTATUS(status) == 0));
  const fs::path whole = run / "style" / "kill_whole";
  CHECK(test::read_text(style / "style.s4dstyle") == test::read_text(whole / "style.s4dstyle"));
  for (const char* frame : {"spiral/styled/0000.png", "spiral/styled/0001.png"})
    CHECK_MESSAGE(test::read_text(style / frame) == test::read_text(whole / frame), frame);
  // iteration,loss,seconds: every logged iteration once, with the uninterrupted run's loss.
  auto iterations_and_losses = [](const fs::path& csv) {
    std::istringstream in(test::read_text(csv));
    std::string kept, row;
    while (std::getline(in, row)) kept += row.substr(0, row.rfind(',')) + "\n";
    return kept;
  };
  CHECK(iterations_and_losses(style / "loss.csv") == iterations_and_losses(whole / "loss.csv"));
}
