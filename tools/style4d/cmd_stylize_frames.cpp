// style4d stylize-frames --in DIR|VIDEO --style-image IMG --out DIR|VIDEO [--stylizer NAME] [--weights DIR]
// [--style-size N] [--strength S] [--seed N]: restyles one camera's frames in time order with a
// frame stylizer (s4d_frame_stylizers).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "args.h"
#include "commands.h"
#include "frame_sequence.h"
#include "s4d/io/image_file.h"
#include "s4d/frame_stylizers/registry.h"
#include "s4d/util/progress.h"

namespace s4d::cli {

int cmd_stylize_frames(const std::vector<std::string>& argv) {
  std::string names;
  for (const std::string& n : frame_stylizers::stylizer_names()) names += (names.empty() ? "" : ", ") + n;
  const std::vector<OptionSpec> specs = {
      {"in", "a folder of PNG frames (sorted by name) or a video (.mp4, .avi, .mov, .mkv)", true, "DIR|VIDEO"},
      {"style-image", "the style image (PNG, JPEG, ...), e.g. assets/styles/builtin.png", true, "IMG", {"style"}},
      {"out", "a folder (one PNG per frame, the input's names) or a .mp4 video (mp4v, lossy)", true, "DIR|VIDEO"},
      {"stylizer", "which stylizer: " + names + " (default patch)", true, "NAME"},
      {"weights", "network stylizers: the folder of their .safetensors weights (docs/stylization.md, \"Network stylizers\")", true,
       "DIR"},
      {"style-size", "network stylizers: the style's shorter side in pixels (default 512; 0 keeps it)", true, "N"},
      {"strength", "0 keeps the content, 1 the full stylization (default 1)", true, "S"},
      {"seed", "seed of the stylizer's random choices (default 0)", true, "N"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("stylize-frames",
                       "--in DIR|VIDEO --style-image IMG --out DIR|VIDEO [--stylizer NAME] [--weights DIR]\n"
                       "    [--style-size N] [--strength S] [--seed N]",
                       "Restyles one camera's frames, in time order, after a style image. The default stylizer\n"
                       "(patch) needs no weights: texture synthesis from the style's patches (Elad & Milanfar\n"
                       "2017), each frame warm-started from the previous result moved by optical flow. The\n"
                       "network stylizers adain, adaattn, mccnet and hgst run on the GPU with the published\n"
                       "weights converted to safetensors; --strength is then their alpha.",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  const std::string in = args.require("in"), style_path = args.require("style-image"), out = args.require("out");
  if (std::filesystem::exists(out) && std::filesystem::equivalent(in, out))
    throw UsageError("--out " + out + " is the input; it would overwrite the frames");
  frame_stylizers::StylizeSettings settings;
  const std::string strength_text = args.get_or("strength", "1");
  try {
    size_t used = 0;
    settings.strength = std::stof(strength_text, &used);
    if (used != strength_text.size()) throw UsageError("trailing characters");
  } catch (const std::exception&) {
    throw UsageError("--strength: expected a number in [0, 1], got '" + strength_text + "'");
  }
  if (!(settings.strength >= 0.0f && settings.strength <= 1.0f))
    throw UsageError("--strength: " + strength_text + " is outside [0, 1]");
  settings.seed = parse_number<uint64_t>("seed", args.get_or("seed", "0"));
  frame_stylizers::NetworkOptions network;
  network.weights = args.get_or("weights", "");
  network.style_size = parse_number<int>("style-size", args.get_or("style-size", "512"));
  if (network.style_size < 0) throw UsageError("--style-size: expected 0 or more pixels");
  const std::string stylizer_name = args.get_or("stylizer", "patch");
  const std::vector<std::string> known = frame_stylizers::stylizer_names();
  if (std::find(known.begin(), known.end(), stylizer_name) == known.end())
    throw UsageError("--stylizer: unknown stylizer '" + stylizer_name + "' (available: " + names + ")");
  const auto stylizer = frame_stylizers::make_stylizer(stylizer_name, network);

  const io::ImageF style = io::read_image_rgb(style_path);
  const FrameSequence input = read_frame_sequence(in);
  const int total = static_cast<int>(input.frames.size());
  util::Progress progress("stylize-frames", static_cast<uint64_t>(total));
  const auto start = std::chrono::steady_clock::now();
  const std::vector<io::ImageF> frames = stylizer->stylize(
      input.frames, style, settings, [&](int done, int) { progress.update(static_cast<uint64_t>(done)); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish();
  write_frame_sequence(out, frames, input.names);
  std::cout << "stylized " << total << " frames (" << frames[0].width << "x" << frames[0].height << ") with "
            << stylizer->name() << " in " << seconds << " s (" << seconds / total << " s per frame) into " << out << "\n";
  return 0;
}

}  // namespace s4d::cli
