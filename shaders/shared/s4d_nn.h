// Shared layouts of the network layers (shaders/nn; ALGORITHMS.md 4.2, 5): VGG-style convolutions,
// pooling, upsampling, channel statistics, AdaIN and the MCC module's pieces. Every tensor is one
// image, float [C, H, W] row-major; weights keep PyTorch's layouts ([Cout, Cin, k, k], Linear
// [out, in]). CPU twins: training/ref/include/s4d/ref/nn_ref.h.
//
// llvmpipe ends an invocation after 65,535 loop iterations in total, so no kernel loops over more
// than Cin (convolutions: the 3x3 taps and the output-channel block are unrolled) or over more than
// H*W / S4D_NN_STATS_WG per pass (statistics); the host refuses sizes past S4D_NN_MAX_LOOP.
#ifndef S4D_NN_H
#define S4D_NN_H
#include "s4d_common.h"

#define S4D_NN_MAX_LOOP 60000

// Convolutions: a workgroup is WG_X x WG_Y invocations, each computing a strip of S4D_NN_CONV_PIX
// pixels along x for one block of S4D_NN_CONV_COUT output channels, so a tile is 32 x 8 pixels.
// Flat group index = block * tiles_x * tiles_y + tile_y * tiles_x + tile_x. Measured on lavapipe
// (CPU time, 3x3, 64-512 channels): 4.6 GFLOP/s; strips of 2 or 8 pixels, blocks of 4 or 16
// channels and 4-wide workgroups were 10-60 % slower.
#define S4D_NN_CONV_WG_X 8
#define S4D_NN_CONV_WG_Y 8
#define S4D_NN_CONV_PIX 4
#define S4D_NN_CONV_COUT 8
// nn_conv1x1_rows: nn_conv1x1 for tensors of one row (a transformer's tokens [c, 1, n]), where an
// 8-row workgroup would leave 7 of its rows idle: S4D_NN_CONV_ROWS_WG_X x 1 invocations, a tile of
// 256 pixels.
#define S4D_NN_CONV_ROWS_WG_X 64
#define S4D_NN_FLAG_RELU 1u        // ReLU on the output
#define S4D_NN_FLAG_ACCUMULATE 2u  // out += conv(in) (residual connections)
#define S4D_B_CONV_IN 0      // [cin, h, w]
#define S4D_B_CONV_WEIGHT 1  // [cout, cin, k, k]
#define S4D_B_CONV_BIAS 2    // [cout]
#define S4D_B_CONV_OUT 3     // [cout, h, w]

// nn_conv_strided: any k x k convolution with stride and zero padding (AlexNet's 11x11 stride 4 and
// 5x5), one invocation per output value looping over cin * k * k (the host keeps that under
// S4D_NN_MAX_LOOP); bindings S4D_B_CONV_*; flags S4D_NN_FLAG_RELU.

// nn_im2col: F.unfold (k, stride, zero padding) into [cin k k, out_h, out_w], so that a strided
// convolution runs as nn_conv1x1 (MUSIQ: its 7x7 stride-2 root and 16384-wide embedding);
// NnConvStridedParams (cout = cin k k; no weights, bias or flags).
#define S4D_B_IM2COL_IN 0   // [cin, in_h, in_w]
#define S4D_B_IM2COL_OUT 1  // [cin k k, out_h, out_w]

// Element-wise kernels (ReLU, pooling, upsampling, AdaIN, channel scaling): one invocation per
// output element.
#define S4D_NN_WG 64
#define S4D_B_RELU_DATA 0     // [n], in place
#define S4D_B_RESIZE_IN 0     // [c, in_h, in_w]
#define S4D_B_RESIZE_OUT 1    // [c, out_h, out_w]
#define S4D_B_SCALE_DATA 0    // nn_scale_channels: [c, count], in place
#define S4D_B_SCALE_FACTORS 1 // [c]
#define S4D_B_BLEND_A 0       // nn_blend: out = alpha a + beta b, [n] each
#define S4D_B_BLEND_B 1
#define S4D_B_BLEND_OUT 2

// DISTS's L2 pooling (nn_l2pool): sqrt(3x3 Hann-weighted mean of squares + eps), eps as DISTS_pt.py.
#define S4D_NN_L2POOL_EPS 1e-12

