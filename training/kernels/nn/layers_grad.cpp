#include "s4d/nn/layers_grad.h"

#include <algorithm>
#include <vector>

#include "layer_checks.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_nn_grad.h"

namespace s4d::nn {

namespace {

using detail::check_loop;
using detail::fail;
using primitives::ceil_div;
using primitives::shader_pipeline;

// Pixels per nn_conv_wgrad chunk: enough invocations to fill the CPU cores on the deep layers (few
// pixels, many channel pairs) and few partial sums on the shallow ones.
constexpr uint32_t wgrad_chunk_pixels = 1024;

void check_same(const char* layer, const Tensor& a, const Tensor& b) {
  if (a.c != b.c || a.h != b.h || a.w != b.w) fail(layer, "shapes " + a.shape() + " and " + b.shape() + " differ");
}

void check_kernel(const std::string& layer, const ConvWeights& w) {
  if (w.k != 1 && w.k != 3) fail(layer, "has a " + std::to_string(w.k) + "x" + std::to_string(w.k) + " kernel; backward supports 1 and 3");
}

void backward_input(engine::Recorder& rec, const Tensor& dy, const ConvWeights& w, Tensor& dx, uint32_t flags) {
  const std::string layer = "conv backward " + w.name;
  check_kernel(layer, w);
  if (dy.c != w.cout) fail(layer, "expects " + std::to_string(w.cout) + " gradient channels, got " + dy.shape());
  if (dx.c != w.cin || dx.h != dy.h || dx.w != dy.w) fail(layer, "input gradient " + dx.shape() + " does not match " + dy.shape());
  check_loop(layer, w.cout, "output channels " + std::to_string(w.cout));
  if (w.k == 3 && (dy.h < 2 || dy.w < 2)) fail(layer, "reflection padding needs H, W >= 2, got " + dy.shape());
  // nn_conv3x3 / nn_conv1x1's tiling with the channel roles swapped: the loop runs over the layer's outputs.
  const gpu::NnConvParams p{.cin = w.cout,
                            .cout = w.cin,
                            .height = dy.h,
                            .width = dy.w,
                            .tiles_x = ceil_div(dy.w, S4D_NN_CONV_WG_X * S4D_NN_CONV_PIX),
                            .tiles_y = ceil_div(dy.h, S4D_NN_CONV_WG_Y),
                            .flags = flags,
                            ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), w.k == 3 ? shaders::Id::nn_conv3x3_bwd_input : shaders::Id::nn_conv1x1_bwd_input),
               {S4D_BIND(CONVB_DY, dy.buffer), S4D_BIND(CONVB_WEIGHT, w.weight), S4D_BIND(CONVB_DX, dx.buffer)}, p,
               p.tiles_x * p.tiles_y * ceil_div(w.cin, S4D_NN_CONV_COUT));
  rec.barrier();
}

}  // namespace

ConvGrads zero_conv_grads(engine::Recorder& rec, const ConvWeights& w) {
  ConvGrads g{engine::Buffer(rec.context(), w.name + " dW", w.weight.size()),
              engine::Buffer(rec.context(), w.name + " db", w.bias.size())};
  rec.fill(g.weight, 0);
  rec.fill(g.bias, 0);
  rec.barrier();
  return g;
}

Tensor zero_tensor(engine::Recorder& rec, const std::string& name, uint32_t c, uint32_t h, uint32_t w) {
  Tensor t = make_tensor(rec.context(), name, c, h, w);
  rec.fill(t.buffer, 0);
  rec.barrier();
  return t;
}

Tensor conv_backward_input(engine::Recorder& rec, const Tensor& dy, const ConvWeights& w) {
  Tensor dx = make_tensor(rec.context(), w.name + " dx", w.cin, dy.h, dy.w);
  backward_input(rec, dy, w, dx, 0);
  return dx;
}

void conv_backward_input_accumulate(engine::Recorder& rec, const Tensor& dy, const ConvWeights& w, Tensor& dx) {
  backward_input(rec, dy, w, dx, S4D_NN_FLAG_ACCUMULATE);
}

