// The command-line grammar, through the style4d program: --version, help COMMAND, grouped --help,
// did-you-mean for commands and options, usage errors exiting 2, old spellings that keep working with
// one deprecation line, the bash completion generated from the option tables, and --config.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace fs = std::filesystem;
using s4d::test::exit_code;
using s4d::test::read_text;

namespace {

const fs::path& scratch() {
  static const fs::path dir = s4d::test::fresh_dir("grammar");
  return dir;
}

// Runs `style4d COMMAND ARGS`; returns the exit code and leaves stdout + stderr in `out`.
int style4d(const std::string& command, const std::string& args, std::string& out) {
  const fs::path log = scratch() / "log.txt";
  const int code = exit_code(s4d::test::run_style4d(command, args, log));
  out = read_text(log);
  return code;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

size_t lines_with(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// The --name options a help text lists (its option column), old spellings and --help aside.
std::set<std::string> options_in_help(const std::string& help) {
  std::set<std::string> out;
  const std::regex option(R"(\n  --([a-z0-9-]+))");
  for (auto it = std::sregex_iterator(help.begin(), help.end(), option); it != std::sregex_iterator(); ++it)
    if ((*it)[1] != "help") out.insert((*it)[1]);
  return out;
}

// What the generated completion offers for the words typed so far (the last one being completed).
std::string complete(const fs::path& script, const std::string& words) {
  const fs::path out = scratch() / "completion.txt";
  const std::string cmd = "bash -c 'source " + script.string() + "; COMP_WORDS=(" + words + "); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); " +
                          "_style4d; echo \"${COMPREPLY[*]}\"' > " + out.string() + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  return read_text(out);
}

}  // namespace

TEST_CASE("--version, help COMMAND and grouped --help") {
  std::string out;
  REQUIRE(style4d("--version", "", out) == 0);
  CHECK(std::regex_search(out, std::regex(R"(^style4d [0-9]+\.[0-9]+\.[0-9]+\n$)")));
  std::string help;
  REQUIRE(style4d("help", "train", out) == 0);
  REQUIRE(style4d("train", "--help", help) == 0);
  CHECK(out == help);
  for (const char* heading : {"\nthe run:\n", "\nschedule:\n", "\ndata:\n", "\nmodel:\n"}) CHECK_MESSAGE(has(help, heading), heading);
  // fast's static stage is chosen from the data (-1), as the preset sets it.
  CHECK(has(help, "fast -1, chosen from the data"));
  CHECK(style4d("help", "no-such-command", out) == 2);
  CHECK(has(out, "unknown command 'no-such-command'"));
  REQUIRE(style4d("--help", "", out) == 0);
  CHECK(has(out, "help COMMAND"));
  CHECK(has(out, "completion bash"));
  CHECK(has(out, "--version"));
}

TEST_CASE("did you mean: the nearest command or option, only when it is near") {
  std::string out;
  CHECK(style4d("trian", "", out) == 2);
  CHECK(has(out, "style4d: error: unknown command 'trian'; did you mean 'train'?"));
  CHECK(style4d("xyzzy", "", out) == 2);
  CHECK(has(out, "unknown command 'xyzzy' (style4d --help"));  // nothing near: no guess
  CHECK(style4d("train", "--data d --run r --iter 5", out) == 2);
  CHECK(has(out, "style4d train: error: unknown option --iter; did you mean --iters? (see --help)"));
  CHECK(style4d("render", "--run r --styel x", out) == 2);
  CHECK(has(out, "did you mean --style?"));
  CHECK(style4d("render", "--run r --qqqqqq x", out) == 2);
  CHECK_FALSE(has(out, "did you mean"));
}

TEST_CASE("usage errors exit 2 in every command, other errors 1") {
  const std::pair<const char*, const char*> usage_errors[] = {
      {"synth", "--cams 3"},                                   // a required option missing
      {"render", "--run r --path nowhere --out o"},            // a value of the wrong form
      {"render", "--run r --path test --out o --spiral-frames 0"},
      {"make-style", "--out x.png --size 8"},
      {"make-style", "--out x.png stray"},                     // a stray argument
      {"export-ply", "--run"},                                 // an option without its value
      {"view", "--camera 0"},                                  // no run
      {"train", "--run r"},                                    // nothing to continue, no --data
      {"train", "--data d --run r --preset turbo"},
      {"train", "--data d --run r --config c.json --preset fast"},
      {"stylize", "--run r"},
      {"bench", "--out o --original a --style-image s"},
      {"check-data", ""},
      {"sweep", "fly"},                                        // a verb without its sweep folder
  };
  for (const auto& [command, args] : usage_errors) {
    const std::string line = std::string(command) + " " + args;
    CAPTURE(line);
    std::string out;
    CHECK(style4d(command, args, out) == 2);
    CHECK_MESSAGE(lines_with(out, ": error: ") == 1, out);
  }
  // A run folder that is not there is not a usage error: exit 1, naming it.
  std::string out;
  CHECK(style4d("export-ply", "--run " + (scratch() / "absent").string() + " --out " + (scratch() / "x.ply").string(), out) == 1);
  CHECK(has(out, (scratch() / "absent").string()));
}

TEST_CASE("old spellings keep working and say so in one line") {
  std::string out;
  const fs::path data = scratch() / "data";
  fs::remove_all(data);
  REQUIRE_MESSAGE(style4d("synth", "--out " + data.string() + " --cams 2 --frames 2 --size 32x24", out) == 0, out);
  CHECK(has(out, "style4d: warning: --frames is an old spelling; use --frame-count (--frames keeps working)"));
  CHECK(lines_with(out, "old spelling") == 1);
  CHECK(fs::exists(data / "cam01" / "0001.png"));
  // --frames of train is --frame-range, of render --spiral-frames, of bench --stylized.
  for (const auto& [command, old_spelling, new_spelling] :
       {std::tuple{"train", "--frames 2", "--frame-range"}, std::tuple{"render", "--frames 4", "--spiral-frames"},
        std::tuple{"bench", "--frames x", "--stylized"}}) {
    CAPTURE(command);
    style4d(command, std::string(old_spelling) + " --no-such-option", out);  // stops at the unknown option
    CHECK_MESSAGE(has(out, std::string("use ") + new_spelling + " "), out);
  }
  style4d("train", "--out r --no-such-option", out);
  CHECK(has(out, "--out is an old spelling; use --run"));
  style4d("stylize-frames", "--style x.png --no-such-option", out);
  CHECK(has(out, "--style is an old spelling; use --style-image"));
}

TEST_CASE("the bash completion lists each command's options as its --help does") {
  const fs::path script = scratch() / "style4d.bash";
  std::string out;
  REQUIRE(style4d("completion", "bash", out) == 0);
  std::ofstream(script) << out;
  CHECK(complete(script, "style4d tra") == "train train-stylizer\n");
  CHECK(complete(script, "style4d help chec") == "check-data\n");
  CHECK(complete(script, "style4d train --fine") == "--fine-iters\n");
  CHECK(complete(script, "style4d render --spiral") == "--spiral-frames\n");
  // After an option that takes a value: file names.
  std::ofstream(scratch() / "unique_name_for_completion.json") << "{}";
  CHECK(complete(script, "style4d render --run x --path " + (scratch() / "unique_name_for_c").string()) ==
        (scratch() / "unique_name_for_completion.json").string() + "\n");
  for (const char* command : {"synth", "check-data", "train", "view", "render", "export-ply", "stylize", "stylize-frames",
                              "make-style", "train-stylizer", "bench", "demo"}) {
    CAPTURE(command);
    std::string help;
    REQUIRE(style4d(command, "--help", help) == 0);
    std::set<std::string> completed;
    std::istringstream words(complete(script, std::string("style4d ") + command + " --"));
    for (std::string w; words >> w;)
      if (w != "--help") completed.insert(w.substr(2));
    CHECK(completed == options_in_help(help));
  }
  CHECK(style4d("completion", "zsh", out) == 2);
}

TEST_CASE("--config starts a run from a saved run's settings and dataset; options change them") {
  std::string out;
  const fs::path data = scratch() / "config_data";
  fs::remove_all(data);
  REQUIRE_MESSAGE(style4d("synth", "--out " + data.string() + " --cams 4 --frame-count 2 --size 32x24", out) == 0, out);
  // A saved run.json as train writes it: the dataset and the settings (here a few; the rest default).
  const fs::path saved = scratch() / "saved_run.json";
  std::ofstream(saved) << nlohmann::json{{"data", data.string()},
                                         {"settings", {{"preset", "fast"}, {"iterations", 30}, {"fine_iterations", 0},
                                                       {"sh_degree", 1}, {"max_time", 0.0}, {"checkpoint_every", 30}}}}
                              .dump();
  const fs::path run = scratch() / "config_run";
  fs::remove_all(run);
  REQUIRE_MESSAGE(style4d("train", "--config " + saved.string() + " --run " + run.string() + " --seed 7", out) == 0, out);
  const nlohmann::json settings = nlohmann::json::parse(read_text(run / "run.json")).at("settings");
  CHECK(settings.at("iterations") == 30);
  CHECK(settings.at("sh_degree") == 1);
  CHECK(settings.at("seed") == 7);  // the option changed it
  CHECK(fs::absolute(nlohmann::json::parse(read_text(run / "run.json")).at("data").get<std::string>()) == fs::absolute(data));
  // A file that is not a run's settings: named, exit 2, nothing created.
  std::ofstream(scratch() / "not_a_run.json") << "[1, 2]";
  const fs::path never = scratch() / "never";
  CHECK(style4d("train", "--config " + (scratch() / "not_a_run.json").string() + " --run " + never.string(), out) == 2);
  CHECK(has(out, "not_a_run.json: expected a run's run.json or train.json"));
  CHECK_FALSE(fs::exists(never));
}
