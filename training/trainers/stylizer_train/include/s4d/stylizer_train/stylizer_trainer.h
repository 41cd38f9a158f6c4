// Trains the MCCNet/HGST decoder and MCC module with the VGG-19 encoder fixed (ALGORITHMS.md 4.5):
// each step a batch of random (content, style) pairs, each image resized to resize x resize (aspect
// not kept, as HGST) and randomly cropped to crop x crop, the loss of s4d/nn/mcc_loss.h and its
// gradients on the GPU, and one Adam step over the decoder and MCC parameters. The result is a
// weights folder the hgst and mccnet stylizers read (decoder, mcc_module and vgg_normalised
// .safetensors); the CCPL heads stay in the checkpoint. An --out folder holding a checkpoint
// (checkpoint.h) continues from it, step for step as if never interrupted; any other non-empty
// folder is refused unless restart.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/nn/mcc_loss.h"

namespace s4d::stylizer_train {

struct StylizerTrainSettings {
  std::filesystem::path content_dir, styles_dir;  // images (PNG, JPEG, ...)
  std::filesystem::path vgg;                      // vgg_normalised.safetensors (fixed)
  std::filesystem::path init;                     // a folder with decoder and mcc_module .safetensors; empty: random
  std::filesystem::path out;                      // the weights folder written (or continued)
  bool restart = false;                           // start over even where out holds a checkpoint or files
  int steps = 160000;
  int batch = 4;  // pairs per step (HGST's); the loss is their mean, TV their sum
  int save_every = 10000;  // the weights are written every this many steps and at the end (HGST's)
  int resize = 512, crop = 256;  // HGST's
  double lr = 1e-4;              // Adam, HGST's, decayed by hgst_learning_rate
  uint64_t seed = 0;            // the initialisation; each step's pairs, crops and noise come from (seed, step)
  std::string losses = "full";  // loss_sets.h
};

// HGST's learning rate at a 1-based step: lr / (1 + 5e-5 floor(step / 2000)) (train_new.py's
// adjust_learning_rate, run every 2000 iterations; about 0.996 lr after 160,000 steps).
double hgst_learning_rate(double lr, int step);

// One step's loss values.
using StepFn = std::function<void(int step, const nn::MccLossValues& loss)>;

// Runs the training to settings.steps and writes settings.out; returns the loss of every step this
// call ran (the terms' means over the batch, the batch's total; on a resumed folder the steps after
// its checkpoint's). Throws std::invalid_argument naming the setting or file that is wrong: a
// non-empty out without a checkpoint, a checkpoint of other --losses, --batch, --crop, --resize,
// --lr or --seed, or already at settings.steps, --init with a checkpoint (each unless restart).
std::vector<nn::MccLossValues> train_stylizer(engine::Context& ctx, const StylizerTrainSettings& settings,
                                              const StepFn& on_step = {});

}  // namespace s4d::stylizer_train
