#include "s4d/nn/layers.h"

#include <stdexcept>

#include "s4d/engine/buffer_from.h"
#include "s4d/primitives/shader_pipeline.h"
#include "layer_checks.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;
using detail::check_loop;
using detail::fail;

void check_stats_input(const std::string& layer, const Tensor& x) {
  if (x.plane() < 2) fail(layer, "needs at least 2 values per channel, got " + x.shape());
  check_loop(layer, (x.plane() + S4D_NN_STATS_WG - 1) / S4D_NN_STATS_WG, x.shape());
}

void check_stats(const std::string& layer, const Tensor& x, const engine::Buffer& stats) {
  if (stats.size() < 2 * size_t{x.c} * sizeof(float))
    fail(layer, "statistics '" + stats.name() + "' hold fewer than 2 x " + std::to_string(x.c) + " values");
}

Tensor conv(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, uint32_t flags, Tensor* into,
            shaders::Id id) {
  const std::string layer = "conv " + w.name;
  if (x.c != w.cin) fail(layer, "expects " + std::to_string(w.cin) + " input channels, got " + x.shape());
  if (id == shaders::Id::nn_conv3x3 && (x.h < 2 || x.w < 2))
    fail(layer, "reflection padding needs H, W >= 2, got " + x.shape());
  check_loop(layer, w.cin, "input channels " + std::to_string(w.cin));
  Tensor out;
  if (into == nullptr) out = make_tensor(rec.context(), w.name, w.cout, x.h, x.w);
  Tensor& y = into != nullptr ? *into : out;
  if (y.c != w.cout || y.h != x.h || y.w != x.w) fail(layer, "output " + y.shape() + " does not match");
  // One-row tensors (a transformer's tokens) take the variant with one-row workgroups.
  const bool rows = id == shaders::Id::nn_conv1x1 && x.h == 1;
  if (rows) id = shaders::Id::nn_conv1x1_rows;
  const gpu::NnConvParams p{.cin = w.cin,
                            .cout = w.cout,
                            .height = x.h,
                            .width = x.w,
                            .tiles_x = ceil_div(x.w, (rows ? S4D_NN_CONV_ROWS_WG_X : S4D_NN_CONV_WG_X) * S4D_NN_CONV_PIX),
                            .tiles_y = rows ? 1u : ceil_div(x.h, S4D_NN_CONV_WG_Y),
                            .flags = flags,
                            ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), id),
               {S4D_BIND(CONV_IN, x.buffer), S4D_BIND(CONV_WEIGHT, w.weight), S4D_BIND(CONV_BIAS, w.bias),
                S4D_BIND(CONV_OUT, y.buffer)},
               p, p.tiles_x * p.tiles_y * ceil_div(w.cout, S4D_NN_CONV_COUT));
  rec.barrier();
  return out;
}

