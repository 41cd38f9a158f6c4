// style4d demo: the main job on the built-in scene and style, with nothing downloaded: the engine
// check, the built-in scene, 4DGS (static then fine stage, `fast` preset), stage 3 (the built-in
// style by the weight-free stylizer) and stage 4 (Style Gaussians), Style4D-Bench over the test and
// spiral protocols of the original and the style, and mp4 videos; DIR/report.md and DIR/demo.json
// hold the results with each stage's seconds and peak device memory. An interrupted demo continues
// where it stopped when run again with the same --out (training and stage 4 resume from their
// checkpoints).
#include <sys/resource.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "args.h"
#include "commands.h"
#include "demo_report.h"
#include "frame_sequence.h"
#include "primitives_bench.h"
#include "s4d/bench/style_eval.h"
#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/run/style_file.h"
#include "s4d/run/run_lock.h"
#include "s4d/style_gaussians/stylize_run.h"
#include "s4d/frame_stylizers/builtin_style.h"
#include "s4d/synth/dataset.h"
#include "s4d/train/trainer.h"
#include "s4d/util/progress.h"

namespace s4d::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// --time-budget's split, from the demo's own stages on an idle 2-core lavapipe machine (docs/demo.md,
// 2026-11-26: train 338 s, stylize 83 s, bench and videos 22 s): training gets this share of what is
// left after the engine check, stylize this share of what is left after training (the rest is the
// bench's and the videos', which have no length to fit).
constexpr double kTrainShare = 0.76, kStylizeShareAfterTrain = 0.79;

uint64_t host_peak_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<uint64_t>(u.ru_maxrss) * 1024;  // Linux reports KiB
}

// Times `work` and records the device-memory peak of its buffers on `ctx` (stages that open their
// own context, the bench, report 0 here; the process peak covers them).
template <class F>
void stage(DemoRecord& rec, engine::Context* ctx, const char* name, const char* what, F&& work) {
  if (ctx) ctx->reset_memory_peak();
  const auto start = Clock::now();
  work();
  rec.stages.push_back({name, what, seconds_since(start), ctx ? ctx->memory_peak() : 0});
}

// The protocol frames the bench rendered, as mp4 next to the report.
void write_video(const fs::path& frames, const fs::path& video) {
  const FrameSequence seq = read_frame_sequence(frames);
  write_frame_sequence(video, seq.frames, seq.names);
}

}  // namespace