// Channel statistics: one workgroup per channel, two passes over its H*W values (mean, then the
// centred squares). nn_channel_stats writes mean and std = sqrt(unbiased variance + eps);
// nn_channel_stats_mcc writes a = sum(x^2) / sum(x) (MCC's style weighting, no stabilisation).
#define S4D_NN_STATS_WG 64
#define S4D_B_STATS_IN 0   // [c, count]
#define S4D_B_STATS_OUT 1  // nn_channel_stats: [2, c] (means, then stds); _mcc: [c]

// AdaIN: out = alpha (sigma_s (x - mu_c) / sigma_c + mu_s) + (1 - alpha) x; mode normalise:
// out = (x - mu_c) / sigma_c (style statistics unused; bind any buffer).
#define S4D_NN_ADAIN_BLEND 0u
#define S4D_NN_ADAIN_NORMALISE 1u
#define S4D_B_ADAIN_IN 0            // [c, count]
#define S4D_B_ADAIN_CONTENT_STATS 1 // [2, c]
#define S4D_B_ADAIN_STYLE_STATS 2   // [2, c]
#define S4D_B_ADAIN_OUT 3           // [c, count]

// AdaAttN's attention (Liu et al. 2021) over one chunk of content positions, in three passes so no
// invocation loops past S4D_NN_MAX_LOOP and the score matrix of a chunk fits one storage buffer:
// nn_attn_scores: S[i, j] = sum_k Q[k, first + i] K[k, j] (one invocation per score, loops over the
// key channels); nn_softmax_rows: each row of S replaced by its softmax (one workgroup per row,
// shared-memory reductions, so no subgroup size is assumed); nn_attn_apply: with the weights P,
// M = sum_j P[i, j] V[c, j], S = sqrt(relu(sum_j P[i, j] V[c, j]^2 - M^2)) and
// out[c, first + i] = S * content[c, first + i] + M (one invocation per output, loops over the
// style positions).
#define S4D_NN_SOFTMAX_WG 64
#define S4D_B_ATTN_Q 0        // nn_attn_scores: [dk, n_c] queries
#define S4D_B_ATTN_K 1        // [dk, n_s] keys
#define S4D_B_ATTN_SCORES 2   // [chunk, n_s]
#define S4D_B_SOFTMAX_DATA 0  // nn_softmax_rows: [chunk, n_s], in place
#define S4D_B_ATTN_P 0        // nn_attn_apply: [chunk, n_s] attention weights
#define S4D_B_ATTN_V 1        // [c, n_s] values
#define S4D_B_ATTN_CONTENT 2  // [c, n_c] normalised content features
#define S4D_B_ATTN_OUT 3      // [c, n_c]; the chunk's columns are written

// Vision transformer pieces (DINO ViT, training/kernels/nn/dino_vit.h). Tokens are a [C, 1, N] tensor: one
// column per token, the class token first, so 1x1 convolutions are the Linear layers.
// nn_layernorm: LayerNorm over the channels of each token (PyTorch LayerNorm(C, eps)): mean, then
// the centred biased variance, one invocation per token looping over C three times.
#define S4D_B_LN_IN 0      // [c, count]
#define S4D_B_LN_WEIGHT 1  // [c]
#define S4D_B_LN_BIAS 2    // [c]
#define S4D_B_LN_OUT 3     // [c, count]
// nn_gelu: x = x Phi(x) in place, Phi the normal CDF (PyTorch GELU(approximate='none')), through
// erfc of Abramowitz & Stegun 7.1.26 (absolute error under 1.5e-7), so x < 0 keeps its small values.
#define S4D_B_GELU_DATA 0  // [n], in place
// nn_vit_embed: out[c, 0] = pos[c, 0] and out[c, t] = patches[c, t - 1] + pos[c, t] for t >= 1,
// where the host folds the class token into pos[:, 0] (NnEltParams: n = c * tokens, count = tokens).
// nn_prepend_token (the same file): out[c, 0] = pos[c], out[c, t] = patches[c, t - 1], no embedding.
#define S4D_B_VIT_PATCHES 0  // [c, tokens - 1]: the patch embedding's [c, gh, gw]
#define S4D_B_VIT_POS 1      // [c, tokens]; nn_prepend_token: [c], the first token only
#define S4D_B_VIT_OUT 2      // [c, tokens]
// nn_attn_average (nn_attn_apply with S4D_NN_ATTN_AVERAGE): out[c, first + i] = sum_j P[i, j] V[c, j],
// the attention of a transformer, bindings S4D_B_ATTN_P, S4D_B_ATTN_V and S4D_B_ATTN_AVG_OUT (no content).
#define S4D_B_ATTN_AVG_OUT 2  // [c, n_c]; the chunk's columns are written
// nn_transpose: out[c, r] = in[r, c] of a [rows, cols] matrix (NnEltParams: n = rows * cols, count = cols);
// the transformer's attention multiplies through nn_conv1x1 with it (scores = conv1x1 of the keys by
// the transposed queries, output = conv1x1 of the transposed weights by the values).
#define S4D_B_TRANSPOSE_IN 0   // [rows, cols]
#define S4D_B_TRANSPOSE_OUT 1  // [cols, rows]

