// style4d train on a tiny synthetic scene: outputs and their contract, interruption by SIGINT and
// --resume ending where an uninterrupted run ends, divergence handling, and bad input.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/run/checkpoint.h"

using namespace s4d;
namespace fs = std::filesystem;


namespace {

// 4 cameras x 3 frames at 48x36: seconds per run on lavapipe.
const fs::path& tiny_dataset() {
  static const fs::path data = [] {
    const fs::path dir = test::fresh_dir("train_data");
    REQUIRE(test::run_style4d("synth", "--out " + (dir / "d").string() + " --cams 4 --frames 3 --size 48x36",
                              dir / "synth.log") == 0);
    return dir / "d";
  }();
  return data;
}

const std::string kTrainArgs = " --preset fast --stage static --iters 240 --max-time 0 --checkpoint-every 40";

// The loss column of loss.csv (stage,iteration,loss,...).
std::vector<double> loss_column(const fs::path& csv) {
  std::istringstream in(test::read_text(csv));
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> out;
  while (std::getline(in, line)) {
    const size_t iteration = line.find(',') + 1;  // stage,iteration,loss,...
    out.push_back(std::stod(line.substr(line.find(',', iteration) + 1)));
  }
  return out;
}

// Starts style4d with stdout and stderr in `log`; returns its pid.
nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

// train.json's per-stage times: every named stage that ran took time, and the stages add up to no
// more than the steps' wall time. GPU timestamps and the host clock are different clocks read at
// different moments: 1 % + 1 ms of slack (the stages added up to 96 % of the steps' time in the
// static run here; the rest is host work: uploads, waits, recording).
void check_stage_ms(const nlohmann::json& train, uint32_t iterations, std::initializer_list<const char*> ran) {
  REQUIRE(train.contains("stage_ms"));
  const nlohmann::json& s = train["stage_ms"];
  CHECK(s["iterations"] == iterations);
  CHECK((s["clock"] == "gpu timestamps" || s["clock"] == "host wall clock"));
  double sum = 0;
  for (const auto& [name, stage] : s["stages"].items()) {
    sum += stage["ms"].get<double>();
    CHECK(stage["ms_per_iteration"].get<double>() == doctest::Approx(stage["ms"].get<double>() / iterations));
  }
  for (const char* name : ran) CHECK_MESSAGE(s["stages"][name]["ms"].get<double>() > 0, name);
  CHECK(sum == doctest::Approx(s["stages_sum_ms"].get<double>()));
  const double step_ms = s["step_ms"].get<double>();
  CHECK(step_ms <= 1000 * train["seconds"].get<double>());
  CHECK(sum <= step_ms * 1.01 + 1.0);
}

TEST_CASE("train writes the run contract and learns the scene") {
  const fs::path dir = test::fresh_dir("train_ok");
  const fs::path run = dir / "run";
  REQUIRE(test::run_style4d("train", "--data " + tiny_dataset().string() + " --out " + run.string() + kTrainArgs,
                            dir / "log") == 0);
  const nlohmann::json j = read_json(run / "train.json");
  for (const char* key : {"test_psnr", "test_ssim", "seconds", "num_gaussians", "settings"}) CHECK(j.contains(key));
  CHECK(j["complete"] == true);
  check_stage_ms(j, 240, {"project", "sort", "raster", "loss", "backward", "adam", "densify"});
  CHECK(j["stage_ms"]["stages"]["field"]["ms"] == 0.0);  // the static stage has no field
  const io::GaussianCloud cloud = io::read_ply_gaussians(run / "geometry" / "gaussians.ply");
  CHECK(cloud.size() == j["num_gaussians"].get<size_t>());
  CHECK(fs::exists(run / "eval" / "cam00_0000.png"));
  CHECK(j["test_views"].size() == 1);  // cam00 at the first frame
  // Training lowered the loss well below where it started.
  const std::vector<double> losses = loss_column(run / "loss.csv");
  REQUIRE(losses.size() == 24);  // a row every 10 iterations
  CHECK(losses.back() < 0.7 * losses.front());
  CHECK(j["test_psnr"].get<double>() > 15.0);  // measured 23.2 dB after 240 iterations at 48x36
  // Progress went to stderr with the iteration, loss and Gaussian count.
  const std::string log = test::read_text(dir / "log");
  CHECK(log.find("static") != std::string::npos);
  CHECK(log.find("gaussians") != std::string::npos);
  // Resuming a finished run changes nothing.
  REQUIRE(test::run_style4d("train", "--resume " + run.string(), dir / "resume.log") == 0);
  CHECK(read_json(run / "train.json")["num_gaussians"] == j["num_gaussians"]);
  CHECK(read_json(run / "train.json")["stage_ms"] == j["stage_ms"]);  // it trained no step
}

// llvmpipe runs compute workgroups on LP_NUM_THREADS threads; with one, the order of the float
// atomics in the backward pass is fixed, so two runs are bit-identical and a resumed run must be too.
// (With more threads, two uninterrupted runs already differ in the last bits, which compound.)
const std::vector<std::string> kResumeArgs = {"--preset", "fast", "--iters", "60", "--fine-iters", "40", "--batch", "2",
                                              "--checkpoint-every", "20", "--static-motion", "0.002"};

// The uninterrupted run both resume tests end against, trained once per process (one lavapipe thread).
const fs::path& whole_run() {
  static const fs::path whole = [] {
    const test::SingleThreadedLavapipe one_thread;
    const fs::path dir = test::fresh_dir("train_whole");
    std::string args = "--data " + tiny_dataset().string() + " --out " + (dir / "whole").string();
    for (const std::string& a : kResumeArgs) args += " " + a;
    REQUIRE(test::run_style4d("train", args, dir / "whole.log") == 0);
    return dir / "whole";
  }();
  return whole;
}

// Trains into `run`, stops it with SIGINT once its first checkpoint exists, then resumes it.
// Returns false when the run finished before the signal arrived (nothing was interrupted).
bool interrupt_and_resume(const fs::path& run, const fs::path& dir) {
  std::vector<std::string> args = {"train", "--data", tiny_dataset().string(), "--out", run.string()};
  args.insert(args.end(), kResumeArgs.begin(), kResumeArgs.end());
  const pid_t pid = test::spawn_style4d(args, dir / "parted.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(run / "checkpoint" / "state.s4dckpt") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  REQUIRE(fs::exists(run / "checkpoint" / "state.s4dckpt"));
  kill(pid, SIGINT);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  INFO(test::read_text(dir / "parted.log"));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return false;
  CHECK(WEXITSTATUS(status) == 130);
  const nlohmann::json partial = read_json(run / "train.json");
  CHECK(partial["complete"] == false);
  CHECK((partial["stage"] == "static" || partial["iteration"].get<int>() < 40));
  CHECK(test::read_text(dir / "parted.log").find("style4d train --run ") != std::string::npos);
  REQUIRE(test::run_style4d("train", "--resume " + run.string(), dir / "resumed.log") == 0);
  return true;
}

}  // namespace

// SIGKILL, in steps and in checkpoint writes, is the next test's.
TEST_CASE("both stages; SIGINT, then --resume, ends exactly where an uninterrupted run ends") {
  const test::SingleThreadedLavapipe one_thread;
  const fs::path dir = test::fresh_dir("train_resume");
  const fs::path& whole = whole_run();
  // Both stages ran: the 4DGS stage is scored per frame of the test camera and beats the static one.
  const nlohmann::json j = read_json(whole / "train.json");
  CHECK(j["stage"] == "fine");
  check_stage_ms(j, 100, {"project", "sort", "raster", "loss", "backward", "field", "adam", "densify"});
  REQUIRE(j["test_views"].size() == 3);
  CHECK(j["test_views"][1]["time"].get<double>() == doctest::Approx(0.5));
  REQUIRE(j["static"]["test_views"].size() == 3);
  CHECK(j["test_psnr"].get<double>() > j["static"]["test_psnr"].get<double>() + 0.1);  // measured +0.29 dB (19.18 vs 18.89)
  const run::Checkpoint cp = run::read_checkpoint(whole / "checkpoint" / "state.s4dckpt");
  CHECK(cp.extra.size() == 7);  // the field's planes and MLP, both Adam moments of each, the still mask
  // Deform only what moves: from the end of densification on, Gaussians under the threshold skip the field
  // and are moved behind the moving ones in memory, every per-Gaussian array with them, so the resumes
  // below also check that reorder (measured 474 of 4000 moving, 275k of 388k evaluations).
  CHECK(j["moving_gaussians"].get<double>() < j["num_gaussians"].get<double>());
  CHECK(j["deform_evaluations"].get<double>() < j["deform_evaluations_unmasked"].get<double>());
  const fs::path run = dir / "sigint";
  if (!interrupt_and_resume(run, dir)) MESSAGE("the run finished before the signal; only completion was checked");
  CHECK(test::read_text(run / "geometry" / "gaussians.ply") == test::read_text(whole / "geometry" / "gaussians.ply"));
  CHECK(loss_column(run / "loss.csv") == loss_column(whole / "loss.csv"));  // every row once, the same losses
  CHECK(read_json(run / "train.json")["test_psnr"] == read_json(whole / "train.json")["test_psnr"]);
}

TEST_CASE("kill -9 anywhere, over and over, checkpoint writes included: every resume continues, the end is exact") {
  const test::SingleThreadedLavapipe one_thread;
  const fs::path dir = test::fresh_dir("train_kill_anywhere");
  // A checkpoint every other step, so kills land in checkpoint writes as well as in steps. The end is
  // checked against the uninterrupted run's, which checkpointed every 20 steps: writing checkpoints
  // changes nothing (two runs differing only there wrote identical files, measured).
  std::vector<std::string> settings = kResumeArgs;
  settings[std::find(settings.begin(), settings.end(), "--checkpoint-every") - settings.begin() + 1] = "2";
  const fs::path& whole = whole_run();
  const fs::path run = dir / "killed";

  std::vector<std::string> first = {"train", "--data", tiny_dataset().string(), "--out", run.string()};
  first.insert(first.end(), settings.begin(), settings.end());
  const std::vector<std::string> resume = {"train", "--resume", run.string()};
  // Delays after a segment's first checkpoint exists, spread so that over the segments the kills fall
  // at different phases of steps and writes (milliseconds; primes, so they do not line up).
  int kills = 0;
  for (const int delay_ms : {0, 37, 151, 313, 577, 911, 1409, 2003}) {
    const bool started = fs::exists(run / "run.json");
    const pid_t pid = test::spawn_style4d(started ? resume : first, dir / ("segment" + std::to_string(kills) + ".log"));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(run / "checkpoint" / "state.s4dckpt") && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    if (WIFEXITED(status)) {
      INFO(test::read_text(dir / ("segment" + std::to_string(kills) + ".log")));
      REQUIRE(WEXITSTATUS(status) == 0);  // finished before the kill
      break;
    }
    ++kills;
    // Whatever the kill interrupted, one of the two rotated checkpoints is complete.
    CHECK_NOTHROW(run::read_checkpoint_or_previous(run / "checkpoint" / "state.s4dckpt",
                                                     run / "checkpoint" / "state.prev.s4dckpt"));
  }
  MESSAGE(kills << " kills before the run finished");
  CHECK(kills >= 3);
  if (!fs::exists(run / "train.json") || read_json(run / "train.json")["complete"] != true)
    REQUIRE(test::run_style4d("train", "--resume " + run.string(), dir / "last.log") == 0);
  CHECK(test::read_text(run / "geometry" / "gaussians.ply") == test::read_text(whole / "geometry" / "gaussians.ply"));
  CHECK(loss_column(run / "loss.csv") == loss_column(whole / "loss.csv"));
  CHECK(read_json(run / "train.json")["test_psnr"] == read_json(whole / "train.json")["test_psnr"]);
}

TEST_CASE("a diverging run rolls back, says so, and never writes a non-finite checkpoint") {
  const fs::path dir = test::fresh_dir("train_diverge");
  const fs::path run = dir / "run";
  const int rc = test::run_style4d(
      "train", "--data " + tiny_dataset().string() + " --out " + run.string() + kTrainArgs + " --lr-scale 1e7", dir / "log");
  const std::string log = test::read_text(dir / "log");
  INFO(log);
  CHECK(log.find("rolled back") != std::string::npos);
  if (rc != 0) CHECK(log.find("diverged") != std::string::npos);
  if (fs::exists(run / "checkpoint" / "state.s4dckpt")) CHECK_NOTHROW(run::read_checkpoint(run / "checkpoint" / "state.s4dckpt"));
}

TEST_CASE("with no --preset, train takes the device's preset and says so; an explicit one wins") {
  // The tests run on lavapipe, a CPU device: `fast`.
  const fs::path dir = test::fresh_dir("train_device_preset");
  const std::string common = "--data " + tiny_dataset().string() + " --stage static --iters 2 --max-time 0 --out ";
  REQUIRE(test::run_style4d("train", common + (dir / "chosen").string(), dir / "chosen.log") == 0);
  const std::string chosen = test::read_text(dir / "chosen.log");
  CHECK_MESSAGE(chosen.find("preset fast: chosen for a CPU device (") != std::string::npos, chosen);
  CHECK(read_json(dir / "chosen" / "train.json")["settings"]["preset"] == "fast");
  REQUIRE(test::run_style4d("train", common + (dir / "given").string() + " --preset default", dir / "given.log") == 0);
  CHECK(test::read_text(dir / "given.log").find("chosen for") == std::string::npos);
  CHECK(read_json(dir / "given" / "train.json")["settings"]["preset"] == "default");
  REQUIRE(test::run_style4d("train", "--help", dir / "help.log") == 0);
  CHECK(test::read_text(dir / "help.log").find("default: fast on a CPU device") != std::string::npos);
}

TEST_CASE("train refuses bad input with a clear message") {
  const fs::path dir = test::fresh_dir("train_bad");
  fs::create_directories(dir / "busy");
  { std::ofstream(dir / "busy" / "file") << "x"; }
  CHECK(test::run_style4d("train", "--data " + tiny_dataset().string() + " --out " + (dir / "busy").string(), dir / "l1") != 0);
  CHECK(test::read_text(dir / "l1").find("not empty") != std::string::npos);
  CHECK(test::run_style4d("train", "--data " + (dir / "nowhere").string() + " --out " + (dir / "r").string(), dir / "l2") != 0);
  CHECK(test::read_text(dir / "l2").find("nowhere") != std::string::npos);
  CHECK(test::run_style4d("train", "--resume " + dir.string(), dir / "l3") != 0);
  CHECK(test::read_text(dir / "l3").find("run.json") != std::string::npos);
  CHECK(test::run_style4d("train", "--data x --out y --preset turbo", dir / "l4") != 0);
  CHECK(test::read_text(dir / "l4").find("turbo") != std::string::npos);
  CHECK(test::run_style4d("train", "--resume " + dir.string() + " --iters 5", dir / "l5") != 0);
  CHECK(test::read_text(dir / "l5").find("--iters") != std::string::npos);
}
