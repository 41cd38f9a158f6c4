// Network stylizers on the GPU (s4d_nn, ALGORITHMS.md 4.2 and 5): AdaIN, AdaAttN, MCCNet and HGST. Each frame
// is stylized on its own; the style is encoded once per call. Weights come from a folder of
// safetensors files named after the published checkpoints and keeping their PyTorch state-dict
// names (docs/stylization.md, "Network stylizers"); there is no weight-free fallback.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/nn/vgg.h"
#include "s4d/frame_stylizers/stylizer.h"

namespace s4d::frame_stylizers {

struct NetworkOptions {
  std::filesystem::path weights;  // the folder holding the network's .safetensors files
  // The style image is resized so its shorter side has this many pixels (AdaIN's and HGST's 512);
  // 0 keeps its size.
  int style_size = 512;
  engine::Context* context = nullptr;  // the device to run on; null: open one (S4D_DEVICE, S4D_VALIDATION)
};

// "adain", "adaattn", "mccnet", "hgst".
std::vector<std::string> network_stylizer_names();

// The weight files a network stylizer reads from NetworkOptions::weights.
std::vector<std::string> network_weight_files(const std::string& name);

// adain (Huang & Belongie 2017): vgg_normalised + decoder. adaattn (Liu et al. 2021):
// vgg_normalised + net_adaattn_3 + net_transformer + net_decoder, the style centre-cropped to a
// square as AdaAttN's test data loader does. mccnet (Deng et al. 2021) and hgst
// (MCCNet's architecture with HGST's weights): vgg_normalised + decoder + mcc_module, with the
// style also centre-cropped to a square, as HGST's test script does. Frames come out of the decoder
// at 8 ceil(H/8) x 8 ceil(W/8), are resized back to H x W and clamped to [0, 1].
// settings.strength is the networks' alpha (content and style features blended before decoding),
// except that 0 returns the frames unchanged. Throws std::invalid_argument for another name, when
// `weights` is empty or not a folder; std::runtime_error naming the file and tensor when a weight
// is missing, misshapen or not finite. `widths` is for tests. stylize() also throws
// std::invalid_argument when a frame or the style is too large for the device's storage buffers
// (the relu1_1-wide feature maps at full size).
std::unique_ptr<Stylizer> make_network_stylizer(const std::string& name, const NetworkOptions& options,
                                                const nn::VggWidths& widths = {});

}  // namespace s4d::frame_stylizers