void conv_backward_weights(engine::Recorder& rec, const Tensor& x, const Tensor& dy, const ConvWeights& w,
                           ConvGrads& grads, bool accumulate) {
  const std::string layer = "conv weight gradient " + w.name;
  check_kernel(layer, w);
  if (x.c != w.cin || dy.c != w.cout || x.h != dy.h || x.w != dy.w)
    fail(layer, "input " + x.shape() + " and gradient " + dy.shape() + " do not match " + std::to_string(w.cin) +
                    " -> " + std::to_string(w.cout));
  if (w.k == 3 && (x.h < 2 || x.w < 2)) fail(layer, "reflection padding needs H, W >= 2, got " + x.shape());
  if (grads.weight.size() < w.weight.size() || grads.bias.size() < w.bias.size())
    fail(layer, "gradient buffers '" + grads.weight.name() + "', '" + grads.bias.name() + "' are smaller than the weights");
  const uint32_t chunk_rows = std::max(1u, std::min(x.h, wgrad_chunk_pixels / x.w));
  check_loop(layer, uint64_t{chunk_rows} * (x.w + 1), "a chunk of " + std::to_string(chunk_rows) + " rows of " + x.shape());
  const uint32_t chunks = ceil_div(x.h, chunk_rows), taps = w.k * w.k;
  const uint32_t weights = w.cout * w.cin * taps, slots = weights + w.cout;
  check_loop(layer, chunks, std::to_string(chunks) + " chunks");
  engine::Buffer partial(rec.context(), layer + " partial sums", size_t{chunks} * slots * sizeof(float));
  const gpu::NnWgradParams p{.cin = w.cin,
                             .cout = w.cout,
                             .height = x.h,
                             .width = x.w,
                             .chunk_rows = chunk_rows,
                             .chunks = chunks,
                             .slots = slots,
                             .invocations = chunks * ceil_div(w.cout, S4D_NN_WGRAD_COUT) * (w.cin + 1)};
  rec.dispatch(shader_pipeline(rec.context(), w.k == 3 ? shaders::Id::nn_conv3x3_wgrad : shaders::Id::nn_conv1x1_wgrad),
               {S4D_BIND(WGRAD_X, x.buffer), S4D_BIND(WGRAD_DY, dy.buffer), S4D_BIND(WGRAD_PARTIAL, partial)}, p,
               ceil_div(p.invocations, S4D_NN_WG));
  rec.barrier();
  const gpu::NnWgradReduceParams r{
      .slots = slots, .weights = weights, .chunks = chunks, .flags = accumulate ? S4D_NN_FLAG_ACCUMULATE : 0u};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_wgrad_reduce),
               {S4D_BIND(WGRED_PARTIAL, partial), S4D_BIND(WGRED_DW, grads.weight), S4D_BIND(WGRED_DB, grads.bias)}, r,
               ceil_div(slots, S4D_NN_WG));
  rec.barrier();
}

void relu_backward(engine::Recorder& rec, Tensor& dy, const Tensor& y) {
  check_same("relu backward", dy, y);
  const gpu::NnEltParams p{.n = static_cast<uint32_t>(dy.count()), .count = 0, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_relu_bwd),
               {S4D_BIND(RELUB_DY, dy.buffer), S4D_BIND(RELUB_Y, y.buffer)}, p, ceil_div(dy.count(), S4D_NN_WG));
  rec.barrier();
}

Tensor upsample2_backward(engine::Recorder& rec, const Tensor& dy) {
  if (dy.h % 2 != 0 || dy.w % 2 != 0) fail("upsample backward", "gradient " + dy.shape() + " has an odd size");
  Tensor dx = make_tensor(rec.context(), "upsample dx", dy.c, dy.h / 2, dy.w / 2);
  const gpu::NnResizeParams p{.channels = dy.c,
                              .in_height = dy.h,
                              .in_width = dy.w,
                              .out_height = dx.h,
                              .out_width = dx.w,
                              .n_out = static_cast<uint32_t>(dx.count()),
                              .pad = 0,
                              ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_upsample_bwd),
               {S4D_BIND(RESIZE_IN, dy.buffer), S4D_BIND(RESIZE_OUT, dx.buffer)}, p, ceil_div(dx.count(), S4D_NN_WG));
  rec.barrier();
  return dx;
}

