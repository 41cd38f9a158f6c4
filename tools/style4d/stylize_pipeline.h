// Stages 3 and 4 of Style4D on a trained run, and what shows their result: `style4d stylize` and
// the demo call this. Writes RUN/style/NAME/:
//   request.json        the settings and style image the style was started with (a different
//                       request for the same name is refused unless restarted)
//   stylized/           stage 3's frames (stylized_frames.h), reused when the inputs match
//   checkpoint.s4dckpt  stage 4's state; style.s4dstyle the trained style (style_file.h)
//   run/                method "scratch": the 4DGS run trained on the stylized frames
//   eval/               test-view renders in the style
//   spiral/original, spiral/styled   spiral-path renders (frames.json) of the run and of the style
//   contact_sheet.png   content, stage-3 frames and style renders of the test camera over time
//   stylize.json        results (keys in docs/stylization.md)
#pragma once
#include <atomic>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/engine/context.h"
#include "s4d/style/style_config.h"

namespace s4d::cli {

struct StylizeRequest {
  std::filesystem::path run, style_image;
  std::string name;          // empty: the style image's file stem
  style::StyleConfig config;
  std::filesystem::path weights;  // network stylizers (adain, mccnet, hgst): the folder of .safetensors
  int style_size = 512;           // network stylizers: the style's shorter side
  bool restart = false;      // discard stage 4's state (and a scratch run); stage-3 frames stay cached
  int spiral_frames = 0;     // 0: the dataset's frame count per camera (at least 2)
};

struct StylizeOutcome {
  bool complete = false;  // false: interrupted, the checkpoint is written
  std::filesystem::path dir;
  nlohmann::json summary;  // what stylize.json holds
};

StylizeOutcome stylize_run(engine::Context& ctx, const StylizeRequest& request, const std::atomic<bool>& stop);

}  // namespace s4d::cli
