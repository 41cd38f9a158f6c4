// Shared layouts of the network layers' backward kernels (shaders/nn/*_bwd.comp, nn_conv_wgrad,
// nn_wgrad_reduce, nn_channel_dots, nn_mse), the gradients of the forward layers in s4d_nn.h that the
// MCCNet/HGST decoder, MCC module and VGG encoder use (ALGORITHMS.md 4.5). Tensors are one image,
// float [C, H, W] row-major, as the forward kernels. CPU twins: training/ref/include/s4d/ref/nn_grad_ref.h.
// Every runtime loop stays under S4D_NN_MAX_LOOP iterations (llvmpipe's per-invocation cap); the
// host refuses or tiles sizes past it.
#ifndef S4D_NN_GRAD_H
#define S4D_NN_GRAD_H
#include "s4d_nn.h"

// Element-wise backward kernels: one invocation per input element, S4D_NN_WG wide.
// nn_conv3x3_bwd_input: dx (+)= the adjoint of ReflectionPad2d(1) + Conv2d(k=3) applied to dy, tiled
// as nn_conv3x3 (NnConvParams with cin = the layer's cout, cout = the layer's cin): an invocation
// computes a strip of S4D_NN_CONV_PIX pixels for a block of S4D_NN_CONV_COUT input channels,
// looping over the output channels.
#define S4D_B_CONVB_DY 0      // [cout, h, w]
#define S4D_B_CONVB_WEIGHT 1  // [cout, cin, 3, 3]
#define S4D_B_CONVB_DX 2      // [cin, h, w]; added to with S4D_NN_FLAG_ACCUMULATE
// nn_conv1x1_bwd_input is nn_conv1x1 with the weights read transposed and no bias: the bindings
// and NnConvParams above; flag S4D_NN_FLAG_ACCUMULATE.

// nn_conv_wgrad (k = 3 with reflection padding, or k = 1): partial sums of dW[co, ci, ky, kx] =
// sum_p dy[co, p] x[ci, p + (ky, kx) - 1] and dB[co] = sum_p dy[co, p] over one chunk of rows each.
// An invocation handles one input channel (or the bias, "channel" cin) for a block of
// S4D_NN_WGRAD_COUT output channels and one chunk; partial[chunk, slot] with slot = weight index
// (co cin + ci) k k + tap, or cout cin k k + co for the bias. nn_wgrad_reduce then sums the chunks.
#define S4D_NN_WGRAD_COUT 4
#define S4D_B_WGRAD_X 0        // [cin, h, w] the layer's input
#define S4D_B_WGRAD_DY 1       // [cout, h, w]
#define S4D_B_WGRAD_PARTIAL 2  // [chunks, slots]
// nn_wgrad_reduce: one invocation per slot, looping over the chunks.
#define S4D_B_WGRED_PARTIAL 0  // [chunks, slots]
#define S4D_B_WGRED_DW 1       // [cout cin k k]; added to with S4D_NN_FLAG_ACCUMULATE
#define S4D_B_WGRED_DB 2       // [cout]; likewise

// nn_relu_bwd: dy = y > 0 ? dy : 0 in place, y the ReLU's output (PyTorch's threshold_backward).
#define S4D_B_RELUB_DY 0  // [n], in place
#define S4D_B_RELUB_Y 1   // [n]
// nn_upsample_bwd: dx[c, y, x] = sum of dy over the 2x2 block it was copied to (NnResizeParams:
// in = dy's size, out = x's size); bindings S4D_B_RESIZE_IN (dy) and S4D_B_RESIZE_OUT (dx).
// nn_maxpool_bwd: dx[c, y, x] = dy of its window when x[c, y, x] is the window's first maximum in
// row-major order (PyTorch's tie rule), else 0 (NnResizeParams: in = x's size, out = pooled size,
// n_out = x's count).
#define S4D_B_POOLB_X 0   // [c, h, w] the pool's input
#define S4D_B_POOLB_DY 1  // [c, ceil(h/2), ceil(w/2)]
#define S4D_B_POOLB_DX 2  // [c, h, w]

// nn_channel_dots: per channel (one workgroup, S4D_NN_STATS_WG wide) sums[c] = sum_p a[c, p] and
// sums[C + c] = sum_p a[c, p] b[c, p].
#define S4D_B_DOTS_A 0     // [c, count]
#define S4D_B_DOTS_B 1     // [c, count]
#define S4D_B_DOTS_SUMS 2  // [2, c]
// nn_mean_std_bwd, with stats = (mu, sigma) of x (nn_channel_stats), N = count:
// mode S4D_NN_STATSB_STATS: dx += dmu / N + dsigma (x - mu) / ((N - 1) sigma), dstats = (dmu, dsigma);
// mode S4D_NN_STATSB_NORMALISE (y = (x - mu) / sigma): dx += dy / sigma + dmu / N + dsigma (x - mu) /
// ((N - 1) sigma) with dmu = -sum dy / sigma and dsigma = -sum dy y / sigma from the nn_channel_dots
// sums of (dy, y) bound as dstats (y rather than x - mu: no cancellation when |mu| >> sigma).
#define S4D_NN_STATSB_STATS 0u
#define S4D_NN_STATSB_NORMALISE 1u
#define S4D_B_STATSB_X 0       // [c, count]
#define S4D_B_STATSB_STATS 1   // [2, c]
#define S4D_B_STATSB_DSTATS 2  // [2, c]: (dmu, dsigma), or the sums (sum dy, sum dy y)
#define S4D_B_STATSB_DY 3      // [c, count]; normalise mode only (bind any buffer otherwise)
#define S4D_B_STATSB_DX 4      // [c, count], added to
// nn_squares_over_sum_bwd: a = S2 / S1 with S1 = sum_p x, S2 = sum_p x^2 (MCC's style weights), so
// dx = da (2 x - a) / S1; sums are nn_channel_dots of (x, x).
#define S4D_B_SOSB_X 0     // [c, count]
#define S4D_B_SOSB_SUMS 1  // [2, c]
#define S4D_B_SOSB_DA 2    // [c]
#define S4D_B_SOSB_DX 3    // [c, count]