// nn_group_norm (MUSIQ's patch stem, training/kernels/nn/musiq_net.h): a batch of small images stacked along
// H in cells of cell_h rows (height a multiple of cell_h), each normalised on its own: GroupNorm over
// the window rows [row0, row0 + rows) x cols [col0, col0 + cols) of the cell (biased variance, then
// weight, bias; S4D_NN_FLAG_RELU: ReLU), every value outside the window set to 0 so it is the zero
// padding of the next convolution. Bindings as nn_layernorm's.
#define S4D_B_GN_IN 0      // [c, height, width]
#define S4D_B_GN_WEIGHT 1  // [c]
#define S4D_B_GN_BIAS 2    // [c]
#define S4D_B_GN_OUT 3     // [c, height, width]

S4D_NAMESPACE_BEGIN

// Push constants of nn_attn_scores, nn_softmax_rows and nn_attn_apply.
struct NnAttnParams {
  uint channels;  // key channels (scores) or value channels (apply)
  uint n_c;       // content positions
  uint n_s;       // style positions
  uint first;     // the chunk's first content position
  uint chunk;     // content positions in the chunk
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Push constants of nn_conv3x3 (reflection padding 1) and nn_conv1x1.
struct NnConvParams {
  uint cin;
  uint cout;
  uint height;
  uint width;
  uint tiles_x;  // ceil(width / (S4D_NN_CONV_WG_X * S4D_NN_CONV_PIX))
  uint tiles_y;  // ceil(height / S4D_NN_CONV_WG_Y)
  uint flags;    // S4D_NN_FLAG_*
  uint _pad0;
};

// Push constants of nn_conv_strided: out = floor((in + 2 pad - kernel) / stride) + 1 per side.
struct NnConvStridedParams {
  uint cin;
  uint cout;
  uint in_height;
  uint in_width;
  uint out_height;
  uint out_width;
  uint kernel;
  uint stride;
  uint pad;
  uint flags;  // S4D_NN_FLAG_RELU
  uint n_out;  // cout * out_height * out_width
  uint _pad0;
};

// Push constants of nn_relu and nn_scale_channels (count: values per channel).
struct NnEltParams {
  uint n;
  uint count;
  uint _pad0;
  uint _pad1;
};

// Push constants of nn_blend (alpha, 1 - alpha: a blend; 1, 1: a sum).
struct NnBlendParams {
  uint n;
  float alpha;
  float beta;
  uint _pad0;
};

// Push constants of nn_maxpool (2x2, stride 2, ceil or floor mode by the output size),
// nn_maxpool3s2 (3x3, stride 2, floor mode, zero (AlexNet) or one (ResNet) padding row and column
// per side that no window takes its maximum from), nn_l2pool (3x3 Hann window, stride 2),
// nn_upsample (nearest, x2), nn_subsample2 (x[c, 2y, 2x]) and nn_resize_nearest (any size).
struct NnResizeParams {
  uint channels;
  uint in_height;
  uint in_width;
  uint out_height;
  uint out_width;
  uint n_out;  // channels * out_height * out_width
  uint pad;    // nn_maxpool3s2's padding (0 or 1); 0 for the others
  uint _pad1;
};

// Push constants of nn_channel_stats and nn_channel_stats_mcc.
struct NnStatsParams {
  uint channels;
  uint count;  // values per channel (H * W)
  float eps;   // added to the variance
  uint _pad0;
};

// Push constants of nn_adain.
struct NnAdainParams {
  uint channels;
  uint count;
  float alpha;
  uint mode;  // S4D_NN_ADAIN_*
};

// Push constants of nn_group_norm.
struct NnGroupNormParams {
  uint channels;
  uint groups;  // divides channels
  uint height;  // cells * cell_h
  uint width;
  uint cell_h;
  uint row0;  // the window in each cell
  uint rows;
  uint col0;
  uint cols;
  uint flags;  // S4D_NN_FLAG_RELU
  float eps;
  uint _pad0;
};

S4D_NAMESPACE_END

#endif  // S4D_NN_H
