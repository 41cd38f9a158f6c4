// The command table and the commands themselves, called in process through the s4d_commands library
// (no program spawned): every command answers --help with its usage, the table has no duplicate
// name, a bad option is a UsageError naming the flag before anything runs, and the sweep's plan,
// status and report work on a planned sweep.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "sweep.h"

namespace {

// Runs `f`, capturing what it prints on stdout into `out`; returns what f returns.
template <class F>
int captured_stdout(F&& f, std::string& out) {
  std::ostringstream captured;
  std::streambuf* was = std::cout.rdbuf(captured.rdbuf());
  int rc = -1;
  try {
    rc = f();
  } catch (...) {
    std::cout.rdbuf(was);
    throw;
  }
  std::cout.rdbuf(was);
  out = captured.str();
  return rc;
}

// Runs `command` with `args`, capturing what it prints on stdout.
int run_captured(const s4d::cli::Command& command, const std::vector<std::string>& args, std::string& out) {
  return captured_stdout([&] { return command.run(args); }, out);
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

TEST_CASE("sweep plan, status and report in process: a planned sweep with nothing run has every cell not started and every bench cell missing") {
  namespace fs = std::filesystem;
  namespace sweep = s4d::cli::sweep;
  using nlohmann::json;
  const fs::path root = fs::temp_directory_path() / ("s4d_in_process_sweep_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  std::ofstream(root / "style.png") << "planning only checks that the style image exists";
  const json spec = {
      {"name", "tiny"},
      {"datasets", {{{"name", "a"}, {"path", "data/a"}}, {{"name", "b"}, {"path", "data/b"}}}},
      {"presets", {"fast"}},
      {"styles", {{{"name", "s"}, {"image", "style.png"}}}},
      {"methods", {{{"name", "full"}, {"stylizer", "patch"}, {"method", "full"}},
                   {{"name", "colors"}, {"stylizer", "patch"}, {"method", "colors"}}}}};
  std::ofstream(root / "spec.json") << spec.dump();

  const sweep::Manifest m = sweep::plan(root / "spec.json", root / "sweep", "/opt/style4d/bin/style4d");
  REQUIRE(m.cells.size() == 10);
  CHECK(m.stage_cells("train").size() == 2);
  CHECK(m.stage_cells("stylize").size() == 4);
  CHECK(m.stage_cells("bench").size() == 4);
  CHECK(m.cell("stylize.b.fast.s.colors").after == std::vector<std::string>{"train.b.fast"});
  CHECK(m.cell("bench.b.fast.s.colors").after == std::vector<std::string>{"stylize.b.fast.s.colors"});
  CHECK(m.program == "/opt/style4d/bin/style4d");
  sweep::write_manifest(m);
  CHECK(sweep::to_json(sweep::read_manifest(root / "sweep")) == sweep::to_json(m));

  std::string out;
  CHECK(captured_stdout([&] { return sweep::print_status(m, true); }, out) == 10);
  const json status = json::parse(out);
  CHECK(status.at("counts") == json{{"not started", 10}});
  CHECK(status.at("cells").size() == 10);
  CHECK(status.at("cells")[0].at("id") == "train.a.fast");

  CHECK(sweep::write_report(m, root / "report") == 4);
  const json report = json::parse(std::ifstream(root / "report" / "report.json"));
  CHECK(report.at("results").empty());
  REQUIRE(report.at("missing").size() == 4);
  for (const json& c : report.at("missing")) CHECK(c.at("state") == "not started");
  CHECK(report.at("rows").size() == 4);  // 2 scenes x 2 methods, no number in any
  CHECK(report.at("rows")[0].at("styles").empty());
  fs::remove_all(root);
}
