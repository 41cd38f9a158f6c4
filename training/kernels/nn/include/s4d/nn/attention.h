// AdaAttN's attention (Liu et al. 2021; kernels nn_attn_scores, nn_softmax_rows, nn_attn_apply,
// and a transformer's, nn_attn_average in place of nn_attn_apply, or nn_transpose and nn_conv1x1;
// twins in ref/nn_ref.h): for content positions i and style positions j, P = softmax_j(Q_i . K_j),
// M = P V, S = sqrt(relu(P V^2 - M^2)), out = S * content + M. The score matrix is built for a chunk
// of content positions at a time, so it fits one storage buffer whatever the content size.
#pragma once
#include <cstddef>
#include <cstdint>

#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// [1, rows, n_s]: scores[i, j] = sum_k q[k, first + i] k[k, j]; q [dk, h, w], k [dk, hs, ws].
Tensor attention_scores(engine::Recorder& rec, const Tensor& q, const Tensor& k, uint32_t first, uint32_t rows);
// Each row (h) of a [1, rows, n] tensor replaced by its softmax over n, in place.
void softmax_rows(engine::Recorder& rec, Tensor& scores);
// out[:, first + i] = S * content + M for the rows i of the weights p [1, rows, n_s], with v
// [c, hs, ws] and content, out [c, h, w].
void attention_apply(engine::Recorder& rec, const Tensor& p, const Tensor& v, const Tensor& content, uint32_t first,
                     Tensor& out);

// out[:, first + i] = sum_j p[i, j] v[:, j] for the rows i of p [1, rows, n_s], v [c, hs, ws], out
// [c, h, w]: a transformer's attention output.
void attention_average(engine::Recorder& rec, const Tensor& p, const Tensor& v, uint32_t first, Tensor& out);
// The transpose [1, cols, rows] of a [1, rows, cols] matrix (kernel nn_transpose).
Tensor transpose(engine::Recorder& rec, const Tensor& x);

// softmax_j(q_i . k_j) v_j over all positions i of q (scale q beforehand), chunked as attention():
// [v.c, q.h, q.w]. Multiplies through the tiled nn_conv1x1: scores = conv1x1 of k by q^T, the output
// conv1x1 of the transposed weights by v (nn_transpose). Needs dk and the key positions <= S4D_NN_MAX_LOOP.
Tensor transformer_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v,
                             size_t max_score_bytes = size_t{64} << 20);

// One pre-norm transformer encoder block of a ViT (DINO's Block, MUSIQ's TransformerBlock):
// x += proj(MHSA(LayerNorm1(x))), x += fc2(GELU(fc1(LayerNorm2(x)))), on tokens [width, 1, n]. The
// attention is softmax((q k^T) / sqrt(head width)) v per head, with the scale folded into qkv's
// query rows (upload_qkv).
struct TransformerBlock {
  NormWeights norm1, norm2;
  ConvWeights qkv, proj, fc1, fc2;  // qkv [3 width, width]: query, key, value rows
};

// The Linear(width, 3 width) of q, k and v (weight [3 width, width], bias [3 width]) with the query
// rows and biases multiplied by 1 / sqrt(width / heads): (s q) . k = s (q . k). Throws
// std::invalid_argument when heads do not divide the width or the counts differ.
ConvWeights upload_qkv(engine::Context& ctx, const std::string& name, uint32_t width, uint32_t heads,
                       std::vector<float> weight, std::vector<float> bias);

// The block on tokens x [width, 1, n] with `heads` heads and LayerNorm eps; returns x updated.
Tensor transformer_block(engine::Recorder& rec, const TransformerBlock& b, uint32_t heads, float eps, Tensor x);
// Multi-head attention: the channels of q [d, 1, nq] and of k, v [d, 1, n] split into `heads` equal
// groups, transformer_attention of each group (scale q beforehand), the heads' outputs stacked again
// in order: [d, 1, nq] (DINO's ViT blocks, CLIP's attention pooling). Needs d / heads and n <=
// S4D_NN_MAX_LOOP; throws std::invalid_argument when the heads do not divide d or the shapes differ.
Tensor multi_head_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, uint32_t heads);

// The whole attention over content positions in chunks whose scores take at most
// `max_score_bytes` (and the device's storage-buffer range). Needs dk and n_s <= S4D_NN_MAX_LOOP.
Tensor attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, const Tensor& content,
                 size_t max_score_bytes = size_t{64} << 20);

}  // namespace s4d::nn
