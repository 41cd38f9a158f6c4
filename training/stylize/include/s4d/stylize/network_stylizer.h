// Network stylizers on the GPU (s4d_nn, ALGORITHMS.md 4.2 and 5): AdaIN. Each frame is stylized on
// its own; the style is encoded once per call. Weights come from a folder of safetensors files
// named after the published checkpoints and keeping their PyTorch state-dict names (README,
// "Network stylizers"); there is no weight-free fallback.
#pragma once
#include <filesystem>
#include <memory>

#include "s4d/engine/context.h"
#include "s4d/nn/adain_net.h"
#include "s4d/nn/vgg.h"
#include "s4d/stylize/stylizer.h"

namespace s4d::stylize {

struct NetworkOptions {
  std::filesystem::path weights;  // the folder holding the network's .safetensors files
  // The style image is resized so its shorter side has this many pixels (AdaIN's and HGST's 512);
  // 0 keeps its size.
  int style_size = 512;
  engine::Context* context = nullptr;  // the device to run on; null: open one (S4D_DEVICE, S4D_VALIDATION)
};

// AdaIN (Huang & Belongie 2017): reads <weights>/vgg_normalised.safetensors (AdaIN's
// vgg_normalised.pth) and <weights>/decoder.safetensors (decoder.pth). Frames come out of the
// decoder at 8 ceil(H/8) x 8 ceil(W/8) and are resized back to H x W, clamped to [0, 1].
// settings.strength is AdaIN's alpha (content and style features blended before decoding), except
// that 0 returns the frames unchanged.
class AdainStylizer final : public Stylizer {
 public:
  // Throws std::invalid_argument when `weights` is not a folder, std::runtime_error naming the file
  // and tensor when a weight is missing, misshapen or not finite. `widths` is for tests.
  explicit AdainStylizer(const NetworkOptions& options, const nn::VggWidths& widths = {});
  ~AdainStylizer() override;
  std::string name() const override { return "adain"; }
  // Also throws std::invalid_argument when a frame or the style is too large for the device's
  // storage buffers (the 64-channel feature maps at full size).
  std::vector<io::ImageF> stylize(const std::vector<io::ImageF>& frames, const io::ImageF& style,
                                  const StylizeSettings& settings, const FrameProgressFn& progress = {}) const override;

 private:
  std::unique_ptr<engine::Context> owned_context_;
  engine::Context* ctx_;
  int style_size_;
  uint32_t widest_;  // channels of the largest full-size feature map
  std::unique_ptr<nn::AdainNet> net_;
};

}  // namespace s4d::stylize
