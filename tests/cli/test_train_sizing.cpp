// A model sized to the scene: a new run whose frames show no motion skips the deformation field
// (train/scene_motion.h), says so in one line and in train.json's recipe; --fine-iters still trains
// one; a scene that moves keeps it. On `synth --still` (every frame the built-in scene at t = 0)
// and the built-in scene itself. The SH degree: a preset's run chooses it from held-out views
// (train/sh_choice.h), says so and keeps the choice everywhere; --sh-degree D keeps D.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/train/sh_choice.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The SH coefficients per colour channel a binary PLY's header declares: f_dc_* and f_rest_* properties / 3.
size_t ply_sh_coeffs(const fs::path& ply) {
  std::ifstream in(ply, std::ios::binary);
  size_t floats = 0;
  for (std::string line; std::getline(in, line) && line != "end_header";)
    if (contains(line, " f_dc_") || contains(line, " f_rest_")) ++floats;
  return floats / 3;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

// The largest step of loss.csv's seconds column over the seconds before it, past the first second:
// a restore within the run (a choice, a refit) must not count the seconds already spent twice,
// which would make that step as long as everything before it (a share near 1).
double largest_seconds_jump(const fs::path& csv) {
  std::istringstream in(test::read_text(csv));
  std::string row;
  std::getline(in, row);  // header
  double before = -1, worst = 0;
  while (std::getline(in, row)) {
    const double seconds = std::stod(row.substr(row.rfind(',') + 1));
    if (before > 1) worst = std::max(worst, (seconds - before) / before);
    before = seconds;
  }
  return worst;
}

// A tiny built-in capture (4 cameras, 3 frames, 48x36) in DIR/data and `settings` in DIR/settings.json.
void tiny_capture_with_settings(const fs::path& dir, const std::string& settings) {
  REQUIRE(test::run_style4d("synth", "--out " + (dir / "data").string() + " --cams 4 --frame-count 3 --size 48x36",
                            dir / "synth.log") == 0);
  std::ofstream(dir / "settings.json") << settings;
}

// loss.csv's iteration column, in file order.
std::vector<long> loss_iterations(const fs::path& csv) {
  std::istringstream rows(test::read_text(csv));
  std::string row;
  std::getline(rows, row);  // header
  std::vector<long> out;
  while (std::getline(rows, row)) out.push_back(std::stol(row.substr(row.find(',') + 1)));
  return out;
}

}  // namespace