// nn_mse: grad += scale (a - b) and, per workgroup of S4D_NN_WG, partials[group] = sum (a - b)^2.
#if S4D_NN_WG != S4D_NN_STATS_WG
#error "nn_mse sums its workgroup with nn_wg_sum.glsl, sized S4D_NN_STATS_WG"
#endif
#define S4D_B_MSE_A 0         // [n]
#define S4D_B_MSE_B 1         // [n]
#define S4D_B_MSE_GRAD 2      // [n], added to
#define S4D_B_MSE_PARTIALS 3  // [ceil(n / S4D_NN_WG)]

// nn_tv_l1: the total variation sum_{c,y,x} |x[c,y,x] - x[c,y,x+1]| + |x[c,y,x] - x[c,y+1,x]| (MCCNet's
// and HGST's TV term, a sum, not a mean): grad += weight dTV/dx (sign(0) = 0, as PyTorch's abs) and
// each workgroup's sum of the differences' magnitudes in partials. One invocation per element.
#define S4D_B_TV1_X 0         // [c, h, w]
#define S4D_B_TV1_GRAD 1      // [c, h, w], added to
#define S4D_B_TV1_PARTIALS 2  // [ceil(n / S4D_NN_WG)]

// HGST's self-similarity term "Iins" (ALGORITHMS.md 4.5) on v = avgpool3(relu5_1), v >= 0, per
// channel c of L values: mean_i min_j (1 - v_i v_j / S), S the sum of squares of the whole tensor,
// which is 1 - mean(v_c) max(v_c) / S. nn_avgpool3 / nn_avgpool3_bwd: 3x3 mean, stride 1, no
// padding, and its adjoint (NnResizeParams: in = the pool's input size, out = its output size,
// n_out = the count written; bindings S4D_B_RESIZE_IN, S4D_B_RESIZE_OUT). nn_channel_max: per
// channel (one workgroup) the maximum and the index of its first occurrence (as a float).
// nn_selfsim_bwd: per element dv (+)= weight / C d(sum_c Iins_c)/dv, from the channel sums
// (nn_channel_dots of (v, v)) and maxima, each invocation summing S and T = sum_c mean_c max_c
// over the channels; invocation 0 writes sum_c Iins_c = C - T / S to value[0].
#define S4D_B_CMAX_IN 0     // [c, count]
#define S4D_B_CMAX_OUT 1    // [2, c]: maxima, then their first indices
#define S4D_B_SELFSIM_V 0      // [c, count]
#define S4D_B_SELFSIM_SUMS 1   // [2, c] (sum v, sum v^2)
#define S4D_B_SELFSIM_MAX 2    // [2, c] nn_channel_max's
#define S4D_B_SELFSIM_GRAD 3   // [c, count], added to
#define S4D_B_SELFSIM_VALUE 4  // [1]

S4D_NAMESPACE_BEGIN

// Push constants of nn_conv_wgrad.
struct NnWgradParams {
  uint cin;
  uint cout;
  uint height;
  uint width;
  uint chunk_rows;  // rows per chunk: chunk_rows * width <= S4D_NN_MAX_LOOP
  uint chunks;      // ceil(height / chunk_rows)
  uint slots;       // cout * cin * k * k + cout
  uint invocations; // chunks * ceil(cout / S4D_NN_WGRAD_COUT) * (cin + 1)
};

// Push constants of nn_wgrad_reduce.
struct NnWgradReduceParams {
  uint slots;
  uint weights;  // cout * cin * k * k: slots past it are biases
  uint chunks;
  uint flags;    // S4D_NN_FLAG_ACCUMULATE
};

// Push constants of nn_channel_dots, nn_mean_std_bwd and nn_squares_over_sum_bwd.
struct NnStatsBwdParams {
  uint channels;
  uint count;  // values per channel
  uint mode;   // nn_mean_std_bwd: S4D_NN_STATSB_*
  uint _pad0;
};

// Push constants of nn_mse.
struct NnMseParams {
  uint n;
  float scale;
  uint _pad0;
  uint _pad1;
};

// Push constants of nn_selfsim_bwd.
struct NnSelfsimParams {
  uint channels;
  uint count;
  float weight;
  uint _pad0;
};

// Push constants of nn_tv_l1.
struct NnTvL1Params {
  uint channels;
  uint height;
  uint width;
  float weight;
};

S4D_NAMESPACE_END

#endif  // S4D_NN_GRAD_H
