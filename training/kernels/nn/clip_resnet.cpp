#include "s4d/nn/clip_resnet.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/nn/attention.h"
#include "s4d/nn/weights.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

constexpr uint32_t kHeadWidth = 64;  // CLIP: vision_heads = width * 32 // 64

uint32_t stored_width(const io::SafetensorsFile& file) {
  const std::vector<int64_t>& s = file.shape("visual.conv3.weight");
  if (s.size() != 4 || s[0] < 2 || s[0] % 2 != 0 || s[0] > 4096)
    throw std::runtime_error(file.path().string() + ": visual.conv3.weight has shape " + io::shape_text(s) +
                             ", not CLIP's [width, width / 2, 3, 3]");
  return static_cast<uint32_t>(s[0]);
}

uint32_t block_count(const io::SafetensorsFile& file, int layer) {
  uint32_t n = 0;
  while (file.contains("visual.layer" + std::to_string(layer) + "." + std::to_string(n) + ".conv1.weight")) ++n;
  if (n == 0) throw std::runtime_error(file.path().string() + ": holds no visual.layer" + std::to_string(layer) + ".0.conv1.weight");
  return n;
}

}  // namespace

ClipResnet::ClipResnet(engine::Context& ctx, const io::SafetensorsFile& file) : ctx_(ctx), width_(stored_width(file)) {
  const uint32_t w = width_, embed = 32 * w;
  heads_ = embed / kHeadWidth;
  stem_[0] = load_conv_bn(ctx, file, "visual.conv1", "visual.bn1", 3, w / 2, 3);
  stem_[1] = load_conv_bn(ctx, file, "visual.conv2", "visual.bn2", w / 2, w / 2, 3);
  stem_[2] = load_conv_bn(ctx, file, "visual.conv3", "visual.bn3", w / 2, w, 3);
  uint32_t cin = w;
  for (int l = 0; l < 4; ++l) {
    blocks_[l] = block_count(file, l + 1);
    const uint32_t planes = w << l;
    layers_[l] = load_bottleneck_layer(ctx, file, "visual.layer" + std::to_string(l + 1), cin, planes, blocks_[l], l == 0 ? 1 : 2);
    cin = 4 * planes;
  }
  const std::vector<int64_t>& c_proj = file.shape("visual.attnpool.c_proj.weight");
  if (c_proj.size() != 2 || c_proj[0] <= 0 || c_proj[0] > int64_t{S4D_NN_MAX_LOOP})
    throw std::runtime_error(file.path().string() + ": visual.attnpool.c_proj.weight has shape " + io::shape_text(c_proj) +
                             ", not [output_dim, " + std::to_string(embed) + "]");
  // (s q) . k = s (q . k): multi_head_attention_forward's scale 1 / sqrt(64) folded into q_proj,
  // bias included (exact: a power of two).
  std::vector<float> q = file.read("visual.attnpool.q_proj.weight", {embed, embed});
  std::vector<float> q_bias = file.read("visual.attnpool.q_proj.bias", {embed});
  const float scale = 1.0f / std::sqrt(float(kHeadWidth));
  for (float& v : q) v *= scale;
  for (float& v : q_bias) v *= scale;
  q_proj_ = upload_conv(ctx, file.path().filename().string() + " visual.attnpool.q_proj", embed, embed, 1, q, q_bias);
  k_proj_ = load_linear(ctx, file, "visual.attnpool.k_proj", embed, embed);
  v_proj_ = load_linear(ctx, file, "visual.attnpool.v_proj", embed, embed);
  c_proj_ = load_linear(ctx, file, "visual.attnpool.c_proj", embed, static_cast<uint32_t>(c_proj[0]));
}

std::vector<float> ClipResnet::features(const Tensor& image) const {
  if (image.c != 3 || image.h < kMinSize || image.w < kMinSize)
    throw std::invalid_argument("clip resnet: needs an RGB image of at least " + std::to_string(kMinSize) + "x" +
                                std::to_string(kMinSize) + " pixels, got " + image.shape());
  engine::Recorder rec(ctx_, "clip resnet");
  Tensor x = conv_strided(rec, image, stem_[0], 2, 1, true);
  x = conv3x3_zero_pad(rec, x, stem_[1], true);
  x = avgpool2(rec, conv3x3_zero_pad(rec, x, stem_[2], true));
  for (const std::vector<Bottleneck>& layer : layers_)
    for (const Bottleneck& b : layer) x = run_bottleneck(rec, x, b, BottleneckStride::avgpool);
  if (x.plane() < 2)
    throw std::invalid_argument("clip resnet: a " + image.shape() + " image leaves layer4 a single position " + x.shape() +
                                "; the attention pooling's mean needs 2");
  const Tensor mean = global_average(rec, x);
  const Tensor tokens = vit_embed(rec, x, mean);  // [E, 1, 1 + h w]: the mean, then the positions
  const Tensor heads = multi_head_attention(rec, conv1x1(rec, mean, q_proj_, false), conv1x1(rec, tokens, k_proj_, false),
                                            conv1x1(rec, tokens, v_proj_, false), heads_);
  const Tensor out = conv1x1(rec, heads, c_proj_, false);
  ctx_.run(std::move(rec));
  return download(ctx_, out);
}

}  // namespace s4d::nn