Tensor maxpool2_backward(engine::Recorder& rec, const Tensor& x, const Tensor& dy) {
  if (dy.c != x.c || dy.h != (x.h + 1) / 2 || dy.w != (x.w + 1) / 2)
    fail("maxpool backward", "gradient " + dy.shape() + " is not the pooled size of " + x.shape());
  Tensor dx = make_tensor(rec.context(), "maxpool dx", x.c, x.h, x.w);
  const gpu::NnResizeParams p{.channels = x.c,
                              .in_height = x.h,
                              .in_width = x.w,
                              .out_height = dy.h,
                              .out_width = dy.w,
                              .n_out = static_cast<uint32_t>(x.count()),
                              .pad = 0,
                              ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_maxpool_bwd),
               {S4D_BIND(POOLB_X, x.buffer), S4D_BIND(POOLB_DY, dy.buffer), S4D_BIND(POOLB_DX, dx.buffer)}, p,
               ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
  return dx;
}

Tensor avgpool3_backward(engine::Recorder& rec, const Tensor& dy) {
  Tensor dx = make_tensor(rec.context(), "avgpool3 dx", dy.c, dy.h + 2, dy.w + 2);
  const gpu::NnResizeParams p{.channels = dy.c,
                              .in_height = dx.h,
                              .in_width = dx.w,
                              .out_height = dy.h,
                              .out_width = dy.w,
                              .n_out = static_cast<uint32_t>(dx.count()),
                              .pad = 0,
                              ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_avgpool3_bwd),
               {S4D_BIND(RESIZE_IN, dy.buffer), S4D_BIND(RESIZE_OUT, dx.buffer)}, p, ceil_div(dx.count(), S4D_NN_WG));
  rec.barrier();
  return dx;
}

engine::Buffer channel_max(engine::Recorder& rec, const Tensor& x) {
  check_loop("channel_max", ceil_div(x.plane(), S4D_NN_STATS_WG), x.shape());
  engine::Buffer out(rec.context(), "channel maxima", 2 * size_t{x.c} * sizeof(float));
  const gpu::NnStatsBwdParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .mode = 0, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_channel_max), {S4D_BIND(CMAX_IN, x.buffer), S4D_BIND(CMAX_OUT, out)},
               p, x.c);
  rec.barrier();
  return out;
}

engine::Buffer selfsim(engine::Recorder& rec, const Tensor& v, const Tensor& grad, float weight) {
  check_same("selfsim", v, grad);
  check_loop("selfsim", v.c, "channels " + std::to_string(v.c));
  const engine::Buffer sums = channel_dots(rec, v, v), maxima = channel_max(rec, v);
  engine::Buffer value(rec.context(), "selfsim value", sizeof(float));
  const gpu::NnSelfsimParams p{.channels = v.c, .count = static_cast<uint32_t>(v.plane()), .weight = weight, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_selfsim_bwd),
               {S4D_BIND(SELFSIM_V, v.buffer), S4D_BIND(SELFSIM_SUMS, sums), S4D_BIND(SELFSIM_MAX, maxima),
                S4D_BIND(SELFSIM_GRAD, grad.buffer), S4D_BIND(SELFSIM_VALUE, value)},
               p, ceil_div(v.count(), S4D_NN_WG));
  rec.barrier();
  return value;
}

engine::Buffer channel_dots(engine::Recorder& rec, const Tensor& a, const Tensor& b) {
  check_same("channel_dots", a, b);
  check_loop("channel_dots", ceil_div(a.plane(), S4D_NN_STATS_WG), a.shape());
  engine::Buffer sums(rec.context(), "channel sums", 2 * size_t{a.c} * sizeof(float));
  const gpu::NnStatsBwdParams p{.channels = a.c, .count = static_cast<uint32_t>(a.plane()), .mode = 0, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_channel_dots),
               {S4D_BIND(DOTS_A, a.buffer), S4D_BIND(DOTS_B, b.buffer), S4D_BIND(DOTS_SUMS, sums)}, p, a.c);
  rec.barrier();
  return sums;
}

