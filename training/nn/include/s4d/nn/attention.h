// AdaAttN's attention (Liu et al. 2021; kernels nn_attn_scores, nn_softmax_rows, nn_attn_apply,
// and a transformer's, nn_attn_average in place of nn_attn_apply;
// twins in ref/nn_ref.h): for content positions i and style positions j, P = softmax_j(Q_i . K_j),
// M = P V, S = sqrt(relu(P V^2 - M^2)), out = S * content + M. The score matrix is built for a chunk
// of content positions at a time, so it fits one storage buffer whatever the content size.
#pragma once
#include <cstddef>
#include <cstdint>

#include "s4d/engine/recorder.h"
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
// softmax_j(q_i . k_j) v_j over all positions i of q (scale q beforehand), chunked as attention():
// [v.c, q.h, q.w]. Needs dk and the key positions <= S4D_NN_MAX_LOOP.
Tensor transformer_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v,
                             size_t max_score_bytes = size_t{64} << 20);

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
