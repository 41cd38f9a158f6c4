// style4d train --data DIR --run RUN [--preset P] [--iters N] | --run RUN: stages 1 and 2 (static
// Gaussians, then 4DGS). SIGINT or SIGTERM writes a checkpoint and exits with 130; `train --run RUN`
// without --data continues it. --config FILE starts a new run from a saved run's settings.
// A finished run whose model is degenerate exits with 3 (kExitDegenerate).
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
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
    throw UsageError("--" + option + ": expected r,g,b with each in [0, 1], got '" + text + "'");
  return c;
}

// A real number; its range is validate()'s (train_config.h).
template <class T>
T parse_real(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  T value{};
  if (!(in >> value) || !in.eof()) throw UsageError("--" + option + ": expected a number, got '" + text + "'");
  return value;
}

// The command-line option that sets each setting, to name it in messages (validate's `flags`).
const std::map<std::string, std::string> kFlagOfSetting = {
    {"iterations", "--iters"}, {"fine_iterations", "--fine-iters"}, {"fine_batch", "--batch"},
    {"static_motion", "--static-motion"}, {"downscale", "--downscale"}, {"max_time", "--max-time"},
    {"static_max_time", "--static-max-time"}, {"background", "--background"}, {"frames", "--frame-range"},
    {"seed", "--seed"}, {"budget", "--budget"}, {"sh_degree", "--sh-degree"}, {"lr_scale", "--lr-scale"},
    {"checkpoint_every", "--checkpoint-every"}, {"time_budget", "--time-budget"}};

// A saved run's run.json or train.json: its settings, and the dataset it was trained on.
struct SavedConfig {
  run::TrainConfig settings;
  std::string data;
};

SavedConfig read_saved_config(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw UsageError("--config " + file + ": cannot open");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("settings"))
    throw UsageError("--config " + file + ": expected a run's run.json or train.json (a JSON object with 'settings')");
  SavedConfig out{run::config_from_json(j.at("settings"), file), ""};
  if (j.contains("data") && j.at("data").is_string()) out.data = j.at("data").get<std::string>();
  return out;
}

// The settings from the options over the preset's (or --config's): each option's value is checked
// once, by run::validate, and a bad one is named by its flag; --set values after them.
run::TrainConfig config_from_args(const Args& args, const std::string& default_preset) {
  if (args.get("config") && args.get("preset")) throw UsageError("--preset: --config FILE gives the settings; not both");
  run::TrainConfig c;
  try {
    c = args.get("config") ? read_saved_config(*args.get("config")).settings : run::preset_config(args.get_or("preset", default_preset));
  } catch (const std::invalid_argument& e) {  // an unknown preset
    throw UsageError(e.what());
  }
  if (auto v = args.get("iters")) run::set_iterations(c, parse_number<uint32_t>("iters", *v));
  if (auto v = args.get("fine-iters")) run::set_fine_iterations(c, parse_number<uint32_t>("fine-iters", *v));
  const std::string stage = args.get_or("stage", "all");
  if (stage == "static") c.fine_iterations = 0;
  else if (stage != "all") throw UsageError("--stage: expected static or all, got '" + stage + "'");
  if (auto v = args.get("static-motion")) c.static_motion = parse_real<float>("static-motion", *v);
  if (auto v = args.get("batch")) c.fine_batch = parse_number<uint32_t>("batch", *v);
  if (auto v = args.get("downscale")) c.downscale = parse_number<int>("downscale", *v);
  if (auto v = args.get("max-time")) c.max_time = parse_real<double>("max-time", *v);
  if (auto v = args.get("static-max-time")) {
    c.static_max_time = parse_real<double>("static-max-time", *v);
    // Negative is the presets' "chosen from the data", not something to ask for by hand.
    if (!(c.static_max_time >= 0 && c.static_max_time <= 1))
      throw UsageError("--static-max-time: expected a time in [0, 1], got '" + *v + "'");
  }
  if (auto v = args.get("background")) c.background = parse_colour("background", *v);
  if (auto v = args.get("frame-range")) {
    try {
      data::parse_frame_range(*v);  // refused here, before anything loads
    } catch (const std::exception& e) {
      throw UsageError(e.what());
    }
    c.frames = *v;
  }
  if (auto v = args.get("seed")) c.seed = parse_number<uint32_t>("seed", *v);
  if (auto v = args.get("budget")) c.budget = parse_number<uint32_t>("budget", *v);
  if (auto v = args.get("sh-degree")) {  // a degree asked for is kept; "auto" chooses up to the preset's
    c.sh_degree_auto = *v == "auto";
    if (!c.sh_degree_auto) c.sh_degree = parse_number<int>("sh-degree", *v);
  }
  if (auto v = args.get("lr-scale")) c.lr_scale = parse_real<double>("lr-scale", *v);
  if (auto v = args.get("checkpoint-every")) c.checkpoint_every = parse_number<uint32_t>("checkpoint-every", *v);
  if (auto v = args.get("time-budget")) c.time_budget = parse_duration("time-budget", *v);
  try {
    run::validate(c, "command line", kFlagOfSetting);
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
  // --set KEY=VALUE: any setting train.json lists, VALUE as JSON (a number, [32, 32, 32, 16], ...).
  nlohmann::json j = run::to_json(c);
  bool background_given = args.get("background").has_value();
  bool fine_given = args.get("fine-iters").has_value();
  bool budget_given = args.get("budget").has_value();
  for (const std::string& kv : args.get_all("set")) {
    background_given = background_given || kv.starts_with("background=");
    fine_given = fine_given || kv.starts_with("fine_iterations=");
    budget_given = budget_given || kv.starts_with("budget=");
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || !j.contains(kv.substr(0, eq)))
      throw UsageError("--set: expected KEY=VALUE with KEY one of the settings in train.json, got '" + kv + "'");
    const std::string key = kv.substr(0, eq), text = kv.substr(eq + 1);
    try {
      j[key] = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      if (!j[key].is_string())  // 1e999, nan: no number JSON holds
        throw UsageError(run::setting_error("--set", key, text, std::string("expected a JSON value (") + e.what() + ")"));
      j[key] = text;  // a bare word: a string setting such as the preset name
    }
  }
  run::TrainConfig out;
  try {
    out = run::config_from_json(j, "--set");  // validated again with the --set values
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
  out.background_given = background_given;
  out.fine_iterations_given = fine_given;
  out.budget_given = budget_given;
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
                             " error(s), listed above (style4d check-data --data " + dir +
                             " shows them all); fix them, or pass --skip-check to train anyway");
  }
  return std::move(checked.dataset);
}

}  // namespace