Tensor resize(engine::Recorder& rec, const Tensor& x, shaders::Id id, uint32_t out_h, uint32_t out_w,
              const char* what, uint32_t pad = 0) {
  Tensor y = make_tensor(rec.context(), what, x.c, out_h, out_w);
  const gpu::NnResizeParams p{.channels = x.c,
                              .in_height = x.h,
                              .in_width = x.w,
                              .out_height = out_h,
                              .out_width = out_w,
                              .n_out = static_cast<uint32_t>(y.count()),
                              .pad = pad,
                              ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), id), {S4D_BIND(RESIZE_IN, x.buffer), S4D_BIND(RESIZE_OUT, y.buffer)}, p,
               ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor adain_mode(engine::Recorder& rec, const Tensor& x, const engine::Buffer& content_stats,
                  const engine::Buffer& style_stats, float alpha, uint32_t mode) {
  const char* layer = mode == S4D_NN_ADAIN_BLEND ? "adain" : "normalise";
  check_stats(layer, x, content_stats);
  check_stats(layer, x, style_stats);
  Tensor y = make_tensor(rec.context(), layer, x.c, x.h, x.w);
  const gpu::NnAdainParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .alpha = alpha, .mode = mode};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_adain),
               {S4D_BIND(ADAIN_IN, x.buffer), S4D_BIND(ADAIN_CONTENT_STATS, content_stats),
                S4D_BIND(ADAIN_STYLE_STATS, style_stats), S4D_BIND(ADAIN_OUT, y.buffer)},
               p, ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor weighted_sum(engine::Recorder& rec, const Tensor& a, const Tensor& b, float alpha, float beta,
                    const char* layer) {
  if (a.c != b.c || a.h != b.h || a.w != b.w) fail(layer, "shapes " + a.shape() + " and " + b.shape() + " differ");
  Tensor y = make_tensor(rec.context(), layer, a.c, a.h, a.w);
  const gpu::NnBlendParams p{.n = static_cast<uint32_t>(a.count()), .alpha = alpha, .beta = beta, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_blend),
               {S4D_BIND(BLEND_A, a.buffer), S4D_BIND(BLEND_B, b.buffer), S4D_BIND(BLEND_OUT, y.buffer)}, p,
               ceil_div(a.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

}  // namespace

ConvWeights upload_conv(engine::Context& ctx, const std::string& name, uint32_t cin, uint32_t cout, uint32_t k,
                        std::span<const float> weight, std::span<const float> bias) {
  if (k == 0 || k > 16) fail("conv " + name, "kernel size " + std::to_string(k) + " is not 1..16");
  if (weight.size() != size_t{cout} * cin * k * k || bias.size() != cout)
    fail("conv " + name, std::to_string(weight.size()) + " weights and " + std::to_string(bias.size()) +
                             " biases do not match " + std::to_string(cin) + " -> " + std::to_string(cout));
  ConvWeights w{name, cin, cout, k, {}, {}};
  w.weight = engine::buffer_from(ctx, name + " weight", weight);
  w.bias = engine::buffer_from(ctx, name + " bias", bias);
  return w;
}

NormWeights upload_norm(engine::Context& ctx, const std::string& name, uint32_t channels, std::span<const float> weight,
                        std::span<const float> bias) {
  if (weight.size() != channels || bias.size() != channels)
    fail("layernorm " + name, std::to_string(weight.size()) + " weights and " + std::to_string(bias.size()) +
                                  " biases for " + std::to_string(channels) + " channels");
  return {name, channels, engine::buffer_from(ctx, name + " weight", weight), engine::buffer_from(ctx, name + " bias", bias)};
}

Tensor conv3x3(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu) {
  if (w.k != 3) fail("conv " + w.name, "is not a 3x3 convolution");
  return conv(rec, x, w, relu ? S4D_NN_FLAG_RELU : 0u, nullptr, shaders::Id::nn_conv3x3);
}

Tensor conv3x3_zero_pad(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu) {
  if (w.k != 3) fail("conv " + w.name, "is not a 3x3 convolution");
  return conv(rec, x, w, relu ? S4D_NN_FLAG_RELU : 0u, nullptr, shaders::Id::nn_conv3x3_zero);
}

Tensor conv_strided(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, uint32_t stride, uint32_t pad, bool relu) {
  const std::string layer = "conv " + w.name;
  if (x.c != w.cin) fail(layer, "expects " + std::to_string(w.cin) + " input channels, got " + x.shape());
  if (stride == 0) fail(layer, "stride 0");
  if (x.h + 2 * pad < w.k || x.w + 2 * pad < w.k)
    fail(layer, "input " + x.shape() + " with padding " + std::to_string(pad) + " is smaller than the " + std::to_string(w.k) +
                    "x" + std::to_string(w.k) + " kernel");
  check_loop(layer, uint64_t{w.cin} * w.k * w.k, "input channels x taps " + std::to_string(w.cin) + " x " + std::to_string(w.k * w.k));
  const uint32_t out_h = (x.h + 2 * pad - w.k) / stride + 1, out_w = (x.w + 2 * pad - w.k) / stride + 1;
  Tensor y = make_tensor(rec.context(), w.name, w.cout, out_h, out_w);
  const gpu::NnConvStridedParams p{.cin = w.cin,
                                   .cout = w.cout,
                                   .in_height = x.h,
                                   .in_width = x.w,
                                   .out_height = out_h,
                                   .out_width = out_w,
                                   .kernel = w.k,
                                   .stride = stride,
                                   .pad = pad,
                                   .flags = relu ? S4D_NN_FLAG_RELU : 0u,
                                   .n_out = static_cast<uint32_t>(y.count()),
                                   ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_conv_strided),
               {S4D_BIND(CONV_IN, x.buffer), S4D_BIND(CONV_WEIGHT, w.weight), S4D_BIND(CONV_BIAS, w.bias),
                S4D_BIND(CONV_OUT, y.buffer)},
               p, ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor im2col(engine::Recorder& rec, const Tensor& x, uint32_t k, uint32_t stride, uint32_t pad) {
  if (k == 0 || stride == 0 || x.h + 2 * pad < k || x.w + 2 * pad < k)
    fail("im2col", "kernel " + std::to_string(k) + ", stride " + std::to_string(stride) + ", padding " + std::to_string(pad) +
                       " do not fit " + x.shape());
  Tensor y = make_tensor(rec.context(), "im2col", x.c * k * k, (x.h + 2 * pad - k) / stride + 1, (x.w + 2 * pad - k) / stride + 1);
  const gpu::NnConvStridedParams p{.cin = x.c,
                                   .cout = y.c,
                                   .in_height = x.h,
                                   .in_width = x.w,
                                   .out_height = y.h,
                                   .out_width = y.w,
                                   .kernel = k,
                                   .stride = stride,
                                   .pad = pad,
                                   .flags = 0,
                                   .n_out = static_cast<uint32_t>(y.count()),
                                   ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_im2col), {S4D_BIND(IM2COL_IN, x.buffer), S4D_BIND(IM2COL_OUT, y.buffer)},
               p, ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor conv1x1(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu) {
  if (w.k != 1) fail("conv " + w.name, "is not a 1x1 convolution");
  return conv(rec, x, w, relu ? S4D_NN_FLAG_RELU : 0u, nullptr, shaders::Id::nn_conv1x1);
}

void conv1x1_accumulate(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, Tensor& out) {
  if (w.k != 1) fail("conv " + w.name, "is not a 1x1 convolution");
  conv(rec, x, w, S4D_NN_FLAG_ACCUMULATE, &out, shaders::Id::nn_conv1x1);
}

void relu_inplace(engine::Recorder& rec, Tensor& x) {
  const gpu::NnEltParams p{.n = static_cast<uint32_t>(x.count()), .count = 0, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_relu), {S4D_BIND(RELU_DATA, x.buffer)}, p,
               ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
}

Tensor maxpool2(engine::Recorder& rec, const Tensor& x) {
  return resize(rec, x, shaders::Id::nn_maxpool, (x.h + 1) / 2, (x.w + 1) / 2, "maxpool");
}

Tensor avgpool3(engine::Recorder& rec, const Tensor& x) {
  if (x.h < 3 || x.w < 3) fail("avgpool3", "needs H, W >= 3, got " + x.shape());
  return resize(rec, x, shaders::Id::nn_avgpool3, x.h - 2, x.w - 2, "avgpool3");
}

Tensor maxpool2_floor(engine::Recorder& rec, const Tensor& x) {
  if (x.h < 2 || x.w < 2) fail("maxpool", "floor mode needs H, W >= 2, got " + x.shape());
  // nn_maxpool with floor(in / 2) outputs: every window lies inside the input, so no clamping applies.
  return resize(rec, x, shaders::Id::nn_maxpool, x.h / 2, x.w / 2, "maxpool");
}

Tensor avgpool2(engine::Recorder& rec, const Tensor& x) {
  if (x.h < 2 || x.w < 2) fail("avgpool2", "needs H, W >= 2, got " + x.shape());
  return resize(rec, x, shaders::Id::nn_avgpool2, x.h / 2, x.w / 2, "avgpool2");
}

Tensor maxpool3s2(engine::Recorder& rec, const Tensor& x, uint32_t pad) {
  if (pad > 1) fail("maxpool3s2", "padding " + std::to_string(pad) + " is not 0 or 1");
  if (x.h + 2 * pad < 3 || x.w + 2 * pad < 3)
    fail("maxpool3s2", "needs H, W >= " + std::to_string(3 - 2 * pad) + " with padding " + std::to_string(pad) + ", got " + x.shape());
  return resize(rec, x, shaders::Id::nn_maxpool3s2, (x.h + 2 * pad - 3) / 2 + 1, (x.w + 2 * pad - 3) / 2 + 1, "maxpool3s2",
                pad);
}

Tensor l2pool(engine::Recorder& rec, const Tensor& x) {
  return resize(rec, x, shaders::Id::nn_l2pool, (x.h + 1) / 2, (x.w + 1) / 2, "l2pool");
}

Tensor subsample2(engine::Recorder& rec, const Tensor& x) {
  return resize(rec, x, shaders::Id::nn_subsample2, (x.h + 1) / 2, (x.w + 1) / 2, "subsample2");
}

Tensor upsample2(engine::Recorder& rec, const Tensor& x) {
  return resize(rec, x, shaders::Id::nn_upsample, 2 * x.h, 2 * x.w, "upsample");
}

engine::Buffer mean_std(engine::Recorder& rec, const Tensor& x, float eps) {
  check_stats_input("mean_std", x);
  engine::Buffer stats(rec.context(), "mean_std", 2 * size_t{x.c} * sizeof(float));
  const gpu::NnStatsParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .eps = eps, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_channel_stats),
               {S4D_BIND(STATS_IN, x.buffer), S4D_BIND(STATS_OUT, stats)}, p, x.c);
  rec.barrier();
  return stats;
}

Tensor global_average(engine::Recorder& rec, const Tensor& x) {
  Tensor means;
  means.buffer = mean_std(rec, x);  // the first x.c values; the standard deviations after them go unread
  means.c = x.c, means.h = 1, means.w = 1;
  return means;
}

Tensor squares_over_sum(engine::Recorder& rec, const Tensor& x) {
  check_stats_input("squares_over_sum", x);
  Tensor a = make_tensor(rec.context(), "squares_over_sum", x.c, 1, 1);
  const gpu::NnStatsParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .eps = 0.0f, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_channel_stats_mcc),
               {S4D_BIND(STATS_IN, x.buffer), S4D_BIND(STATS_OUT, a.buffer)}, p, x.c);
  rec.barrier();
  return a;
}