TEST_CASE("a capture that does not move gets no deformation field unless --fine-iters asks; one that moves keeps it") {
  const fs::path dir = test::fresh_dir("train_sizing");
  for (const char* name : {"still", "moving"}) {
    const std::string still = std::string(name) == "still" ? " --still" : "";
    REQUIRE(test::run_style4d("synth", "--out " + (dir / name).string() + " --cams 4 --frame-count 3 --size 48x36" + still,
                              dir / (std::string(name) + "_synth.log")) == 0);
  }
  // The still capture: the 4DGS stage is skipped and its 20 steps go to the static stage. (Settings
  // from a file, so that the fine stage's length is the recipe's, not asked for.)
  std::ofstream(dir / "settings.json") << R"({"settings": {"preset": "fast", "iterations": 30, "fine_iterations": 20,
      "sh_degree": 1, "budget": 15000, "densify_from": 10, "densify_until": 25, "test_every": 10, "checkpoint_every": 10}})";
  REQUIRE(test::run_style4d("train", "--data " + (dir / "still").string() + " --run " + (dir / "r_still").string() +
                                         " --config " + (dir / "settings.json").string(),
                            dir / "still.log") == 0);
  const std::string log = test::read_text(dir / "still.log");
  CHECK_MESSAGE(contains(log, "no deformation field: the frames show no motion: up to 0 % of a camera's pixels change "
                              "(over 4 cameras, 12 frame pairs"), log);
  const nlohmann::json t = read_json(dir / "r_still" / "train.json");
  CHECK(t["stage"] == "static");
  CHECK(t["settings"]["fine_iterations"] == 0);
  CHECK(t["settings"]["iterations"] == 30 + 20);
  CHECK(t["settings"]["densify_until"] == 42);  // the static schedules scaled to its new length (25 x 50 / 30)
  CHECK(read_json(dir / "r_still" / "run.json")["settings"]["fine_iterations"] == 0);
  const nlohmann::json& field = t["dataset"]["recipe"]["deformation_field"];
  CHECK(field["motion"] == "still");
  CHECK(field["changed_share"] == 0.0);
  CHECK(field["trained"].get<std::string>().starts_with("no:"));

  // Asked for, the field is trained on the same capture.
  REQUIRE(test::run_style4d("train", "--data " + (dir / "still").string() + " --run " + (dir / "r_asked").string() +
                                         " --preset fast --iters 30 --fine-iters 3",
                            dir / "asked.log") == 0);
  const nlohmann::json asked = read_json(dir / "r_asked" / "train.json");
  CHECK(asked["stage"] == "fine");
  CHECK(asked["dataset"]["recipe"]["deformation_field"]["trained"] == "yes: --fine-iters asked for it");
  // The preset's SH degree 1 is the most the run keeps: degree 1 active from step 10 (fast's 300 of
  // 900, scaled to 30), both degrees rendered on the held-out camera at step 20.
  const nlohmann::json& sh = asked["dataset"]["recipe"]["sh_degree"];
  REQUIRE_MESSAGE(sh.is_object(), asked["dataset"].dump());
  const std::vector<double> psnr = sh["psnr_by_degree"].get<std::vector<double>>();
  REQUIRE(psnr.size() == 2);
  const int chosen = train::lowest_sufficient_degree(psnr);
  CHECK(sh["degree"] == chosen);
  CHECK(sh["at_step"] == 20);
  CHECK(sh["held_out"] == true);
  CHECK(asked["settings"]["sh_degree"] == chosen);
  CHECK(asked["settings"]["sh_degree_auto"] == false);
  CHECK(read_json(dir / "r_asked" / "run.json")["settings"]["sh_degree"] == chosen);
  CHECK(ply_sh_coeffs(dir / "r_asked" / "geometry" / "gaussians.ply") == size_t((chosen + 1) * (chosen + 1)));
  CHECK_MESSAGE(contains(test::read_text(dir / "asked.log"), "SH degree " + std::to_string(chosen) + " of 1: held-out PSNR"),
                test::read_text(dir / "asked.log"));
  // The choice restored the run's state mid-run, and so did the field's box (fitted at fine step
  // 2 of 3, once the time window is open): neither counts the seconds before it again. Measured 0.35, and 1.26 on the code that
  // counted them twice; allowed: 0.7.
  CHECK(largest_seconds_jump(dir / "r_asked" / "loss.csv") < 0.7);
  const nlohmann::json& box = asked["dataset"]["recipe"]["field_box"];
  REQUIRE_MESSAGE(box.is_object(), asked["dataset"].dump());
  CHECK(box["at_step"] == 2);
  CHECK(box["moving"].get<uint32_t>() <= box["gaussians"].get<uint32_t>());
  CHECK(read_json(dir / "r_asked" / "run.json")["dataset"]["recipe"]["field_box"] == box);
  for (int k = 0; k < 3; ++k) {
    CHECK(box["min"][k].get<double>() >= box["old_min"][k].get<double>());
    CHECK(box["max"][k].get<double>() <= box["old_max"][k].get<double>());
    if (!box["fitted"].get<bool>()) CHECK(box["min"][k] == box["old_min"][k]);
  }
  CHECK_MESSAGE(contains(test::read_text(dir / "asked.log"), "deformation field box at fine iteration 2: "),
                test::read_text(dir / "asked.log"));

  // The built-in scene moves: its sliding box alone changes a tenth of a camera's pixels.
  REQUIRE(test::run_style4d("train", "--data " + (dir / "moving").string() + " --run " + (dir / "r_moving").string() +
                                         " --preset fast --iters 30 --set fine_iterations=3 --sh-degree 1",
                            dir / "moving.log") == 0);
  const nlohmann::json moving = read_json(dir / "r_moving" / "train.json");
  CHECK(moving["stage"] == "fine");
  const nlohmann::json& m = moving["dataset"]["recipe"]["deformation_field"];
  CHECK(m["motion"] == "moving");
  CHECK(m["changed_share"].get<double>() > 0.1);
  // The field's time axis, fitted with its box at fine step 2 of 3, is what the run's settings hold,
  // and so what a render builds.
  const nlohmann::json& axis = moving["dataset"]["recipe"]["field_time"];
  REQUIRE_MESSAGE(axis.is_object(), moving["dataset"].dump());
  CHECK(axis["at_step"] == 2);
  CHECK(axis["old_resolution"] == 16);
  CHECK(moving["settings"]["field_time"] == nlohmann::json::array({-1.0, 1.0}));
  CHECK(moving["settings"]["field_resolution"][3] == axis["resolution"]);
  CHECK(read_json(dir / "r_moving" / "run.json")["settings"]["field_resolution"][3] == axis["resolution"]);
  CHECK(axis["fitted"].get<bool>() == (axis["resolution"].get<uint32_t>() < 16));
  // A degree asked for is kept as it is.
  CHECK(moving["settings"]["sh_degree"] == 1);
  CHECK(moving["settings"]["sh_degree_auto"] == false);
  CHECK_FALSE(moving["dataset"]["recipe"].contains("sh_degree"));
  CHECK(ply_sh_coeffs(dir / "r_moving" / "geometry" / "gaussians.ply") == 4);
}

