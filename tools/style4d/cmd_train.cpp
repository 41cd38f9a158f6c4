// style4d train --data DIR --out RUN [--preset P] [--iters N] | --resume RUN: stages 1 and 2
// (static Gaussians, then 4DGS). SIGINT or SIGTERM writes a checkpoint and exits with 130;
// --resume continues it. A finished run whose model is degenerate exits with 3 (kExitDegenerate).
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "s4d/data/dataset_check.h"
#include "s4d/engine/context.h"
#include "s4d/run/run_lock.h"
#include "s4d/train/data_recipe.h"
#include "s4d/train/trainer.h"
#include "train_plots.h"

namespace s4d::cli {

// A finished run whose model is degenerate (no Gaussians, or renders no better than the
// background): its files are written, but scripts must not take it for a result.
constexpr int kExitDegenerate = 3;


namespace {

std::atomic<bool> g_stop{false};

extern "C" void request_stop(int) { g_stop.store(true); }

// "r,g,b" with each in [0, 1].
std::array<float, 3> parse_colour(const std::string& option, const std::string& text) {
  std::array<float, 3> c{};
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0;
  in >> c[0] >> comma1 >> c[1] >> comma2 >> c[2];
  if (!in || !in.eof() || comma1 != ',' || comma2 != ',' || c[0] < 0 || c[0] > 1 || c[1] < 0 || c[1] > 1 || c[2] < 0 ||
      c[2] > 1)
    throw std::invalid_argument("--" + option + ": expected r,g,b with each in [0, 1], got '" + text + "'");
  return c;
}

// A real number; its range is validate()'s (train_config.h).
template <class T>
T parse_real(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  T value{};
  if (!(in >> value) || !in.eof()) throw std::invalid_argument("--" + option + ": expected a number, got '" + text + "'");
  return value;
}

// The settings from the options: each option's value is checked once, by run::validate, with
// SOURCE "command line" (the preset and the options) or "--set" (after the --set values).
run::TrainConfig config_from_args(const Args& args, const std::string& default_preset) {
  run::TrainConfig c = run::preset_config(args.get_or("preset", default_preset));
  if (auto v = args.get("iters")) run::set_iterations(c, parse_number<uint32_t>("iters", *v));
  if (auto v = args.get("fine-iters")) run::set_fine_iterations(c, parse_number<uint32_t>("fine-iters", *v));
  const std::string stage = args.get_or("stage", "all");
  if (stage == "static") c.fine_iterations = 0;
  else if (stage != "all") throw std::invalid_argument("--stage: expected static or all, got '" + stage + "'");
  if (auto v = args.get("static-motion")) c.static_motion = parse_real<float>("static-motion", *v);
  if (auto v = args.get("batch")) c.fine_batch = parse_number<uint32_t>("batch", *v);
  if (auto v = args.get("downscale")) c.downscale = parse_number<int>("downscale", *v);
  if (auto v = args.get("max-time")) c.max_time = parse_real<double>("max-time", *v);
  if (auto v = args.get("static-max-time")) {
    c.static_max_time = parse_real<double>("static-max-time", *v);
    // Negative is the presets' "chosen from the data", not something to ask for by hand.
    if (!(c.static_max_time >= 0 && c.static_max_time <= 1))
      throw std::invalid_argument("--static-max-time: expected a time in [0, 1], got '" + *v + "'");
  }
  if (auto v = args.get("background")) c.background = parse_colour("background", *v);
  if (auto v = args.get("frames")) {
    data::parse_frame_range(*v);  // refused here, before anything loads
    c.frames = *v;
  }
  if (auto v = args.get("seed")) c.seed = parse_number<uint32_t>("seed", *v);
  if (auto v = args.get("budget")) c.budget = parse_number<uint32_t>("budget", *v);
  if (auto v = args.get("sh-degree")) c.sh_degree = parse_number<int>("sh-degree", *v);
  if (auto v = args.get("lr-scale")) c.lr_scale = parse_real<double>("lr-scale", *v);
  if (auto v = args.get("checkpoint-every")) c.checkpoint_every = parse_number<uint32_t>("checkpoint-every", *v);
  run::validate(c, "command line");
  // --set KEY=VALUE: any setting train.json lists, VALUE as JSON (a number, [32, 32, 32, 16], ...).
  nlohmann::json j = run::to_json(c);
  bool background_given = args.get("background").has_value();
  for (const std::string& kv : args.get_all("set")) {
    background_given = background_given || kv.starts_with("background=");
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || !j.contains(kv.substr(0, eq)))
      throw std::invalid_argument("--set: expected KEY=VALUE with KEY one of the settings in train.json, got '" + kv + "'");
    const std::string key = kv.substr(0, eq), text = kv.substr(eq + 1);
    try {
      j[key] = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      if (!j[key].is_string())  // 1e999, nan: no number JSON holds
        throw std::invalid_argument(run::setting_error("--set", key, text, std::string("expected a JSON value (") + e.what() + ")"));
      j[key] = text;  // a bare word: a string setting such as the preset name
    }
  }
  run::TrainConfig out = run::config_from_json(j, "--set");  // validated again with the --set values
  out.background_given = background_given;
  return out;
}

// The preset when --preset is not given: `fast` on a CPU device (lavapipe), whose 4DGS stage is sized
// for its speed, `default` on a GPU (docs/gpu.md). Said in one line, so a run never surprises.
std::string device_preset(const engine::DeviceInfo& device) {
  const bool cpu = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  const std::string preset = cpu ? "fast" : "default";
  std::cout << "preset " << preset << ": chosen for " << (cpu ? "a CPU" : "a GPU") << " device (" << device.name
            << "); --preset overrides\n";
  return preset;
}

// A new run checks its dataset first, loaded as the trainer loads it (style4d check-data): warnings
// are printed, errors are printed and refuse the run. Returns the dataset for the trainer.
data::Dataset check_dataset_first(const std::string& dir, const run::TrainConfig& config) {
  data::CheckedDataset checked = data::load_and_check(dir, train::load_options(config, false));
  const data::DatasetReport& report = checked.report;
  for (const data::Problem& p : report.problems) std::cerr << data::format_problem(p) << "\n";
  if (report.errors() > 0) {
    throw std::runtime_error("the dataset check found " + std::to_string(report.errors()) +
                             " error(s), listed above (style4d check-data " + dir +
                             " shows them all); fix them, or pass --skip-check to train anyway");
  }
  return std::move(checked.dataset);
}

}  // namespace