Tensor adain(engine::Recorder& rec, const Tensor& x, const engine::Buffer& content_stats,
             const engine::Buffer& style_stats, float alpha) {
  return adain_mode(rec, x, content_stats, style_stats, alpha, S4D_NN_ADAIN_BLEND);
}

Tensor normalise(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats) {
  return adain_mode(rec, x, stats, stats, 1.0f, S4D_NN_ADAIN_NORMALISE);
}

void scale_channels(engine::Recorder& rec, Tensor& x, const engine::Buffer& factors) {
  if (factors.size() < size_t{x.c} * sizeof(float))
    fail("scale_channels", "factors '" + factors.name() + "' hold fewer than " + std::to_string(x.c) + " values");
  const gpu::NnEltParams p{
      .n = static_cast<uint32_t>(x.count()), .count = static_cast<uint32_t>(x.plane()), ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_scale_channels),
               {S4D_BIND(SCALE_DATA, x.buffer), S4D_BIND(SCALE_FACTORS, factors)}, p, ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
}

Tensor blend(engine::Recorder& rec, const Tensor& a, const Tensor& b, float alpha) {
  return weighted_sum(rec, a, b, alpha, 1.0f - alpha, "blend");
}

Tensor add(engine::Recorder& rec, const Tensor& a, const Tensor& b) {
  return weighted_sum(rec, a, b, 1.0f, 1.0f, "add");
}