int cmd_train(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      group("the run"),
      {"data", "dataset directory in any layout of docs/real-data.md (DyNeRF/Neu3D, 4DGaussians, D-NeRF, HyperNeRF,\n"
                 "                        COLMAP rig), e.g. from style4d synth", true, "DIR"},
      {"run", "the run directory: with --data (or --config) a new run (must not exist, or be empty); without,\n"
              "                        the run to continue from its last checkpoint", true, "RUN", {"out"}},
      {"resume", "continue the run in RUN (old spelling of --run RUN without --data)", true, "RUN"},
      {"config", "a new run with the settings (and, without --data, the dataset) of a saved run's run.json or\n"
                 "                        train.json; the options below change them", true, "FILE"},
      {"skip-check", "start a new run without checking the dataset first (style4d check-data)", false, ""},
      group("schedule"),
      {"preset", "fast | default | quality (default: fast on a CPU device such as lavapipe, default on a GPU)", true, "P"},
      {"stage", "all: static then 4DGS (default); static: stage 1 only", true, "all|static"},
      {"time-budget", "fit the run to this much training time, e.g. 90s, 20m, 1h30m: both stages' lengths and\n"
                      "                        schedules, and the Gaussian budget unless --budget is given, are planned from\n"
                      "                        measured step times (train.json time_budget)", true, "DURATION"},
      {"iters", "iterations of the static stage; the preset's schedules are scaled to fit", true, "N"},
      {"fine-iters", "iterations of the 4DGS stage; its densification window is scaled to fit", true, "N"},
      {"batch", "views per 4DGS step (default: the preset's)", true, "B"},
      {"checkpoint-every", "iterations between checkpoints", true, "N"},
      {"seed", "seed of view order, initial points and split samples (default 0)", true, "S"},
      group("data"),
      {"downscale", "integer image downscale factor (default 1)", true, "K"},
      {"frame-range", "only frames (times) N first, or A to B-1, their times mapped onto [0, 1]: a cap for long\n"
                      "                        captures", true, "N|A:B", {"frames"}},
      {"max-time", "use only views with time <= T, e.g. 0 for the first frame (default 1)", true, "T"},
      {"static-max-time", "the static stage uses only views with time <= T; 0 makes the first frame the canonical\n"
                          "                        scene (preset's default: fast -1, chosen from the data; others 1)", true, "T"},
      {"background", "render and compositing background r,g,b in [0, 1] (default: found from the frames: alpha, a\n"
                     "                        uniform border colour, else the layout's)", true, "R,G,B"},
      group("model"),
      {"budget", "most Gaussians densification may create, fixed; without it the preset's budget is a ceiling:\n"
                 "                        the run starts at a quarter and doubles it while a paired probe's held-out\n"
                 "                        views gain (train.json dataset.recipe.gaussian_budget)", true, "N"},
      {"sh-degree", "spherical-harmonic degree 0..3, kept as given; default auto: the lowest degree up to\n"
                    "                        the preset's (fast 1, default 3) that serves held-out views as well\n"
                    "                        (train.json dataset.recipe.sh_degree)", true, "D"},
      {"static-motion", "Gaussians moving less than X x scene extent skip the deformation field (0: off)", true, "X"},
      {"lr-scale", "multiply every learning rate (default 1)", true, "X"},
      {"set", "KEY=VALUE: any setting of train.json's 'settings' (repeatable), e.g. grid_lr=0.005", true, "KEY=VALUE"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("train", "--data DIR --run RUN [options] | --config FILE --run RUN [options] | --run RUN",
                       "Trains static Gaussians, then the 4DGS deformation field. Writes RUN/geometry/gaussians.ply\n"
                       "(canonical Gaussians, standard 3DGS PLY; the field is in the checkpoint),\n"
                       "RUN/train.json (test_psnr, test_ssim, moving-content PSNR, seconds, num_gaussians, the\n"
                       "Gaussian count after every densification, settings, per test view), RUN/gaussian_count.png,\n"
                       "RUN/checkpoint/state.s4dckpt, RUN/loss.csv and RUN/eval/*.png (test-view renders).\n"
                       "Ctrl-C writes a checkpoint and exits; `train --run RUN` continues where it stopped. A\n"
                       "finished run is never trained again: continuing it says so and changes nothing.\n"
                       "A finished run whose model is degenerate (fewer than 16 Gaussians, or test renders\n"
                       "no better than the background alone) says why and exits with 3.\n"
                       "A new run first checks the dataset as `style4d check-data` does: warnings are printed,\n"
                       "errors are printed and refuse the run (--skip-check skips the check).",
                       specs);
    return 0;
  }
  refuse_positionals(args);
  // The run, and whether this is a new one: --data or --config start one, --run alone continues.
  if (args.get("resume") && args.get("run")) throw UsageError("--resume RUN: the run is --run RUN; give one of the two");
  if (args.get("resume")) warn_deprecated("--resume RUN", "--run RUN");
  const bool fresh = args.get("data") || args.get("config");
  const std::optional<std::string> continued = args.get("resume") ? args.get("resume") : fresh ? std::nullopt : args.get("run");
  if (!fresh && !continued) throw UsageError("missing required option --run (see --help)");
  std::string data_dir;
  if (fresh) {
    if (args.get("resume")) throw UsageError("--resume continues a run; a new run takes --data DIR --run RUN");
    args.require("run");
    data_dir = args.get("data") ? *args.get("data") : read_saved_config(*args.get("config")).data;
    if (data_dir.empty()) throw UsageError("--config " + *args.get("config") + ": names no dataset ('data'); give --data DIR");
  } else if (!std::filesystem::exists(std::filesystem::path(*continued) / "run.json") && !args.get("resume")) {
    throw UsageError("--run " + *continued + ": no run to continue there (no run.json); a new run needs --data DIR");
  }
  // A new run's settings and, unless skipped, its checked dataset, which the trainer then takes as is.
  std::optional<run::TrainConfig> config;
  std::optional<data::Dataset> checked;
  engine::Context ctx;
  if (fresh) {
    config = config_from_args(args, args.get("preset") ? "" : device_preset(ctx.info()));
    if (!args.flag("skip-check")) checked = check_dataset_first(data_dir, *config);
  }

  // One writer per run: the lock is held until this process ends (released by the kernel however it
  // ends), and a second `train` on the run refuses at once (run_lock.h).
  namespace fs = std::filesystem;
  std::optional<run::RunLock> lock;
  std::optional<fs::path> created;  // a new run's folder this command made, removed again if the run cannot start
  if (continued) {
    for (const OptionSpec& o : specs)
      if (!o.name.empty() && o.name != "run" && o.name != "resume" && (args.get(o.name) || args.flag(o.name)))
        throw UsageError("--" + o.name + " cannot change a run being continued");
    if (fs::exists(fs::path(*continued) / "run.json")) lock.emplace(*continued);  // otherwise resume says what is missing
    // A finished run is left as it is, whatever state its checkpoints are in; success, so that a script
    // continuing until done stops.
    if (lock && train::run_finished(*continued)) {
      std::cout << *continued << ": finished (train.json: complete); nothing to continue, its results are unchanged\n";
      return 0;
    }
  } else {
    const fs::path out = args.require("run");
    if (!fs::exists(out)) created = out;
    if (created || (fs::is_directory(out) && run::empty_but_for_lock(out))) {  // else the trainer refuses it
      fs::create_directories(out);
      lock.emplace(out);
    }
  }
  std::unique_ptr<train::Trainer> trainer;
  if (continued) {
    trainer = train::Trainer::resume(ctx, *continued);
  } else {
    try {
      trainer = std::make_unique<train::Trainer>(ctx, data_dir, *config, args.require("run"), std::move(checked));
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
  const fs::path run_dir = continued ? fs::path(*continued) : fs::path(args.require("run"));
  write_gaussian_count_plot(run::RunDir{run_dir});
  std::cout << run::stage_name(r.stage) << " stage: test PSNR " << r.test.psnr << " dB, SSIM " << r.test.ssim;
  if (r.test.moving.psnr) std::cout << ", moving content " << *r.test.moving.psnr << " dB";
  std::cout << ", " << r.num_gaussians << " Gaussians, " << r.seconds << " s\n";
  if (!r.degenerate.empty()) {
    // The run's files stay for inspection; the exit code tells scripts the model is unusable.
    std::cerr << "error: " << run_dir.string() << ": degenerate model: " << r.degenerate << "\n";
    return kExitDegenerate;
  }
  return 0;
}

}  // namespace s4d::cli