int cmd_train(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"data", "dataset directory in any layout of docs/real-data.md (DyNeRF/Neu3D, 4DGaussians, D-NeRF, HyperNeRF,\n"
                 "                        COLMAP rig), e.g. from style4d synth", true, "DIR"},
      {"out", "run directory to create (must not exist, or be empty)", true, "RUN"},
      {"resume", "continue the run in RUN from its last checkpoint (other options are taken from the run)", true, "RUN"},
      {"stage", "all: static then 4DGS (default); static: stage 1 only", true, "all|static"},
      {"fine-iters", "iterations of the 4DGS stage; its densification window is scaled to fit", true, "N"},
      {"batch", "views per 4DGS step (default: the preset's)", true, "B"},
      {"static-motion", "Gaussians moving less than X x scene extent skip the deformation field (0: off)", true, "X"},
      {"preset", "fast | default | quality (default: fast on a CPU device such as lavapipe, default on a GPU)", true, "P"},
      {"iters", "iterations; the preset's schedules are scaled to fit", true, "N"},
      {"downscale", "integer image downscale factor (default 1)", true, "K"},
      {"max-time", "use only views with time <= T, e.g. 0 for the first frame (default 1)", true, "T"},
      {"set", "KEY=VALUE: any setting of train.json's 'settings' (repeatable), e.g. grid_lr=0.005", true, "KEY=VALUE"},
      {"static-max-time", "the static stage uses only views with time <= T; 0 makes the first frame the "
                          "canonical scene (preset's default: fast 0, others 1)", true, "T"},
      {"background", "render and compositing background r,g,b in [0, 1] (default: found from the frames: alpha, a\n"
                     "                        uniform border colour, else the layout's)", true, "R,G,B"},
      {"frames", "only frames (times) N first, or A to B-1, their times mapped onto [0, 1]: a cap for long captures", true,
       "N|A:B"},
      {"seed", "seed of view order, initial points and split samples (default 0)", true, "S"},
      {"budget", "most Gaussians densification may create", true, "N"},
      {"sh-degree", "highest spherical-harmonic degree, 0..3", true, "D"},
      {"checkpoint-every", "iterations between checkpoints", true, "N"},
      {"lr-scale", "multiply every learning rate (default 1)", true, "X"},
      {"skip-check", "start a new run without checking the dataset first (style4d check-data)", false, ""},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("train", "--data DIR --out RUN [options] | --resume RUN",
                       "Trains static Gaussians, then the 4DGS deformation field. Writes RUN/geometry/gaussians.ply\n"
                       "(canonical Gaussians, standard 3DGS PLY; the field is in the checkpoint),\n"
                       "RUN/train.json (test_psnr, test_ssim, moving-content PSNR, seconds, num_gaussians, the\n"
                       "Gaussian count after every densification, settings, per test view), RUN/gaussian_count.png,\n"
                       "RUN/checkpoint/state.s4dckpt, RUN/loss.csv and RUN/eval/*.png (test-view renders).\n"
                       "Ctrl-C writes a checkpoint and exits; --resume RUN continues where it stopped.\n"
                       "A finished run whose model is degenerate (fewer than 16 Gaussians, or test renders\n"
                       "no better than the background alone) says why and exits with 3.\n"
                       "A new run first checks the dataset as `style4d check-data` does: warnings are printed,\n"
                       "errors are printed and refuse the run (--skip-check skips the check).",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw std::invalid_argument("unexpected argument '" + args.positionals().front() + "'");
  // A new run's settings and, unless skipped, its checked dataset, which the trainer then takes as is.
  std::optional<run::TrainConfig> config;
  std::optional<data::Dataset> checked;
  engine::Context ctx;
  if (!args.get("resume")) {
    config = config_from_args(args, args.get("preset") ? "" : device_preset(ctx.info()));
    if (!args.flag("skip-check")) checked = check_dataset_first(args.require("data"), *config);
  }

  // One writer per run: the lock is held until this process ends (released by the kernel however it
  // ends), and a second `train` on the run refuses at once (run_lock.h).
  namespace fs = std::filesystem;
  std::optional<run::RunLock> lock;
  std::optional<fs::path> created;  // a new run's folder this command made, removed again if the run cannot start
  if (auto run = args.get("resume")) {
    for (const char* other : {"data", "out", "preset", "iters", "downscale", "max-time", "static-max-time", "set", "background", "frames", "seed", "budget", "sh-degree", "lr-scale", "stage", "fine-iters", "batch", "static-motion"})
      if (args.get(other)) throw std::invalid_argument(std::string("--") + other + " cannot change a run being resumed");
    if (fs::exists(fs::path(*run) / "run.json")) lock.emplace(*run);  // otherwise resume says what is missing
  } else {
    const fs::path out = args.require("out");
    if (!fs::exists(out)) created = out;
    if (created || (fs::is_directory(out) && run::empty_but_for_lock(out))) {  // else the trainer refuses it
      fs::create_directories(out);
      lock.emplace(out);
    }
  }
  std::unique_ptr<train::Trainer> trainer;
  if (auto run = args.get("resume")) {
    trainer = train::Trainer::resume(ctx, *run);
  } else {
    try {
      trainer = std::make_unique<train::Trainer>(ctx, args.require("data"), *config, args.require("out"), std::move(checked));
    } catch (...) {
      if (created && lock) {  // leave no empty run folder behind
        lock->release(true);
        std::error_code ec;
        fs::remove(*created, ec);
      }
      throw;
    }
  }
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  const train::TrainResult r = trainer->run(g_stop);
  if (!r.complete) return 130;
  write_gaussian_count_plot(run::RunDir{args.get("resume") ? fs::path(*args.get("resume")) : fs::path(args.require("out"))});
  std::cout << run::stage_name(r.stage) << " stage: test PSNR " << r.test.psnr << " dB, SSIM " << r.test.ssim;
  if (r.test.moving.psnr) std::cout << ", moving content " << *r.test.moving.psnr << " dB";
  std::cout << ", " << r.num_gaussians << " Gaussians, " << r.seconds << " s\n";
  if (!r.degenerate.empty()) {
    // The run's files stay for inspection; the exit code tells scripts the model is unusable.
    std::cerr << "error: " << args.get_or("out", args.get_or("resume", "")) << ": degenerate model: " << r.degenerate << "\n";
    return kExitDegenerate;
  }
  return 0;
}

}  // namespace s4d::cli