Tensor subtract(engine::Recorder& rec, const Tensor& a, const Tensor& b) {
  return weighted_sum(rec, a, b, 1.0f, -1.0f, "subtract");
}

Tensor layernorm(engine::Recorder& rec, const Tensor& x, const NormWeights& w, float eps) {
  const std::string layer = "layernorm " + w.name;
  if (x.c != w.channels) fail(layer, "expects " + std::to_string(w.channels) + " channels, got " + x.shape());
  check_loop(layer, x.c, "channels " + std::to_string(x.c));
  Tensor y = make_tensor(rec.context(), w.name, x.c, x.h, x.w);
  const gpu::NnStatsParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .eps = eps, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_layernorm),
               {S4D_BIND(LN_IN, x.buffer), S4D_BIND(LN_WEIGHT, w.weight), S4D_BIND(LN_BIAS, w.bias), S4D_BIND(LN_OUT, y.buffer)},
               p, ceil_div(x.plane(), S4D_NN_WG));
  rec.barrier();
  return y;
}

void gelu_inplace(engine::Recorder& rec, Tensor& x) {
  const gpu::NnEltParams p{.n = static_cast<uint32_t>(x.count()), .count = 0, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_gelu), {S4D_BIND(GELU_DATA, x.buffer)}, p,
               ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
}

