#include "s4d/nn/vgg.h"

#include <stdexcept>
#include <string>

#include "s4d/nn/weights.h"

namespace s4d::nn {

uint32_t pooled_size(uint32_t size, int level) {
  for (int l = 1; l < level; ++l) size = (size + 1) / 2;
  return size;
}

VggEncoder::VggEncoder(engine::Context& ctx, const io::SafetensorsFile& file, int levels, const VggWidths& widths)
    : levels_(levels), widths_(widths) {
  if (levels < 1 || levels > 5)
    throw std::invalid_argument("VggEncoder: levels " + std::to_string(levels) + " is not 1..5");
  const auto& w = widths.level;
  auto conv = [&](int index, uint32_t cin, uint32_t cout, int ends_level = 0) {
    steps_.push_back({load_conv(ctx, file, std::to_string(index), cin, cout, 3), ends_level});
  };
  auto pool = [&] { steps_.push_back({}); };
  // nn.Sequential indices: each 3x3 conv sits after its ReflectionPad2d and before its ReLU.
  steps_.push_back({load_conv(ctx, file, "0", 3, 3, 1), 0});
  conv(2, 3, w[0], 1);
  if (levels == 1) return;
  conv(5, w[0], w[0]);
  pool();
  conv(9, w[0], w[1], 2);
  if (levels == 2) return;
  conv(12, w[1], w[1]);
  pool();
  conv(16, w[1], w[2], 3);
  if (levels == 3) return;
  for (const int i : {19, 22, 25}) conv(i, w[2], w[2]);
  pool();
  conv(29, w[2], w[3], 4);
  if (levels == 4) return;
  for (const int i : {32, 35, 38}) conv(i, w[3], w[3]);
  pool();
  conv(42, w[3], w[4], 5);
}

Tensor VggEncoder::encode(engine::Recorder& rec, const Tensor& rgb, int level) const {
  if (level < 1 || level > levels_)
    throw std::invalid_argument("VggEncoder: level " + std::to_string(level) + " is not 1.." + std::to_string(levels_));
  if (rgb.c != 3) throw std::invalid_argument("VggEncoder: expects an RGB image [3, H, W], got " + rgb.shape());
  Tensor x = conv1x1(rec, rgb, steps_.front().conv, false);
  for (size_t i = 1; i < steps_.size(); ++i) {
    const Step& s = steps_[i];
    x = s.conv.name.empty() ? maxpool2(rec, x) : conv3x3(rec, x, s.conv, true);
    if (s.ends_level == level) break;
  }
  return x;
}

std::vector<Tensor> VggEncoder::encode_all(engine::Recorder& rec, const Tensor& rgb) const {
  if (rgb.c != 3) throw std::invalid_argument("VggEncoder: expects an RGB image [3, H, W], got " + rgb.shape());
  std::vector<Tensor> levels;
  levels.reserve(static_cast<size_t>(levels_));  // `x` may point into it
  Tensor y = conv1x1(rec, rgb, steps_.front().conv, false);
  const Tensor* x = &y;
  for (size_t i = 1; i < steps_.size(); ++i) {
    const Step& s = steps_[i];
    Tensor next = s.conv.name.empty() ? maxpool2(rec, *x) : conv3x3(rec, *x, s.conv, true);
    if (s.ends_level != 0) {
      levels.push_back(std::move(next));
      x = &levels.back();
    } else {
      y = std::move(next);
      x = &y;
    }
  }
  return levels;
}

VggDecoder::VggDecoder(engine::Context& ctx, const io::SafetensorsFile& file, const VggWidths& widths) {
  const auto& w = widths.level;
  auto conv = [&](int index, uint32_t cin, uint32_t cout, bool upsample_after = false, bool relu = true) {
    steps_.push_back({load_conv(ctx, file, std::to_string(index), cin, cout, 3), relu, upsample_after, std::to_string(index)});
  };
  conv(1, w[3], w[2], true);
  for (const int i : {5, 8, 11}) conv(i, w[2], w[2]);
  conv(14, w[2], w[1], true);
  conv(18, w[1], w[1]);
  conv(21, w[1], w[0], true);
  conv(25, w[0], w[0]);
  conv(28, w[0], 3, false, false);
}

Tensor VggDecoder::decode(engine::Recorder& rec, const Tensor& features) const {
  const Tensor* x = &features;
  Tensor y;
  for (const Step& s : steps_) {
    y = conv3x3(rec, *x, s.conv, s.relu);
    if (s.upsample_after) y = upsample2(rec, y);
    x = &y;
  }
  return y;
}

std::vector<Tensor> VggEncoder::forward_tape(engine::Recorder& rec, const Tensor& rgb) const {
  if (rgb.c != 3) throw std::invalid_argument("VggEncoder: expects an RGB image [3, H, W], got " + rgb.shape());
  std::vector<Tensor> tape;
  tape.reserve(steps_.size());
  tape.push_back(conv1x1(rec, rgb, steps_.front().conv, false));
  for (size_t i = 1; i < steps_.size(); ++i)
    tape.push_back(steps_[i].conv.name.empty() ? maxpool2(rec, tape.back()) : conv3x3(rec, tape.back(), steps_[i].conv, true));
  return tape;
}

size_t VggEncoder::level_step(int level) const {
  for (size_t i = 0; i < steps_.size(); ++i)
    if (steps_[i].ends_level == level) return i;
  throw std::invalid_argument("VggEncoder: level " + std::to_string(level) + " is not 1.." + std::to_string(levels_));
}

Tensor VggEncoder::backward(engine::Recorder& rec, const std::vector<Tensor>& tape, std::vector<Tensor> level_grads) const {
  if (tape.size() != steps_.size() || level_grads.size() != static_cast<size_t>(levels_))
    throw std::invalid_argument("VggEncoder::backward: " + std::to_string(tape.size()) + " tape entries and " +
                                std::to_string(level_grads.size()) + " level gradients for " + std::to_string(steps_.size()) +
                                " steps and " + std::to_string(levels_) + " levels");
  Tensor g;
  for (size_t i = steps_.size(); i-- > 0;) {
    const Step& s = steps_[i];
    if (s.ends_level != 0 && level_grads[s.ends_level - 1].count() != 0) {
      Tensor& lg = level_grads[s.ends_level - 1];
      g = g.count() == 0 ? std::move(lg) : add(rec, g, lg);
    }
    if (g.count() == 0) continue;
    if (i == 0) {
      g = conv_backward_input(rec, g, s.conv);  // the 1x1 preprocessing, no ReLU
    } else if (s.conv.name.empty()) {
      g = maxpool2_backward(rec, tape[i - 1], g);
    } else {
      relu_backward(rec, g, tape[i]);
      g = conv_backward_input(rec, g, s.conv);
    }
  }
  if (g.count() == 0) throw std::invalid_argument("VggEncoder::backward: no level gradient given");
  return g;
}

std::vector<Tensor> VggDecoder::forward_tape(engine::Recorder& rec, const Tensor& features) const {
  std::vector<Tensor> tape;
  for (const Step& s : steps_) {
    tape.push_back(conv3x3(rec, tape.empty() ? features : tape.back(), s.conv, s.relu));
    if (s.upsample_after) tape.push_back(upsample2(rec, tape.back()));
  }
  return tape;
}

Tensor VggDecoder::backward(engine::Recorder& rec, const Tensor& features, const std::vector<Tensor>& tape,
                            const Tensor& dimage, std::span<ConvGrads> grads) const {
  if (grads.size() != steps_.size())
    throw std::invalid_argument("VggDecoder::backward: " + std::to_string(grads.size()) + " gradient sets for " +
                                std::to_string(steps_.size()) + " convolutions");
  // Tape index of each step's convolution output.
  std::vector<size_t> at;
  for (size_t i = 0, t = 0; i < steps_.size(); ++i, ++t) {
    at.push_back(t);
    if (steps_[i].upsample_after) ++t;
  }
  if (tape.size() != at.back() + 1) throw std::invalid_argument("VggDecoder::backward: the tape is not of this decoder");
  Tensor g = make_tensor(rec.context(), "decoder d image", dimage.c, dimage.h, dimage.w);
  rec.copy(dimage.buffer, g.buffer, dimage.count() * sizeof(float));
  rec.barrier();
  for (size_t i = steps_.size(); i-- > 0;) {
    const Step& s = steps_[i];
    if (s.upsample_after) g = upsample2_backward(rec, g);
    if (s.relu) relu_backward(rec, g, tape[at[i]]);
    const Tensor& input = i == 0 ? features : tape[at[i] - 1];
    conv_backward_weights(rec, input, g, s.conv, grads[i], true);
    g = conv_backward_input(rec, g, s.conv);
  }
  return g;
}

std::vector<std::pair<std::string, const ConvWeights*>> VggDecoder::parameters() const {
  std::vector<std::pair<std::string, const ConvWeights*>> p;
  for (const Step& s : steps_) p.emplace_back(s.prefix, &s.conv);
  return p;
}

}  // namespace s4d::nn
