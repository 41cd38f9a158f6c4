// Never lose a run, through `style4d train`: a finished run is never trained again, whatever state
// its checkpoints are in; continuing a stopped run without a loadable checkpoint refuses and leaves
// every result byte-identical (a run killed before its first checkpoint, with nothing to lose,
// starts again); a damaged newest checkpoint falls back to the previous one and says so; settings out
// of range are refused from run.json (resume and render) and --set in one format, and from the command
// line named by their flag; a second writer is refused while the run lock is held.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/run/checkpoint.h"
#include "s4d/run/run_lock.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

// 4 cameras x 3 frames at 48x36, and one finished static run on its first frame with checkpoints
// at 10, 20, 30 and the final one at 40 (so state.prev.s4dckpt is iteration 30).
struct Base {
  fs::path dir, data, run;
};

const Base& base() {
  static const Base b = [] {
    Base out;
    out.dir = test::fresh_dir("train_safety");
    out.data = out.dir / "d";
    out.run = out.dir / "base";
    REQUIRE(test::run_style4d("synth", "--out " + out.data.string() + " --cams 4 --frames 3 --size 48x36",
                              out.dir / "synth.log") == 0);
    const int rc = test::run_style4d("train",
                                     "--data " + out.data.string() + " --out " + out.run.string() +
                                         " --preset fast --stage static --iters 40 --max-time 0 --checkpoint-every 10",
                                     out.dir / "base.log");
    INFO(test::read_text(out.dir / "base.log"));
    REQUIRE(rc == 0);
    return out;
  }();
  return b;
}

fs::path copy_of_base(const std::string& name) {
  const fs::path run = base().dir / name;
  fs::remove_all(run);
  fs::copy(base().run, run, fs::copy_options::recursive);
  fs::remove(run / ".lock");
  return run;
}

// A copy of the base run as a run stopped before its end leaves it: train.json says "complete": false.
fs::path copy_of_interrupted(const std::string& name) {
  const fs::path run = copy_of_base(name);
  nlohmann::json train = nlohmann::json::parse(test::read_text(run / "train.json"));
  train["complete"] = false;
  std::ofstream(run / "train.json") << train.dump(2);
  return run;
}

// Every file of a run (its lock aside) by relative path, with its bytes.
std::map<std::string, std::string> contents(const fs::path& run) {
  std::map<std::string, std::string> out;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(run))
    if (e.is_regular_file() && e.path().filename() != ".lock")
      out[fs::relative(e.path(), run).string()] = test::read_text(e.path());
  return out;
}

