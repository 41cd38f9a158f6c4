#include "s4d/nn/adaattn_net.h"

#include <cmath>
#include <stdexcept>

#include "s4d/nn/attention.h"
#include "s4d/nn/weights.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

// mean_variance_norm: (x - mu) / sigma per channel, unbiased variance + 1e-5.
Tensor mean_variance_norm(engine::Recorder& rec, const Tensor& x) { return normalise(rec, x, mean_std(rec, x)); }

// The largest h' x w' <= max_sample of the map's aspect.
void sample_grid(uint32_t h, uint32_t w, uint32_t max_sample, uint32_t& out_h, uint32_t& out_w) {
  const double scale = std::sqrt(static_cast<double>(max_sample) / (static_cast<double>(h) * w));
  out_h = std::max(1u, static_cast<uint32_t>(static_cast<double>(h) * scale));
  out_w = std::max(1u, static_cast<uint32_t>(static_cast<double>(w) * scale));
  while (uint64_t{out_h} * out_w > max_sample) (out_h > out_w ? out_h : out_w) -= 1;  // rounding of sqrt
}

}  // namespace

AdaattnModule::AdaattnModule(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix,
                             uint32_t in_planes, uint32_t key_planes)
    : f_(load_conv(ctx, file, prefix + "f", key_planes, key_planes, 1)),
      g_(load_conv(ctx, file, prefix + "g", key_planes, key_planes, 1)),
      h_(load_conv(ctx, file, prefix + "h", in_planes, in_planes, 1)) {}

StyleCode AdaattnModule::style(engine::Recorder& rec, const Tensor& features, const Tensor& key,
                               uint32_t max_sample) const {
  StyleCode code;
  if (features.plane() <= max_sample) {
    code.push_back(conv1x1(rec, key, g_, false));
    code.push_back(conv1x1(rec, features, h_, false));
    return code;
  }
  uint32_t h = 0, w = 0;
  sample_grid(features.h, features.w, max_sample, h, w);
  code.push_back(conv1x1(rec, resize_nearest(rec, key, h, w), g_, false));
  code.push_back(conv1x1(rec, resize_nearest(rec, features, h, w), h_, false));
  return code;
}

Tensor AdaattnModule::apply(engine::Recorder& rec, const Tensor& content, const Tensor& content_key,
                            const Tensor& style_k, const Tensor& style_v) const {
  return attention(rec, conv1x1(rec, content_key, f_, false), style_k, style_v, mean_variance_norm(rec, content));
}

Tensor adaattn_key(engine::Recorder& rec, const std::vector<Tensor>& levels, int last) {
  const Tensor& top = levels.at(static_cast<size_t>(last));
  std::vector<Tensor> parts;
  for (int i = 0; i < last; ++i)
    parts.push_back(mean_variance_norm(rec, resize_nearest(rec, levels[static_cast<size_t>(i)], top.h, top.w)));
  parts.push_back(mean_variance_norm(rec, top));
  std::vector<const Tensor*> views;
  for (const Tensor& t : parts) views.push_back(&t);
  return concat_channels(rec, views);
}