int cmd_demo(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"out", "output directory (created; default style4d-demo); an interrupted demo continues in it", true, "DIR"},
      {"keys", "keys for the GPU sort/scan check (default 1048576)", true, "N"},
      {"iters", "static-stage iterations (default: the fast preset's)", true, "N"},
      {"fine-iters", "4DGS fine-stage iterations (default: the fast preset's, 1500)", true, "N"},
      {"style-iters", "stage-4 iterations (default 500)", true, "N"},
      {"mlp-iters", "the last N stage-4 iterations also train the style MLPs (default 60)", true, "N"},
      {"spiral-frames", "frames of the spiral protocol and video (default 60)", true, "N"},
      {"time-budget", "fit the whole demo to this much time, e.g. 5m: training and stage 4 are planned from their\n"
                      "                        measured step times (train and stylize --time-budget)", true, "DURATION"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("demo", "--out DIR",
                       "Runs the whole Style4D pipeline on the built-in scene and style with nothing\n"
                       "downloaded and writes DIR/report.md: 4DGS, stylization, Style Gaussians,\n"
                       "Style4D-Bench, videos, and each stage's time and memory.",
                       specs);
    return 0;
  }
  const fs::path out = args.get_or("out", "style4d-demo");
  const uint32_t keys = parse_number<uint32_t>("keys", args.get_or("keys", "1048576"));
  run::TrainConfig config = run::preset_config("fast");
  if (auto v = args.get("iters")) run::set_iterations(config, parse_number<uint32_t>("iters", *v));
  // Stage 4 is shortened from stylize's 1500/300 so that the build and the demo fit 15 minutes on
  // two lavapipe cores (docs/demo.md); the fine stage runs fast's full 1500 (1200 misses 28 dB by
  // about a decibel).
  if (auto v = args.get("fine-iters")) run::set_fine_iterations(config, parse_number<uint32_t>("fine-iters", *v));
  style_gaussians::StylizeRequest request;
  request.config.iterations = parse_number<uint32_t>("style-iters", args.get_or("style-iters", "500"));
  request.config.mlp_iterations = parse_number<uint32_t>("mlp-iters", args.get_or("mlp-iters", "60"));
  const std::string spiral_frames = args.get_or("spiral-frames", "60");
  const double budget = args.get("time-budget") ? parse_duration("time-budget", *args.get("time-budget")) : 0.0;
  fs::create_directories(out);
  // One demo per folder at a time: a second one on the same --out refuses (run_lock.h); its training
  // and stylize steps also take the run's locks as the commands do.
  const run::RunLock lock(out);
  const auto start = Clock::now();
  DemoRecord rec;
  rec.out = out;

  // The built-in scene, reused when an earlier demo run already finished writing it.
  const fs::path data = out / "data";
  const s4d::synth::SynthOptions scene;
  stage(rec, nullptr, "synth", "built-in synthetic dynamic scene (analytic ray caster)", [&] {
    if (fs::exists(data / "poses_bounds.npy")) return;
    util::Progress progress("synth", static_cast<uint64_t>(scene.cams) * static_cast<uint64_t>(scene.frames));
    s4d::synth::write_dataset(data, scene, [&](uint64_t done, uint64_t) { progress.update(done); });
    progress.finish();
  });
  rec.synth = {{"dataset", data.string()}, {"cams", scene.cams}, {"frames", scene.frames}, {"width", scene.width},
               {"height", scene.height}};

  engine::Context ctx;
  rec.device = ctx.info();
  std::cerr << "[demo] device: " << ctx.info().name << " (" << ctx.info().driver_info << ")\n";
  stage(rec, &ctx, "engine", "GPU radix sort and scan against their CPU twins", [&] {
    rec.sort = bench::bench_radix_sort(ctx, keys, 3);
    rec.scan = bench::bench_exclusive_scan(ctx, keys, 3);
  });

  const fs::path run = out / "run";
  const std::atomic<bool> never_stop{false};
  stage(rec, &ctx, "train", "stages 1-2: static Gaussians, then the 4DGS deformation field", [&] {
    fs::create_directories(run);
    // A continued demo goes on with its run's own plan (run.json).
    if (budget > 0) config.time_budget = std::max(1.0, kTrainShare * (budget - seconds_since(start)));
    const run::RunLock run_lock(run);  // as `style4d train`; released before the styles lock it shared
    auto trainer = fs::exists(run / "run.json") ? train::Trainer::resume(ctx, run)
                                                : std::make_unique<train::Trainer>(ctx, data, config, run);
    const train::TrainResult trained = trainer->run(never_stop);
    const nlohmann::json train_json = nlohmann::json::parse(std::ifstream(run / "train.json"));
    const nlohmann::json& settings = train_json.at("settings");
    rec.train = {{"run", run.string()},
                 {"preset", settings.at("preset")},
                 {"iterations", settings.at("iterations")},
                 {"fine_iterations", settings.at("fine_iterations")},
                 {"test_psnr", trained.test.psnr},
                 {"test_ssim", trained.test.ssim},
                 {"static_test_psnr", train_json.at("static").at("test_psnr")},
                 {"num_gaussians", trained.num_gaussians},
                 {"training_seconds", trained.seconds}};
    if (budget > 0) rec.time_budget = {{"given_seconds", budget}, {"train_seconds", settings.value("time_budget", 0.0)}};
  });

  // Stages 3-4 with the built-in style (written next to the run: the demo needs no file of ours).
  const fs::path style_image = out / "builtin_style.png";
  if (!fs::exists(style_image)) io::write_png(style_image, frame_stylizers::builtin_style());
  request.run = run, request.style_image = style_image, request.name = "builtin";
  request.spiral_frames = parse_number<int>("spiral-frames", spiral_frames);
  if (budget > 0) {
    // A continued stylize keeps the budget its request.json was started with.
    const fs::path started = run::style_dir(run, "builtin") / "request.json";
    request.time_budget = fs::exists(started) ? nlohmann::json::parse(std::ifstream(started)).value("time_budget", 0.0)
                                              : std::max(1.0, kStylizeShareAfterTrain * (budget - seconds_since(start)));
    rec.time_budget["stylize_seconds"] = request.time_budget;
  }
  stage(rec, &ctx, "stylize", "stages 3-4: the weight-free stylizer on every camera's frames, then Style Gaussians",
        [&] { rec.stylize = bench::stylize_and_measure(ctx, request, never_stop).summary; });

  const fs::path bench_dir = out / "bench";
  stage(rec, nullptr, "bench", "Style4D-Bench: test and spiral protocols rendered and scored, original and style", [&] {
    if (cmd_bench({"--run", run.string(), "--style", "original", "--style", "builtin", "--out", bench_dir.string(),
                   "--spiral-frames", spiral_frames, "--scene", "builtin"}) != 0)
      throw std::runtime_error("demo: the bench stage failed (see above)");
    rec.bench = nlohmann::json::parse(std::ifstream(bench_dir / "report.json"));
  });

  stage(rec, nullptr, "videos", "mp4 of the spiral and the test camera, original and style", [&] {
    fs::create_directories(out / "videos");
    for (const char* source : {"original", "builtin"}) {
      const std::string spiral = std::string("videos/spiral_") + source + ".mp4";
      const std::string test = std::string("videos/test_") + source + ".mp4";
      write_video(bench_dir / "renders" / source / "spiral", out / spiral);
      write_video(bench_dir / "renders" / source / "test" / s4d::synth::camera_dir_name(0), out / test);
      rec.videos.push_back(spiral);
      rec.videos.push_back(test);
    }
  });

  rec.host_peak_bytes = host_peak_bytes();
  rec.total_seconds = seconds_since(start);
  if (budget > 0) rec.time_budget["took_seconds"] = rec.total_seconds;
  write_demo_report(rec);
  const bool ok = engine_ok(rec);
  std::cout << "demo: engine on " << ctx.info().name << (ok ? " works" : " FAILED its check") << "; 4DGS test PSNR "
            << rec.train.at("test_psnr").get<double>() << " dB; " << rec.total_seconds << " s in all\n"
            << "demo: report: " << (out / "report.md").string() << "\n";
  return ok ? 0 : 1;
}

}  // namespace s4d::cli
