// style4d view --run RUN: the real-time viewer of a trained run (viewer/), or with --screenshot a
// headless capture of one dataset camera at one time, which needs no display and no GLFW.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <tuple>

#include "args.h"
#include "commands.h"
#include "run_outputs.h"
#include "s4d/engine/context.h"
#include "s4d/scene/trained_run.h"
#include "s4d/viewer/capture.h"
#include "s4d/viewer/dataset_cameras.h"
#include "style_args.h"
#ifdef S4D_HAVE_VIEWER_WINDOW
#include "viewer_app.h"
#endif

namespace s4d::cli {

namespace {

// --camera N or --camera NAME (cam01, as render --path train:cam01 names it).
size_t camera_index(const std::string& text, const std::vector<io::CameraView>& cameras) {
  std::string names;
  for (size_t k = 0; k < cameras.size() && k < 12; ++k) names += (k ? ", " : "") + cameras[k].name;
  names += cameras.size() > 12 ? ", ..." : "";
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
    const size_t index = parse_number<size_t>("camera", text);
    if (index >= cameras.size())
      throw UsageError("--camera " + text + ": the run's dataset has cameras 0.." + std::to_string(cameras.size() - 1) + " (" +
                       names + ")");
    return index;
  }
  for (size_t k = 0; k < cameras.size(); ++k) {
    std::string underscored = cameras[k].name;  // D-NeRF's train/r_000 is render's train_r_000
    std::replace(underscored.begin(), underscored.end(), '/', '_');
    if (cameras[k].name == text || underscored == text) return k;
  }
  throw UsageError("--camera " + text + ": no such camera; give an index 0.." + std::to_string(cameras.size() - 1) +
                   " or a name (" + names + ")");
}

}  // namespace

int cmd_view(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"run", "the trained run to show (style4d train); `view RUN` is the old spelling", true, "RUN"},
      {"style", "style to show (default: original)", true, "NAME"},
      mix_spec(),
      alpha_spec(),
      half_spec(),
      {"screenshot", "render one frame without a window into this PNG and exit", true, "F.png"},
      {"time", "time t in [0, 1] to start at or capture (default 0)", true, "T"},
      {"camera", "dataset camera to start from or capture: its index or its name, as render's train:CAM\n"
                 "                        (default 0)", true, "N|NAME"},
      {"play", "start playing", false, ""},
      {"exit-after", "quit after N presented frames (tests)", true, "N"},
      {"record", "record the camera path from the first frame; written on exit as transforms.json", true, "FILE"},
      {"out-dir", "where screenshots (P) and camera paths (R) go (default RUN/viewer)", true, "DIR"},
      {"size", "window size (default: the first camera's aspect, 640..1280 wide)", true, "WxH"},
      {"frame-budget-ms", "frame time to hold while the view moves by rendering fewer pixels; 0: always full "
                          "resolution (default 100, or 0 with --exit-after)", true, "MS"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("view", "--run RUN [options]",
                       "Shows a trained run in a window: left drag orbits, right/middle drag pans, the wheel zooms,\n"
                       "W/A/S/D/Q/E fly (Shift: faster), 1..9 and 0 snap to dataset cameras, Space plays/pauses,\n"
                       "T toggles the original and the last style, N steps to the next style, [ and ] move the blend\n"
                       "factor of the panel's second style (--mix; the panel has a slider), P saves a screenshot,\n"
                       "R starts/stops recording the camera path (a transforms.json with a time per frame that\n"
                       "`style4d render --run RUN --path FILE` replays through the 4D run and any style), Esc quits.\n"
                       "With --screenshot it renders one frame through the same renderer without a window.",
                       specs);
    return 0;
  }
  if (args.positionals().size() > 1 || (args.get("run") && !args.positionals().empty()))
    throw UsageError("unexpected argument '" + args.positionals().back() + "'");
  if (!args.positionals().empty()) warn_deprecated("view RUN", "view --run RUN");
  const std::filesystem::path run_dir = args.positionals().empty() ? args.require("run") : args.positionals()[0];
  const std::string time_text = args.get_or("time", "0");
  const double time = parse_number<double>("time", time_text);
  if (!(time >= 0 && time <= 1)) throw UsageError("--time: expected a value in [0, 1], got '" + time_text + "'");
  const std::string camera_text = args.get_or("camera", "0");
  const scene::StyleChoice style = parse_style_choice(args);
  if (auto png = args.get("screenshot")) tools::refuse_run_output(*png, run_dir, "screenshot");
  if (auto dir = args.get("out-dir")) tools::refuse_run_output(*dir, run_dir, "out-dir");
  const uint32_t exit_after = parse_number<uint32_t>("exit-after", args.get_or("exit-after", "0"));
  // Test runs (--exit-after) see full-resolution frames unless they ask for the adaptive scale.
  const std::string budget_text = args.get_or("frame-budget-ms", exit_after ? "0" : "100");
  const double frame_budget_ms = parse_number<double>("frame-budget-ms", budget_text);
  if (!(frame_budget_ms >= 0))
    throw UsageError("--frame-budget-ms: expected 0 (always full resolution) or a time in ms, got '" +
                                budget_text + "'");
  const scene::TrainedRun run = scene::read_trained_run(run_dir);
  const size_t camera = camera_index(camera_text, viewer::dataset_cameras(run.dataset));

  if (args.get("screenshot")) {
    engine::Context ctx;
    const std::filesystem::path png = *args.get("screenshot");
    viewer::capture(ctx, run, {.png = png, .time = time, .camera = camera, .style = style, .storage = parse_storage(args)});
    std::cout << "captured camera " << camera << " (" << viewer::dataset_cameras(run.dataset).at(camera).name
              << ") at t = " << time
              << " into " << png.string() << "\n";
    return 0;
  }
#ifdef S4D_HAVE_VIEWER_WINDOW
  viewer::ViewerOptions options{.style = style,
                                .storage = parse_storage(args),
                                .camera = camera,
                                .time = time,
                                .play = args.flag("play"),
                                .exit_after = exit_after,
                                .out_dir = args.get_or("out-dir", (run_dir / "viewer").string()),
                                .record = args.get_or("record", "")};
  if (args.get("size")) std::tie(options.width, options.height) = parse_size("size", *args.get("size"));
  options.frame_budget_ms = frame_budget_ms;
  const viewer::ViewerSummary summary = viewer::run_viewer(run, options);
  std::cout << "presented " << summary.frames << " frames on " << summary.device << ", mean frame "
            << summary.mean_frame_ms << " ms; rasterized " << summary.rasterized << " at mean scale "
            << summary.mean_scale << ", " << summary.mean_rasterized_ms << " ms each, " << summary.rerendered
            << " again after the instance buffers grew\n";
  return 0;
#else
  throw std::runtime_error("this build has no viewer window (configured with S4D_BUILD_VIEWER=OFF); "
                           "capture headless with --screenshot F.png");
#endif
}

}  // namespace s4d::cli