// The Gaussian budget (train/budget_growth.h): a preset's run starts at a quarter of it and probes
// when the budget holds a densification back; the record in train.json agrees with itself, with
// the densification log and with loss.csv (the kept branch's rows past the densification go when
// the run goes back for the grown branch). --budget fixes the budget.
TEST_CASE("the Gaussian budget grows by paired probes, and --budget fixes it") {
  const fs::path dir = test::fresh_dir("train_budget_growth");
  tiny_capture_with_settings(dir, R"({"settings": {"preset": "fast", "iterations": 60, "fine_iterations": 0,
      "sh_degree": 0, "budget": 400, "budget_start": 0.25, "densify_from": 10, "densify_until": 50, "densify_every": 10,
      "test_every": 20, "checkpoint_every": 20}})");
  REQUIRE(test::run_style4d("train", "--data " + (dir / "data").string() + " --run " + (dir / "grow").string() +
                                         " --config " + (dir / "settings.json").string(),
                            dir / "grow.log") == 0);
  const std::string log = test::read_text(dir / "grow.log");
  const nlohmann::json t = read_json(dir / "grow" / "train.json");
  const nlohmann::json& g = t["dataset"]["recipe"]["gaussian_budget"];
  REQUIRE_MESSAGE(g.is_object(), t["dataset"].dump());
  CHECK(g["grows"] == true);
  CHECK(g["ceiling"] == 400);
  CHECK(g["start"] == 100);
  REQUIRE_MESSAGE(!g["probes"].empty(), log);  // 200 initial points over a budget of 100: the first densification probes
  uint32_t budget = 100;
  for (const nlohmann::json& p : g["probes"]) {
    CHECK(p["from"] == budget);
    CHECK(p["to"] == std::min<uint32_t>(400, 2 * budget));
    CHECK(p["steps"] == 10);
    CHECK(p["demoted"].get<uint32_t>() * 10 >= budget);  // at least a tenth of the budget held back
    CHECK(p["held_out"] == true);
    CHECK(p["seconds"].get<double>() > 0);
    CHECK(p["seconds"].get<double>() < t["seconds"].get<double>() / 2);  // 10 of 70 steps: measured 0.43 of 3.2 s
    const bool grown = p["gain_db"].get<double>() >= g["keep_db"].get<double>();
    CHECK(p["grown"] == grown);
    CHECK(p["gaussians_grown"].get<uint32_t>() <= p["to"].get<uint32_t>());
    CHECK_MESSAGE(contains(log, std::string("Gaussian budget ") + (grown ? "grown to " : "kept at ")), log);
    // The run went on from the branch the probe chose: the densification at the probe's step is
    // logged once, within the budget of that branch (growth fills it; a cloud already over it
    // only prunes).
    uint32_t at_step = 0;
    for (const nlohmann::json& d : t["densify_log"]) {
      if (d["event"] != "densify" || d["iteration"] != p["at_step"]) continue;
      ++at_step;
      const uint32_t limit = (grown ? p["to"] : p["from"]).get<uint32_t>();
      const uint32_t kept = d["before"].get<uint32_t>() - d["pruned"].get<uint32_t>();
      CHECK(d["after"].get<uint32_t>() <= std::max(limit, kept));
      if (grown) CHECK(d["after"].get<uint32_t>() > std::min(p["from"].get<uint32_t>(), kept));  // it grew past the kept budget
    }
    CHECK(at_step == 1);
    if (grown) budget = p["to"].get<uint32_t>();
  }
  CHECK(g["budget"] == budget);
  // Each probe trained its steps twice: the process's steps are the stage's and the kept branches'.
  CHECK(t["stage_ms"]["iterations"] == 60 + 10 * g["probes"].size());
  CHECK(read_json(dir / "grow" / "run.json")["dataset"]["recipe"]["gaussian_budget"] == g);
  // loss.csv: each row once, in order.
  std::vector<long> expected;
  for (long it = 10; it <= 60; it += 10) expected.push_back(it);
  CHECK(loss_iterations(dir / "grow" / "loss.csv") == expected);

  REQUIRE(test::run_style4d("train", "--data " + (dir / "data").string() + " --run " + (dir / "fixed").string() +
                                         " --config " + (dir / "settings.json").string() + " --budget 400",
                            dir / "fixed.log") == 0);
  const nlohmann::json fixed = read_json(dir / "fixed" / "train.json");
  const nlohmann::json& f = fixed["dataset"]["recipe"]["gaussian_budget"];
  CHECK(f["grows"] == false);
  CHECK(f["budget"] == 400);
  CHECK(f["probes"].empty());
  CHECK(f["why"] == "off: --budget fixed it");
}