namespace {

void stats_backward(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats, const engine::Buffer& dstats,
                    const Tensor& dy, Tensor& dx, uint32_t mode) {
  const char* layer = mode == S4D_NN_STATSB_NORMALISE ? "normalise backward" : "mean_std backward";
  check_same(layer, x, dx);
  check_same(layer, x, dy);
  if (x.plane() < 2) fail(layer, "needs at least 2 values per channel, got " + x.shape());
  if (stats.size() < 2 * size_t{x.c} * sizeof(float) || dstats.size() < 2 * size_t{x.c} * sizeof(float))
    fail(layer, "statistics '" + stats.name() + "' or '" + dstats.name() + "' hold fewer than 2 x " + std::to_string(x.c) + " values");
  const gpu::NnStatsBwdParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .mode = mode, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_mean_std_bwd),
               {S4D_BIND(STATSB_X, x.buffer), S4D_BIND(STATSB_STATS, stats), S4D_BIND(STATSB_DSTATS, dstats),
                S4D_BIND(STATSB_DY, dy.buffer), S4D_BIND(STATSB_DX, dx.buffer)},
               p, ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
}

}  // namespace

void mean_std_backward(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats, const engine::Buffer& dstats,
                       Tensor& dx) {
  stats_backward(rec, x, stats, dstats, x, dx, S4D_NN_STATSB_STATS);  // x stands in for the unread dy
}

void normalise_backward(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats, const Tensor& y,
                        const Tensor& dy, Tensor& dx) {
  check_same("normalise backward", x, y);
  stats_backward(rec, x, stats, channel_dots(rec, dy, y), dy, dx, S4D_NN_STATSB_NORMALISE);
}

Tensor squares_over_sum_backward(engine::Recorder& rec, const Tensor& x, const Tensor& da) {
  if (da.count() != x.c) fail("squares_over_sum backward", "gradient " + da.shape() + " does not have one value per channel of " + x.shape());
  const engine::Buffer sums = channel_dots(rec, x, x);
  Tensor dx = make_tensor(rec.context(), "squares_over_sum dx", x.c, x.h, x.w);
  const gpu::NnStatsBwdParams p{.channels = x.c, .count = static_cast<uint32_t>(x.plane()), .mode = 0, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_squares_over_sum_bwd),
               {S4D_BIND(SOSB_X, x.buffer), S4D_BIND(SOSB_SUMS, sums), S4D_BIND(SOSB_DA, da.buffer),
                S4D_BIND(SOSB_DX, dx.buffer)},
               p, ceil_div(x.count(), S4D_NN_WG));
  rec.barrier();
  return dx;
}

engine::Buffer squared_error(engine::Recorder& rec, const engine::Buffer& a, const engine::Buffer& b,
                             const engine::Buffer& grad, size_t count, float scale) {
  const size_t bytes = count * sizeof(float);
  if (count == 0 || a.size() < bytes || b.size() < bytes || grad.size() < bytes)
    fail("squared_error", "'" + a.name() + "', '" + b.name() + "' or '" + grad.name() + "' hold fewer than " +
                              std::to_string(count) + " values");
  const uint32_t groups = ceil_div(count, S4D_NN_WG);
  engine::Buffer partials(rec.context(), "squared error partials", size_t{groups} * sizeof(float));
  const gpu::NnMseParams p{.n = static_cast<uint32_t>(count), .scale = scale, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_mse),
               {S4D_BIND(MSE_A, a), S4D_BIND(MSE_B, b), S4D_BIND(MSE_GRAD, grad), S4D_BIND(MSE_PARTIALS, partials)}, p,
               groups);
  rec.barrier();
  return partials;
}

engine::Buffer tv_l1(engine::Recorder& rec, const Tensor& x, const Tensor& grad, float weight) {
  check_same("tv_l1", x, grad);
  const uint32_t groups = ceil_div(x.count(), S4D_NN_WG);
  engine::Buffer partials(rec.context(), "tv partials", size_t{groups} * sizeof(float));
  const gpu::NnTvL1Params p{.channels = x.c, .height = x.h, .width = x.w, .weight = weight};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_tv_l1),
               {S4D_BIND(TV1_X, x.buffer), S4D_BIND(TV1_GRAD, grad.buffer), S4D_BIND(TV1_PARTIALS, partials)}, p, groups);
  rec.barrier();
  return partials;
}

double squared_error_value(engine::Context& ctx, const engine::Buffer& partials) {
  double sum = 0;
  for (const float v : ctx.download<float>(partials, partials.size() / sizeof(float))) sum += v;
  return sum;
}

}  // namespace s4d::nn