// Flips one bit inside the array `name` of a checkpoint.
void damage_array(const fs::path& file, const std::string& name) {
  std::string bytes = test::read_text(file);
  uint64_t len = 0;
  std::memcpy(&len, bytes.data() + 8, 8);
  const nlohmann::json header = nlohmann::json::parse(bytes.substr(24, len));
  size_t offset = 24 + len;
  for (const nlohmann::json& a : header.at("arrays")) {
    const size_t size = a.at("floats").get<size_t>() * 4;
    if (a.at("name") == name) {
      bytes[offset + size / 2] = static_cast<char>(bytes[offset + size / 2] ^ 0x10);
      std::ofstream(file, std::ios::binary) << bytes;
      return;
    }
    offset += size;
  }
  FAIL("no array " << name << " in " << file);
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

// Runs `style4d train ARGS`; returns its log, and whether it succeeded in `ok`.
std::string run_train(const std::string& args, const fs::path& log, bool& ok) {
  ok = test::run_style4d("train", args, log) == 0;
  return test::read_text(log);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("a finished run is never trained again: continuing it says so, exits 0 and changes no byte") {
  struct Case {
    const char* name;
    std::function<void(const fs::path&)> damage;
  };
  const Case cases[] = {
      {"intact", [](const fs::path&) {}},
      {"newest_damaged", [](const fs::path& r) { damage_array(r / "checkpoint" / "state.s4dckpt", "means"); }},
      {"newest_missing", [](const fs::path& r) { fs::remove(r / "checkpoint" / "state.s4dckpt"); }},
      {"both_missing", [](const fs::path& r) { fs::remove_all(r / "checkpoint"); }},
      {"both_damaged", [](const fs::path& r) {
         damage_array(r / "checkpoint" / "state.s4dckpt", "means");
         damage_array(r / "checkpoint" / "state.prev.s4dckpt", "means");
       }},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const fs::path run = copy_of_base(std::string("finished_") + c.name);
    c.damage(run);
    const auto before = contents(run);
    REQUIRE(before.count("geometry/gaussians.ply") == 1);
    bool ok = false;
    std::string log = run_train("--run " + run.string(), base().dir / "l_finished", ok);
    CHECK_MESSAGE(ok, log);
    CHECK_MESSAGE(contains(log, run.string() + ": finished (train.json: complete); nothing to continue, its results are "
                                "unchanged"), log);
    CHECK(contents(run) == before);
    // The old spelling does the same, with one line saying it is old.
    log = run_train("--resume " + run.string(), base().dir / "l_finished_old", ok);
    CHECK_MESSAGE(ok, log);
    CHECK_MESSAGE(contains(log, "style4d: warning: --resume RUN is an old spelling; use --run RUN"), log);
    CHECK(contents(run) == before);
  }
}

TEST_CASE("resume without a loadable checkpoint refuses and leaves train.json, the PLY and loss.csv byte-identical") {
  const fs::path run = copy_of_interrupted("no_checkpoint");
  fs::remove(run / "checkpoint" / "state.s4dckpt");
  fs::remove(run / "checkpoint" / "state.prev.s4dckpt");
  const auto before = contents(run);
  REQUIRE(before.count("train.json") == 1);
  REQUIRE(before.count("loss.csv") == 1);
  REQUIRE(before.count("geometry/gaussians.ply") == 1);
  bool ok = true;
  std::string log = run_train("--resume " + run.string(), base().dir / "l_missing", ok);
  CHECK_FALSE(ok);
  CHECK_MESSAGE(contains(log, (run / "checkpoint" / "state.s4dckpt").string() + ": missing"), log);
  CHECK_MESSAGE(contains(log, "train.json, geometry/gaussians.ply, eval/"), log);
  CHECK_MESSAGE(contains(log, "not resumed"), log);
  CHECK(contents(run) == before);

  // The case: no checkpoint and a truncated PLY (killed while writing it).
  fs::resize_file(run / "geometry" / "gaussians.ply", fs::file_size(run / "geometry" / "gaussians.ply") / 2);
  const auto truncated = contents(run);
  log = run_train("--resume " + run.string(), base().dir / "l_cut_ply", ok);
  CHECK_FALSE(ok);
  CHECK_MESSAGE(contains(log, "not resumed"), log);
  CHECK(contents(run) == truncated);

  // Both checkpoints damaged: refused, naming both, nothing written.
  const fs::path damaged = copy_of_interrupted("both_damaged");
  damage_array(damaged / "checkpoint" / "state.s4dckpt", "means");
  damage_array(damaged / "checkpoint" / "state.prev.s4dckpt", "sh.adam_v");
  const auto both = contents(damaged);
  log = run_train("--resume " + damaged.string(), base().dir / "l_both", ok);
  CHECK_FALSE(ok);
  CHECK_MESSAGE(contains(log, (damaged / "checkpoint" / "state.s4dckpt").string() + ": array 'means': checksum mismatch"), log);
  CHECK_MESSAGE(contains(log, (damaged / "checkpoint" / "state.prev.s4dckpt").string() + ": array 'sh.adam_v': checksum mismatch"),
                log);
  CHECK(contents(damaged) == both);
}

TEST_CASE("resume falls back to the previous checkpoint when the newest is damaged, in one line, and keeps it") {
  const fs::path run = copy_of_interrupted("fallback");
  const fs::path newest = run / "checkpoint" / "state.s4dckpt", prev = run / "checkpoint" / "state.prev.s4dckpt";
  CHECK(run::read_checkpoint(newest).meta.at("iteration") == 40);
  CHECK(run::read_checkpoint(prev).meta.at("iteration") == 30);
  damage_array(newest, "means");
  bool ok = false;
  const std::string log = run_train("--resume " + run.string(), base().dir / "l_fallback", ok);
  INFO(log);
  REQUIRE(ok);
  const std::string line = "warning: " + newest.string() + ": array 'means': checksum mismatch; resuming from the previous "
                           "checkpoint " + prev.string() + " (static stage, iteration 30)\n";
  CHECK(contains(log, line));
  CHECK(log.find("previous checkpoint") == log.rfind("previous checkpoint"));  // said once
  // Trained on from iteration 30 to the end; the damaged newest was replaced, the good previous kept.
  CHECK(read_json(run / "train.json")["complete"] == true);
  CHECK(run::read_checkpoint(newest).meta.at("iteration") == 40);
  CHECK(run::read_checkpoint(prev).meta.at("iteration") == 30);
}

TEST_CASE("a run killed before its first checkpoint, with no results to lose, trains again from the start and says so") {
  const fs::path run = base().dir / "killed_early";
  fs::remove_all(run);
  fs::create_directories(run);
  fs::copy_file(base().run / "run.json", run / "run.json");
  std::ofstream(run / "loss.csv") << "stage,iteration,loss,l1,ssim,gaussians,seconds\nstatic,10,0.5,0.5,0.5,100,1\n";
  bool ok = false;
  const std::string log = run_train("--resume " + run.string(), base().dir / "l_early", ok);
  INFO(log);
  REQUIRE(ok);
  CHECK(contains(log, run.string() + ": no checkpoint yet (the run stopped before its first) and no results to lose"));
  CHECK(read_json(run / "train.json")["complete"] == true);
  CHECK(fs::exists(run / "checkpoint" / "state.s4dckpt"));
}

TEST_CASE("settings in run.json outside their range are refused on resume and on render, naming the file and the field") {
  struct Case {
    const char* key;
    nlohmann::json value;
    const char* message;
  };
  const Case cases[] = {{"iterations", -5, "field 'iterations' = -5: must not be negative"},
                        {"sh_degree", 9, "field 'sh_degree' = 9: must be 0..3"},
                        {"budget", 0, "field 'budget' = 0: must be at least 1"}};
  for (const Case& c : cases) {
    const std::string key = c.key;
    CAPTURE(key);
    const fs::path run = copy_of_interrupted(std::string("bad_") + c.key);
    nlohmann::json j = read_json(run / "run.json");
    j["settings"][c.key] = c.value;
    std::ofstream(run / "run.json") << j.dump(2);
    const auto before = contents(run);
    bool ok = true;
    const std::string log = run_train("--resume " + run.string(), base().dir / "l_bad", ok);
    CHECK_FALSE(ok);
    CHECK_MESSAGE(contains(log, (run / "run.json").string() + ": " + c.message), log);
    CHECK(contents(run) == before);
    // Render reads the same settings (through scene::read_trained_run).
    CHECK(test::run_style4d("render", "--run " + run.string() + " --path test --out " + (base().dir / "r").string(),
                            base().dir / "l_render") != 0);
    const std::string render_log = test::read_text(base().dir / "l_render");
    CHECK_MESSAGE(contains(render_log, (run / "run.json").string()), render_log);
    CHECK_MESSAGE(contains(render_log, c.message), render_log);
  }
  // A run.json of the wrong JSON type names the file.
  const fs::path run = copy_of_interrupted("bad_types");
  nlohmann::json j = read_json(run / "run.json");
  j["settings"] = "fast";
  std::ofstream(run / "run.json") << j.dump(2);
  bool ok = true;
  std::string log = run_train("--resume " + run.string(), base().dir / "l_type", ok);
  CHECK_FALSE(ok);
  CHECK_MESSAGE(contains(log, (run / "run.json").string() + ": the training settings are a JSON string, expected a JSON object"),
                log);
  std::ofstream(run / "run.json") << "[1, 2]";
  log = run_train("--resume " + run.string(), base().dir / "l_type2", ok);
  CHECK_FALSE(ok);
  CHECK_MESSAGE(contains(log, (run / "run.json").string() + ": expected a JSON object with 'data' and 'settings'"), log);
}

TEST_CASE("settings from the command line, named by their flag, and from --set are refused as usage errors") {
  const std::string out = (base().dir / "never").string();
  const std::string start = "--data " + base().data.string() + " --out " + out + " --preset fast ";
  const std::pair<const char*, const char*> cases[] = {
      {"--batch 0", "style4d train: error: --batch 0: must be at least 1"},
      {"--budget 0", "style4d train: error: --budget 0: must be at least 1"},
      {"--sh-degree 9", "style4d train: error: --sh-degree 9: must be 0..3"},
      {"--downscale 0", "style4d train: error: --downscale 0: must be at least 1"},
      {"--lr-scale -1", "style4d train: error: --lr-scale -1: a learning rate must be a finite number > 0"},
      {"--checkpoint-every 0", "style4d train: error: --checkpoint-every 0: must be at least 1"},
      {"--set sh_degree=9", "--set: field 'sh_degree' = 9: must be 0..3"},
      {"--set iterations=-5", "--set: field 'iterations' = -5: must not be negative"},
      {"--set means_lr=1e999", "--set: field 'means_lr' = 1e999: expected a JSON value"},
      {"--set grid_lr=0", "--set: field 'grid_lr' = 0: a learning rate must be a finite number > 0"},
      {"--set ssim_weight=1e300", "--set: field 'ssim_weight' = 1e+300: outside the float range"},
      {"--set background=[0,2,0]", "--set: field 'background' = [0, 2, 0]: each component must be in [0, 1]"},
      {"--set field_width=256", "--set: field 'field_width' = 256: must be 1..128"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const int code = test::exit_code(test::run_style4d("train", start + args, base().dir / "l_args"));
    const std::string log = test::read_text(base().dir / "l_args");
    CHECK(code == 2);  // a usage error
    CHECK_MESSAGE(contains(log, message), log);
    CHECK_FALSE(fs::exists(out));  // refused before anything is created
  }
}

TEST_CASE("a second writer is refused at once while the run lock is held") {
  const fs::path run = copy_of_base("locked");
  const auto before = contents(run);
  const std::string held_by_me = ": locked by another style4d process (pid " + std::to_string(::getpid()) + ")";
  {
    const run::RunLock lock(run);  // as `style4d train` holds it
    bool ok = true;
    std::string log = run_train("--resume " + run.string(), base().dir / "l_lock", ok);
    CHECK_FALSE(ok);
    CHECK_MESSAGE(contains(log, run.string() + held_by_me), log);
    CHECK(contents(run) == before);
    // stylize holds the run shared, so a run being trained is not stylized either.
    const std::string style = (fs::path(S4D_SOURCE_DIR) / "assets" / "styles" / "builtin.png").string();
    CHECK(test::run_style4d("stylize", "--run " + run.string() + " --style " + style, base().dir / "l_lock_style") != 0);
    log = test::read_text(base().dir / "l_lock_style");
    CHECK_MESSAGE(contains(log, run.string() + held_by_me), log);
    CHECK_FALSE(fs::exists(run / "style"));
  }
  {
    // A new run into a folder another process is creating.
    const fs::path fresh = base().dir / "fresh_locked";
    fs::remove_all(fresh);
    fs::create_directories(fresh);
    const run::RunLock lock(fresh);
    bool ok = true;
    const std::string log = run_train("--data " + base().data.string() + " --out " + fresh.string() +
                                      " --preset fast --stage static --iters 10 --max-time 0 --skip-check",
                                  base().dir / "l_lock_new", ok);
    CHECK_FALSE(ok);
    CHECK_MESSAGE(contains(log, fresh.string() + held_by_me), log);
    CHECK(run::empty_but_for_lock(fresh));
  }
  // Released: the same resume goes ahead (the run is finished, so it says so and writes nothing).
  bool ok = false;
  const std::string log = run_train("--resume " + run.string(), base().dir / "l_unlocked", ok);
  CHECK_MESSAGE(ok, log);
}