Tensor vit_embed(engine::Recorder& rec, const Tensor& patches, const Tensor& pos) {
  const bool first_only = pos.plane() == 1;
  if (pos.c != patches.c || pos.h != 1 || (!first_only && pos.plane() != patches.plane() + 1))
    fail("vit_embed", "position embedding " + pos.shape() + " does not match patches " + patches.shape() +
                          " (needs [c, 1, 1 + h w] or [c, 1, 1])");
  const auto tokens = static_cast<uint32_t>(patches.plane() + 1);
  Tensor y = make_tensor(rec.context(), "tokens", pos.c, 1, tokens);
  const gpu::NnEltParams p{.n = static_cast<uint32_t>(y.count()), .count = tokens, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), first_only ? shaders::Id::nn_prepend_token : shaders::Id::nn_vit_embed),
               {S4D_BIND(VIT_PATCHES, patches.buffer), S4D_BIND(VIT_POS, pos.buffer), S4D_BIND(VIT_OUT, y.buffer)}, p,
               ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor resize_nearest(engine::Recorder& rec, const Tensor& x, uint32_t out_h, uint32_t out_w) {
  if (out_h == 0 || out_w == 0) fail("resize_nearest", "empty output size for " + x.shape());
  // The kernel's integer source index multiplies output and input sizes.
  if (uint64_t{out_h} * x.h >= (uint64_t{1} << 32) || uint64_t{out_w} * x.w >= (uint64_t{1} << 32))
    fail("resize_nearest",
         "sizes too large: " + x.shape() + " to " + std::to_string(out_h) + "x" + std::to_string(out_w));
  return resize(rec, x, shaders::Id::nn_resize_nearest, out_h, out_w, "resize_nearest");
}

Tensor concat_channels(engine::Recorder& rec, std::span<const Tensor* const> parts) {
  if (parts.empty()) fail("concat_channels", "no tensors");
  uint32_t c = 0;
  for (const Tensor* t : parts) {
    if (t->h != parts[0]->h || t->w != parts[0]->w)
      fail("concat_channels", "sizes " + parts[0]->shape() + " and " + t->shape() + " differ");
    c += t->c;
  }
  Tensor y = make_tensor(rec.context(), "concat", c, parts[0]->h, parts[0]->w);
  size_t offset = 0;  // [C, H, W] stacks channels, so each part is one contiguous copy
  for (const Tensor* t : parts) {
    rec.copy(t->buffer, y.buffer, t->count() * sizeof(float), 0, offset);
    offset += t->count() * sizeof(float);
  }
  rec.barrier();
  return y;
}

}  // namespace s4d::nn
