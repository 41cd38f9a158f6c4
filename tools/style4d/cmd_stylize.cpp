// style4d stylize --run RUN --style-image IMG [--style NAME] [--stylizer NAME] [--method full|colors|scratch]
// ...: stages 3 and 4 of Style4D on a trained run (s4d/style_gaussians/stylize_run.h), then the
// measurement of the result (s4d/bench/style_eval.h). SIGINT or SIGTERM writes a
// checkpoint and exits with 130; the same command continues it.
#include <atomic>
#include <csignal>
#include <iostream>
#include <optional>
#include <sstream>

#include "args.h"
#include "commands.h"
#include "s4d/bench/style_eval.h"
#include "s4d/style_gaussians/stylize_run.h"
#include "s4d/frame_stylizers/registry.h"

namespace s4d::cli {

namespace {

std::atomic<bool> g_stop{false};

extern "C" void request_stylize_stop(int) { g_stop.store(true); }

float parse_float(const std::string& option, const std::string& text) {
  try {
    size_t used = 0;
    const float v = std::stof(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw UsageError("--" + option + ": expected a number, got '" + text + "'");
}

// Method scratch retrains 4DGS with the run's settings: stage 4's options would do nothing there.
void refuse_stage4_options(const Args& args) {
  for (const char* option : {"style-setting", "mlp-iters", "batch", "checkpoint-every", "tv-weight", "mlp-lr", "mlp-lr-final",
                             "depth-input", "depth-scale", "mlp-init", "region"})
    if (args.get(option))
      throw UsageError(std::string("--") + option + ": a stage-4 option; method scratch retrains 4DGS with the "
                                  "run's settings (its length: --iters)");
  for (const char* flag : {"input-sigmoid", "freeze-colors"})
    if (args.flag(flag))
      throw UsageError(std::string("--") + flag + ": a stage-4 option; method scratch retrains 4DGS with the "
                                  "run's settings (its length: --iters)");
}

style_gaussians::StyleConfig config_from_args(const Args& args) {
  style_gaussians::StyleConfig c = style_gaussians::style_setting(args.get_or("style-setting", "tuned"));
  if (auto v = args.get("method")) c.method = style_gaussians::method_setting(*v);
  if (c.method == run::StyleMethod::scratch) refuse_stage4_options(args);
  if (auto v = args.get("stylizer")) c.stylizer = *v;
  if (auto v = args.get("strength")) c.strength = parse_float("strength", *v);
  if (auto v = args.get("iters"); v && c.method != run::StyleMethod::scratch)
    style_gaussians::set_iterations(c, parse_number<uint32_t>("iters", *v));
  if (auto v = args.get("mlp-iters")) c.mlp_iterations = parse_number<uint32_t>("mlp-iters", *v);
  if (auto v = args.get("batch")) c.batch = parse_number<uint32_t>("batch", *v);
  if (auto v = args.get("seed")) c.seed = parse_number<uint32_t>("seed", *v);
  if (auto v = args.get("checkpoint-every")) c.checkpoint_every = parse_number<uint32_t>("checkpoint-every", *v);
  if (auto v = args.get("tv-weight")) c.tv_weight = parse_float("tv-weight", *v);
  if (auto v = args.get("mlp-lr")) c.mlp_lr = parse_float("mlp-lr", *v);
  if (auto v = args.get("mlp-lr-final")) c.mlp_lr_final = parse_float("mlp-lr-final", *v);
  if (auto v = args.get("depth-input")) {
    const std::optional<run::DepthInput> input = run::parse_depth_input(*v);
    if (!input) throw UsageError("--depth-input: expected ndc or relative, got '" + *v + "'");
    c.depth_input = *input;
  }
  if (auto v = args.get("depth-scale")) c.depth_scale = parse_float("depth-scale", *v);
  if (auto v = args.get("mlp-init")) c.mlp_init = *v;
  if (auto v = args.get("region")) {
    std::istringstream in(*v);
    std::string item;
    while (std::getline(in, item, ',')) c.region.push_back(parse_float("region", item));
    if (c.region.size() != 6) throw UsageError("--region: expected x0,y0,z0,x1,y1,z1 (six numbers), got '" + *v + "'");
  }
  c.input_sigmoid = args.flag("input-sigmoid");
  c.train_colors = !args.flag("freeze-colors");
  style_gaussians::validate(c);
  return c;
}

}  // namespace

int cmd_stylize(const std::vector<std::string>& argv) {
  std::string names;
  for (const std::string& n : frame_stylizers::stylizer_names()) names += (names.empty() ? "" : ", ") + n;
  const std::vector<OptionSpec> specs = {
      group("what to stylize"),
      {"run", "a trained run (style4d train)", true, "RUN"},
      {"style-image", "the style image, e.g. assets/styles/builtin.png", true, "IMG"},
      {"style", "the style's name in RUN/style/, as render, view and bench name it (default: the image's file\n"
                "                        name without extension); --style IMG without --style-image is the old spelling\n"
                "                        of --style-image IMG", true, "NAME"},
      {"name", "old spelling of --style NAME", true, "NAME"},
      {"restart", "discard stage 4's state of this style and train again (stage-3 frames stay cached)", false, ""},
      group("stage 3: the 2D stylizer"),
      {"stylizer", "stage 3's 2D stylizer: " + names + " (default patch)", true, "NAME"},
      {"weights", "network stylizers (adain, adaattn, mccnet, hgst): the folder of their .safetensors files", true, "DIR"},
      {"style-size", "network stylizers: the style image's shorter side in pixels (default 512)", true, "N"},
      {"strength", "stage 3: 0 keeps the content, 1 the full stylization (default 1)", true, "S"},
      group("stage 4: the Style Gaussians"),
      {"method", "full (per-Gaussian MLPs, the paper), colors (no MLPs), scratch (4DGS retrained on the "
                 "stylized frames) (default full)", true, "M"},
      {"style-setting", "stage 4's defaults: tuned (ours) or paper (Style4D's: MLPs from the start, their learning "
                        "rate 1e-4 -> 1e-5, 2 views a step); the options below override them (default tuned)", true, "S"},
      {"iters", "stage 4 iterations (default 1500); method scratch: the retraining's iterations, the run's "
                "schedules scaled to fit as `train --iters` does (default: the run's own)", true, "N"},
      {"mlp-iters", "method full: the last N iterations also train the MLPs (default: tuned 300, paper all; the "
                    "others train colours and opacities only, on the plain rasterizer)", true, "N"},
      {"batch", "stage 4 training views per step, gradients summed (default: tuned 1, paper 2)", true, "N"},
      {"seed", "seed of the stylizer and of stage 4 (default 0)", true, "N"},
      {"checkpoint-every", "stage 4 iterations between checkpoints (default 500)", true, "N"},
      {"tv-weight", "weight of the image TV term (default 0.05)", true, "W"},
      {"mlp-lr", "learning rate of the style MLPs (default: tuned 2.5e-4, paper 1e-4)", true, "LR"},
      {"mlp-lr-final", "the MLPs' rate decays log-linearly from --mlp-lr to this over their steps; 0 keeps it "
                       "(default: tuned 0, paper 1e-5)", true, "LR"},
      {"depth-input", "how the MLP reads the ray-hit depth: relative (t* - centre depth) or ndc (default relative)", true, "D"},
      {"depth-scale", "relative depth scale (default 0: 1 / (3 x median Gaussian scale))", true, "S"},
      {"mlp-init", "identity (SuperGaussians' with a zero last layer: adds nothing at first) or uniform (SuperGaussians) "
                   "(default: tuned identity, paper uniform)", true, "I"},
      {"input-sigmoid", "squash the MLP inputs with a sigmoid (SuperGaussians)", false, ""},
      {"region", "stylize only the Gaussians whose centre lies in this world box (min then max corner); "
                 "the rest keep the original look", true, "x0,y0,z0,x1,y1,z1"},
      {"freeze-colors", "method full: train only the MLPs, keep the run's colours and opacities", false, ""},
      {"time-budget", "fit the whole command to this much time, e.g. 90s, 5m: stage 4's length is planned from\n"
                      "                        its measured step times, once stage 3 and the measurement's first half are timed", true, "DURATION"},
      group("measurement"),
      {"spiral-frames", "frames of the spiral render that measures consistency (default: the clip's frame count)", true, "N"},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("stylize", "--run RUN --style-image IMG [--style NAME] [--stylizer NAME] [--method full|colors|scratch] [--iters N] ...",
                       "Stages 3 and 4 of Style4D: stylizes every training camera's frames with a 2D stylizer,\n"
                       "then trains the run's Style Gaussians (geometry frozen; per Gaussian a colour and opacity\n"
                       "change and a tiny MLP on time and ray-hit depth) against them with L1 + TV. Results in\n"
                       "RUN/style/NAME/ (stylize.json, style.s4dstyle, contact_sheet.png, spiral renders).\n"
                       "Ctrl-C writes a checkpoint; the same command continues it.",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  style_gaussians::StylizeRequest req;
  req.run = args.require("run");
  if (args.get("style-image")) {
    req.style_image = *args.get("style-image");
    if (args.get("style") && args.get("name")) throw UsageError("--name is the old spelling of --style NAME; give one");
    if (args.get("name")) warn_deprecated("--name NAME", "--style NAME");
    req.name = args.get("style") ? *args.get("style") : args.get_or("name", "");
  } else {  // the old grammar: --style IMG [--name NAME]
    if (!args.get("style")) throw UsageError("missing required option --style-image (see --help)");
    warn_deprecated("--style IMG", "--style-image IMG");
    if (args.get("name")) warn_deprecated("--name NAME", "--style NAME");
    req.style_image = *args.get("style");
    req.name = args.get_or("name", "");
  }
  try {
    req.config = config_from_args(args);
  } catch (const std::invalid_argument& e) {  // a setting, method or value the options name wrongly
    throw UsageError(e.what());
  }
  if (auto v = args.get("iters"); v && req.config.method == run::StyleMethod::scratch)
    req.scratch_iterations = parse_number<uint32_t>("iters", *v);
  req.restart = args.flag("restart");
  if (auto v = args.get("time-budget")) req.time_budget = parse_duration("time-budget", *v);
  if (auto v = args.get("weights")) req.weights = *v;
  req.style_size = parse_number<int>("style-size", args.get_or("style-size", "512"));
  req.spiral_frames = parse_number<int>("spiral-frames", args.get_or("spiral-frames", "0"));
  engine::Context ctx;
  std::signal(SIGINT, request_stylize_stop);
  std::signal(SIGTERM, request_stylize_stop);
  const bench::StyleMeasured m = bench::stylize_and_measure(ctx, req, g_stop);
  if (!m.outcome.complete) return 130;
  const style_gaussians::StylizeOutcome& out = m.outcome;
  const nlohmann::json& s = m.summary;
  const nlohmann::json& exact = s.at("warp_error").at("spiral_exact_flow");
  std::cout << "style " << s.at("style").get<std::string>() << " (" << s.at("method").get<std::string>() << ") in "
            << out.dir.string() << "\n"
            << "  test PSNR against the stylized frames  " << s.at("stage4").at("test_psnr_vs_stylized").get<double>() << " dB\n"
            << "  spiral warp error, exact flow: the style's render " << exact.at("styled_render").get<double>()
            << ", the 2D stylizer on the spiral " << exact.at("stylized_2d").get<double>() << "\n"
            << "  spiral warp error, DIS flow:   the style's render " << s.at("warp_error").at("spiral_styled_render").get<double>()
            << ", the 2D stylizer on the spiral " << s.at("warp_error").at("spiral_stylized_2d").get<double>() << "\n"
            << "  warp error, 2D stylized frames (training cameras) " << s.at("warp_error").at("stylized_frames_2d").get<double>() << "\n"
            << "  seconds                                 " << s.at("seconds").get<double>();
  if (req.time_budget > 0) std::cout << " of a " << req.time_budget << " s budget";
  std::cout << "\n";
  return 0;
}

}  // namespace s4d::cli
