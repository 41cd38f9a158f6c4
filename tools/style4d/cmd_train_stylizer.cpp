// style4d train-stylizer --content DIR --styles DIR --vgg FILE --out DIR [--init DIR] [--steps N]
// [--batch N] [--save-every N] [--resize N] [--crop N] [--lr X] [--seed N] [--losses mccnet|ccpl|content|lcl|full]
// [--restart]: trains the MCCNet/HGST decoder and MCC module with the VGG-19 encoder fixed
// (s4d_stylizer_train) and writes a weights folder for --stylizer hgst; an --out with a checkpoint
// continues.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>

#include "args.h"
#include "commands.h"
#include "s4d/stylizer_train/loss_sets.h"
#include "s4d/stylizer_train/stylizer_trainer.h"

namespace s4d::cli {

int cmd_train_stylizer(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"content", "a folder of content images (PNG, JPEG)", true, "DIR"},
      {"styles", "a folder of style images (PNG, JPEG)", true, "DIR"},
      {"vgg", "vgg_normalised.safetensors, the fixed encoder (docs/stylization.md, \"Network stylizers\")", true, "FILE"},
      {"out", "the weights folder written: decoder, mcc_module, vgg_normalised and checkpoint .safetensors", true, "DIR"},
      {"init", "a folder with decoder.safetensors and mcc_module.safetensors to start from (default: random)", true, "DIR"},
      {"steps", "Adam steps in all, a continued checkpoint's included (default 160000, HGST's)", true, "N"},
      {"batch", "content/style pairs per Adam step (default 4, HGST's)", true, "N"},
      {"save-every", "write the weights and checkpoint every N steps and at the end (default 10000, HGST's)", true, "N"},
      {"resize", "images are resized to N x N first (default 512)", true, "N"},
      {"crop", "then randomly cropped to N x N, a multiple of 8, at least 40 (default 256)", true, "N"},
      {"lr", "Adam's learning rate (default 1e-4)", true, "X"},
      {"seed", "seed of the initialisation, the pairs and the crops (default 0)", true, "N"},
      {"losses", "the loss terms and levels: full (default, HGST's), lcl, content, ccpl or mccnet (docs/stylization.md)", true,
       "mccnet|ccpl|content|lcl|full"},
      {"restart", "start over where --out already holds files or a checkpoint (default: continue a checkpoint)", false, ""},
  };
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("train-stylizer",
                       "--content DIR --styles DIR --vgg FILE --out DIR [--init DIR] [--steps N] [--batch N]\n"
                       "    [--save-every N] [--resize N] [--crop N] [--lr X] [--seed N] [--losses mccnet|ccpl|content|lcl|full]\n"
                       "    [--restart]",
                       "Trains the MCCNet/HGST decoder and MCC module on the GPU, the VGG-19 encoder fixed, with\n"
                       "HGST's loss (--losses full: content, style, identity 1 and 2, noise, TV, self-similarity\n"
                       "and the jittered CCPL \"LCL\"; docs/stylization.md, \"Training HGST: status\"). --out is then a\n"
                       "--weights folder for the hgst and mccnet stylizers. An --out holding checkpoint.safetensors\n"
                       "continues to --steps (the same --losses only); any other non-empty --out needs --restart.",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  stylizer_train::StylizerTrainSettings s;
  s.content_dir = args.require("content");
  s.styles_dir = args.require("styles");
  s.vgg = args.require("vgg");
  s.out = args.require("out");
  s.init = args.get_or("init", "");
  s.steps = parse_number<int>("steps", args.get_or("steps", "160000"));
  s.batch = parse_number<int>("batch", args.get_or("batch", "4"));
  s.save_every = parse_number<int>("save-every", args.get_or("save-every", "10000"));
  s.resize = parse_number<int>("resize", args.get_or("resize", "512"));
  s.crop = parse_number<int>("crop", args.get_or("crop", "256"));
  const std::string lr = args.get_or("lr", "1e-4");
  try {
    size_t used = 0;
    s.lr = std::stod(lr, &used);
    if (used != lr.size()) throw UsageError("trailing characters");
  } catch (const std::exception&) {
    throw UsageError("--lr: expected a number, got '" + lr + "'");
  }
  s.seed = parse_number<uint64_t>("seed", args.get_or("seed", "0"));
  s.losses = args.get_or("losses", "full");
  stylizer_train::loss_set(s.losses);  // refuses an unknown name before the GPU starts
  s.restart = args.flag("restart");
  engine::Context ctx;
  const auto start = std::chrono::steady_clock::now();
  const auto losses = stylizer_train::train_stylizer(ctx, s, [&](int step, const nn::MccLossValues& l) {
    if (step == 1 || step % 10 == 0 || step == s.steps)
      std::printf("step %d loss %.6g (content %.4g style %.4g identity1 %.4g identity2 %.4g noise %.4g tv %.4g selfsim %.4g ccpl %.4g)\n",
                  step, l.total, l.content, l.style, l.identity1, l.identity2, l.noise, l.tv, l.selfsim, l.ccpl);
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "trained " << losses.size() << " steps in " << seconds << " s; weights in " << s.out.string() << "\n";
  return 0;
}

}  // namespace s4d::cli
