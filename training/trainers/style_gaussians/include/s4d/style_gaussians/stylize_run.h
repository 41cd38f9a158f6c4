// Stages 3 and 4 of Style4D on a trained run, as two calls (stylize_frames, then train_style), so
// that what measures the result (s4d/bench/style_eval.h, which `style4d stylize` and the demo call)
// can do its style-independent part, and time it, before stage 4. Writes RUN/style/NAME/:
//   request.json        the settings and style image the style was started with (a different
//                       request for the same name is refused unless restarted)
//   stylized/           stage 3's frames (stylized_frames.h), reused when the inputs match
//   checkpoint.s4dckpt  stage 4's state; style.s4dstyle the trained style (style_file.h)
//   run/                method "scratch": the 4DGS run trained on the stylized frames
//   eval/               test-view renders in the style
// The measurement adds spiral/, contact_sheet.png and stylize.json.
#pragma once
#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/run/run_lock.h"
#include "s4d/scene/trained_run.h"
#include "s4d/style_gaussians/style_config.h"
#include "s4d/style_gaussians/stylized_frames.h"
#include "s4d/frame_stylizers/stylizer.h"

namespace s4d::style_gaussians {

struct StylizeRequest {
  std::filesystem::path run, style_image;
  std::string name;          // empty: the style image's file stem
  StyleConfig config;
  std::filesystem::path weights;  // network stylizers (adain, mccnet, hgst): the folder of .safetensors
  int style_size = 512;           // network stylizers: the style's shorter side
  bool restart = false;      // discard stage 4's state (and a scratch run); stage-3 frames stay cached
  int spiral_frames = 0;     // 0: the dataset's frame count per camera (at least 2)
  // Method scratch: the retraining's iterations, its schedules scaled as `train --iters` does
  // (run::set_iterations); 0 keeps the run's own schedule.
  uint32_t scratch_iterations = 0;
  // Seconds for the whole: stages 3 and 4 and the measurement (bench::stylize_and_measure fits
  // stage 4 into what is left); 0: the settings' lengths. request.json records it.
  double time_budget = 0;
};

// What stages 3 and 4 leave for the measurement; all but `complete` and `dir` are set only when
// complete.
struct StylizeOutcome {
  bool complete = false;  // false: interrupted, the checkpoint is written
  std::filesystem::path dir;
  scene::TrainedRun run;  // as read before stage 3 (its style list lacks the new style)
  std::string name;
  io::ImageF style_image;
  std::unique_ptr<frame_stylizers::Stylizer> stylizer;
  frame_stylizers::StylizeSettings settings;
  nlohmann::json style_image_key;  // request.json's "style_image"
  StylizedFrames frames;           // stage 3
  nlohmann::json stage4;           // stage 4's seconds, test PSNR / SSIM against the stylized frames, ...
  std::filesystem::path eval_dir;  // stage 4's test-view renders in the style
  double stage3_seconds = 0;       // in this process, loading the run included
  // The run (shared) and the style (one writer) stay locked until the outcome is dropped, so that
  // the measurement writes under the same locks.
  std::optional<run::RunLock> run_lock, style_lock;
};

// Locks the run and the style, checks request.json against the request and runs stage 3 (reusing
// its cached frames); the outcome is not yet complete.
StylizeOutcome stylize_frames(engine::Context& ctx, const StylizeRequest& request);
// Stage 4 on what stylize_frames returned: complete, or interrupted by `stop` (checkpoint written).
// `deadline` > 0: stage 4's training seconds (summed over a stopped style's runs) to end by (style_budget.h; method
// scratch: the retraining's --time-budget).
void train_style(engine::Context& ctx, const StylizeRequest& request, StylizeOutcome& out, const std::atomic<bool>& stop,
                 double deadline = 0);

}  // namespace s4d::style_gaussians