AdaattnNet::AdaattnNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& adaattn_3,
                       const io::SafetensorsFile& transformer, const io::SafetensorsFile& decoder,
                       const VggWidths& widths, uint32_t max_sample)
    : encoder_(ctx, vgg, 5, widths),
      attn_3_(ctx, adaattn_3, "", widths.level[2], widths.level[0] + widths.level[1] + widths.level[2]),
      attn_4_(ctx, transformer, "attn_adain_4_1.", widths.level[3],
              widths.level[0] + widths.level[1] + widths.level[2] + widths.level[3]),
      attn_5_(ctx, transformer, "attn_adain_5_1.", widths.level[4],
              widths.level[0] + widths.level[1] + widths.level[2] + widths.level[3] + widths.level[4]),
      merge_conv_(load_conv(ctx, transformer, "merge_conv", widths.level[3], widths.level[3], 3)),
      max_sample_(max_sample) {
  const auto& w = widths.level;
  if (w[3] != w[4])
    throw std::invalid_argument("AdaattnNet: relu4_1 and relu5_1 widths differ (" + std::to_string(w[3]) + ", " +
                                std::to_string(w[4]) + ")");
  if (max_sample == 0 || max_sample > S4D_NN_MAX_LOOP)
    throw std::invalid_argument("AdaattnNet: max_sample " + std::to_string(max_sample) + " is not 1.." +
                                std::to_string(S4D_NN_MAX_LOOP));
  // Decoder(skip_connection_3=True): nn.Sequential indices of each Conv2d (after its ReflectionPad2d).
  const auto conv = [&](const char* name, uint32_t cin, uint32_t cout) {
    decoder_.push_back(load_conv(ctx, decoder, name, cin, cout, 3));
  };
  conv("decoder_layer_1.1", w[3], w[2]);
  conv("decoder_layer_2.1", 2 * w[2], w[2]);
  conv("decoder_layer_2.4", w[2], w[2]);
  conv("decoder_layer_2.7", w[2], w[2]);
  conv("decoder_layer_2.10", w[2], w[1]);
  conv("decoder_layer_2.14", w[1], w[1]);
  conv("decoder_layer_2.17", w[1], w[0]);
  conv("decoder_layer_2.21", w[0], w[0]);
  conv("decoder_layer_2.24", w[0], 3);
}

StyleCode AdaattnNet::style(engine::Recorder& rec, const Tensor& style) const {
  const std::vector<Tensor> s = encoder_.encode_all(rec, style);
  StyleCode code;
  const AdaattnModule* modules[] = {&attn_3_, &attn_4_, &attn_5_};
  for (int level = 2; level <= 4; ++level)
    for (Tensor& t : modules[level - 2]->style(rec, s[static_cast<size_t>(level)], adaattn_key(rec, s, level),
                                                max_sample_))
      code.push_back(std::move(t));
  return code;
}

Tensor AdaattnNet::stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const {
  if (style.size() != 6)
    throw std::invalid_argument("AdaattnNet: the style code holds " + std::to_string(style.size()) + " tensors, not 6");
  const std::vector<Tensor> c = encoder_.encode_all(rec, content);
  const auto module = [&](const AdaattnModule& m, int level) {
    const Tensor& features = c[static_cast<size_t>(level)];
    const size_t k = 2 * static_cast<size_t>(level - 2);
    Tensor out = m.apply(rec, features, adaattn_key(rec, c, level), style[k], style[k + 1]);
    return alpha == 1.0f ? std::move(out) : blend(rec, out, features, alpha);
  };
  const Tensor skip = module(attn_3_, 2);
  const Tensor a4 = module(attn_4_, 3), a5 = module(attn_5_, 4);
  // Transformer: merge_conv(pad(attn_4_1 + upsample(attn_5_1))). relu5_1 is ceil(h4 / 2) high, so
  // for odd relu4_1 sizes (where PyTorch's sum fails) the nearest resize drops the last row/column.
  const Tensor cs = conv3x3(rec, add(rec, a4, resize_nearest(rec, a5, a4.h, a4.w)), merge_conv_, false);
  // decoder_layer_1, then torch.cat with the relu3_1 module's output (resized likewise when relu3_1
  // is not exactly twice relu4_1's size), then decoder_layer_2 (upsampling after its 4th and 6th convolutions).
  const Tensor up = upsample2(rec, conv3x3(rec, cs, decoder_[0], true));
  const Tensor skip_sized = resize_nearest(rec, skip, up.h, up.w);  // a copy when the sizes agree
  const Tensor* parts[] = {&up, &skip_sized};
  Tensor x = concat_channels(rec, parts);
  for (size_t i = 1; i < decoder_.size(); ++i) {
    const bool last = i + 1 == decoder_.size();
    x = conv3x3(rec, x, decoder_[i], !last);
    if (i == 4 || i == 6) x = upsample2(rec, x);
  }
  return x;
}

}  // namespace s4d::nn
