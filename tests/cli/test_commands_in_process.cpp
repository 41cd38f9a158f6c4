// The command table and the commands themselves, called in process through the s4d_commands library
// (no program spawned): every command answers --help with its usage, the table has no duplicate
// name, and a bad option is a UsageError naming the flag before anything runs.
#include <doctest/doctest.h>

#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"

namespace {

// Runs `command` with `args`, capturing what it prints on stdout.
int run_captured(const s4d::cli::Command& command, const std::vector<std::string>& args, std::string& out) {
  std::ostringstream captured;
  std::streambuf* was = std::cout.rdbuf(captured.rdbuf());
  int rc = -1;
  try {
    rc = command.run(args);
  } catch (...) {
    std::cout.rdbuf(was);
    throw;
  }
  std::cout.rdbuf(was);
  out = captured.str();
  return rc;
}

}  // namespace

TEST_CASE("every command in the table answers --help in process with its usage line") {
  std::set<std::string> names;
  for (const s4d::cli::Command& c : s4d::cli::command_table()) {
    CAPTURE(c.name);
    CHECK(names.insert(c.name).second);
    CHECK(std::string(c.summary).size() > 10);
    std::string out;
    CHECK(run_captured(c, {"--help"}, out) == 0);
    CHECK_MESSAGE(out.rfind(std::string("usage: style4d ") + c.name, 0) == 0, out);
    CHECK(s4d::cli::find_command(c.name) == &c);
  }
  CHECK(names.count("stylize") == 1);
  CHECK(names.count("demo") == 1);
  CHECK(s4d::cli::find_command("no-such-command") == nullptr);
}

TEST_CASE("a bad --time-budget is a usage error naming the flag, in process, for train, stylize and demo") {
  const std::vector<std::pair<std::string, std::vector<std::string>>> calls = {
      {"train", {"--data", "nowhere", "--run", "nowhere_run", "--time-budget", "10x"}},
      {"stylize", {"--run", "nowhere", "--style-image", "nowhere.png", "--time-budget", "10x"}},
      {"demo", {"--out", "nowhere_demo", "--time-budget", "10x"}},
  };
  for (const auto& [name, args] : calls) {
    CAPTURE(name);
    const s4d::cli::Command* c = s4d::cli::find_command(name);
    REQUIRE(c != nullptr);
    std::string out;
    CHECK_THROWS_WITH_AS(run_captured(*c, args, out), "--time-budget: expected a duration such as 90s, 20m or 1h30m, got '10x'",
                         s4d::cli::UsageError);
  }
}