// A run stopped during a probe goes back to the probe's densification, does it at the budget
// decided and writes that state; the resumed run trains on from there and probes again when the
// budget holds the next densification back. The stop lands in the probe: the probe's two branches
// take 200 steps from iteration 100 on, and the signal is sent once loss.csv reaches 130.
TEST_CASE("a run stopped during a budget probe checkpoints the kept densification and resumes from it") {
  const fs::path dir = test::fresh_dir("train_budget_probe_stop");
  tiny_capture_with_settings(dir, R"({"settings": {"preset": "fast", "iterations": 400, "fine_iterations": 0,
      "sh_degree": 0, "budget": 400, "budget_start": 0.25, "densify_from": 50, "densify_until": 300, "densify_every": 100,
      "test_every": 50, "checkpoint_every": 100}})");
  const fs::path run = dir / "run";
  const pid_t pid = test::spawn_style4d({"train", "--data", (dir / "data").string(), "--run", run.string(), "--config",
                                         (dir / "settings.json").string()},
                                        dir / "stopped.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  auto reached_130 = [&] { return contains(fs::exists(run / "loss.csv") ? test::read_text(run / "loss.csv") : "", "static,130,"); };
  while (!reached_130() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  REQUIRE(reached_130());
  kill(pid, SIGINT);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  const std::string stopped = test::read_text(dir / "stopped.log");
  INFO(stopped);
  REQUIRE(test::exit_code(status) == 130);
  CHECK(contains(stopped, "Gaussian budget probe at static iteration 100 left undecided (the run stopped)"));
  const nlohmann::json partial = read_json(run / "train.json");
  CHECK(partial["iteration"] == 100);  // the densification's state, not a branch's
  CHECK(partial["dataset"]["recipe"]["gaussian_budget"]["probes"].empty());
  CHECK(partial["dataset"]["recipe"]["gaussian_budget"]["budget"] == 100);

  REQUIRE(test::run_style4d("train", "--resume " + run.string(), dir / "resumed.log") == 0);
  const nlohmann::json t = read_json(run / "train.json");
  CHECK(t["complete"] == true);
  uint32_t at_100 = 0;
  for (const nlohmann::json& d : t["densify_log"])
    if (d["event"] == "densify" && d["iteration"] == 100) {
      ++at_100;
      CHECK(d["after"].get<uint32_t>() <= std::max<uint32_t>(100, d["before"].get<uint32_t>() - d["pruned"].get<uint32_t>()));
    }
  CHECK(at_100 == 1);
  for (const nlohmann::json& p : t["dataset"]["recipe"]["gaussian_budget"]["probes"]) CHECK(p["at_step"] != 100);
  std::vector<long> expected;  // every row once, in order
  for (long it = 10; it <= 400; it += 10) expected.push_back(it);
  CHECK(loss_iterations(run / "loss.csv") == expected);
}
