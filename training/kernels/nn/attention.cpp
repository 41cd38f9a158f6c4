#include "s4d/nn/attention.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/engine/buffer_from.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("attention: " + what); }

// llvmpipe silently ends invocations past 65,535 loop iterations (s4d_nn.h).
void check_loop(uint64_t iterations, const std::string& what) {
  if (iterations > S4D_NN_MAX_LOOP)
    fail(what + " " + std::to_string(iterations) + " is over the " + std::to_string(S4D_NN_MAX_LOOP) +
         " loop iterations the kernels allow");
}

gpu::NnAttnParams params(uint32_t channels, size_t n_c, size_t n_s, uint32_t first, uint32_t rows) {
  return {.channels = channels,
          .n_c = static_cast<uint32_t>(n_c),
          .n_s = static_cast<uint32_t>(n_s),
          .first = first,
          .chunk = rows,
          ._pad0 = 0,
          ._pad1 = 0,
          ._pad2 = 0};
}

void check_rows(const Tensor& x, uint32_t first, uint32_t rows) {
  if (rows == 0 || uint64_t{first} + rows > x.plane())
    fail("rows " + std::to_string(first) + "+" + std::to_string(rows) + " outside " + x.shape());
}

}  // namespace

Tensor attention_scores(engine::Recorder& rec, const Tensor& q, const Tensor& k, uint32_t first, uint32_t rows) {
  if (q.c != k.c) fail("queries " + q.shape() + " and keys " + k.shape() + " differ in channels");
  check_rows(q, first, rows);
  check_loop(q.c, "key channels");
  Tensor s = make_tensor(rec.context(), "attention scores", 1, rows, static_cast<uint32_t>(k.plane()));
  const auto p = params(q.c, q.plane(), k.plane(), first, rows);
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_attn_scores),
               {S4D_BIND(ATTN_Q, q.buffer), S4D_BIND(ATTN_K, k.buffer), S4D_BIND(ATTN_SCORES, s.buffer)}, p,
               ceil_div(s.count(), S4D_NN_WG));
  rec.barrier();
  return s;
}

void softmax_rows(engine::Recorder& rec, Tensor& scores) {
  if (scores.c != 1) fail("softmax expects [1, rows, n], got " + scores.shape());
  check_loop(3 * uint64_t{ceil_div(scores.w, S4D_NN_SOFTMAX_WG)}, "softmax row passes");
  const auto p = params(0, 0, scores.w, 0, scores.h);
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_softmax_rows), {S4D_BIND(SOFTMAX_DATA, scores.buffer)}, p,
               scores.h);
  rec.barrier();
}

namespace {

// nn_attn_apply with the content, nn_attn_average without.
void apply_rows(engine::Recorder& rec, const Tensor& p, const Tensor& v, const Tensor* content, uint32_t first, Tensor& out) {
  if (p.c != 1 || p.w != v.plane())
    fail("weights " + p.shape() + " do not match values " + v.shape());
  const Tensor& rows_of = content != nullptr ? *content : out;
  if (rows_of.c != v.c || out.c != v.c || out.h != rows_of.h || out.w != rows_of.w)
    fail("values " + v.shape() + ", content " + rows_of.shape() + " and output " + out.shape() + " do not match");
  check_rows(rows_of, first, p.h);
  check_loop(p.w, "style positions");
  const auto pc = params(v.c, rows_of.plane(), v.plane(), first, p.h);
  if (content != nullptr)
    rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_attn_apply),
                 {S4D_BIND(ATTN_P, p.buffer), S4D_BIND(ATTN_V, v.buffer), S4D_BIND(ATTN_CONTENT, content->buffer),
                  S4D_BIND(ATTN_OUT, out.buffer)},
                 pc, ceil_div(size_t{v.c} * p.h, S4D_NN_WG));
  else
    rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_attn_average),
                 {S4D_BIND(ATTN_P, p.buffer), S4D_BIND(ATTN_V, v.buffer), S4D_BIND(ATTN_AVG_OUT, out.buffer)}, pc,
                 ceil_div(size_t{v.c} * p.h, S4D_NN_WG));
  rec.barrier();
}

// The chunked attention of q over k, v, with AdaAttN's statistics applied to `content`.
Tensor chunked(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, const Tensor& content,
               size_t max_score_bytes) {
  if (k.h != v.h || k.w != v.w || q.h != content.h || q.w != content.w)
    fail("queries " + q.shape() + " / content " + content.shape() + " or keys " + k.shape() + " / values " + v.shape() +
         " differ in size");
  const size_t row_bytes = k.plane() * sizeof(float);
  const size_t budget = std::min<size_t>(max_score_bytes, rec.context().info().max_storage_buffer_range);
  if (row_bytes > budget) fail(std::to_string(k.plane()) + " style positions: one score row is over the budget");
  const auto chunk = static_cast<uint32_t>(std::min<size_t>(q.plane(), budget / row_bytes));
  Tensor out = make_tensor(rec.context(), "attention", v.c, q.h, q.w);
  for (uint32_t first = 0; first < q.plane(); first += chunk) {
    const auto rows = static_cast<uint32_t>(std::min<size_t>(chunk, q.plane() - first));
    Tensor s = attention_scores(rec, q, k, first, rows);
    softmax_rows(rec, s);
    apply_rows(rec, s, v, &content, first, out);
  }
  return out;
}

}  // namespace

void attention_apply(engine::Recorder& rec, const Tensor& p, const Tensor& v, const Tensor& content, uint32_t first,
                     Tensor& out) {
  apply_rows(rec, p, v, &content, first, out);
}

void attention_average(engine::Recorder& rec, const Tensor& p, const Tensor& v, uint32_t first, Tensor& out) {
  apply_rows(rec, p, v, nullptr, first, out);
}

Tensor attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, const Tensor& content,
                 size_t max_score_bytes) {
  return chunked(rec, q, k, v, content, max_score_bytes);
}

namespace {

// The transpose [cols, 1, rows] of the [rows, cols] matrix in `in` (kernel nn_transpose).
Tensor transposed(engine::Recorder& rec, const engine::Buffer& in, uint32_t rows, uint32_t cols, const std::string& name) {
  Tensor y = make_tensor(rec.context(), name, cols, 1, rows);
  const gpu::NnEltParams p{.n = static_cast<uint32_t>(y.count()), .count = cols, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_transpose),
               {S4D_BIND(TRANSPOSE_IN, in), S4D_BIND(TRANSPOSE_OUT, y.buffer)}, p, ceil_div(y.count(), S4D_NN_WG));
  rec.barrier();
  return y;
}

// A 1x1 convolution's parameters over `bytes` of `from` (at `offset`), with the zero bias `zeros`.
ConvWeights matrix(engine::Recorder& rec, const engine::Buffer& from, size_t offset, uint32_t cin, uint32_t cout,
                   engine::Buffer zeros, const std::string& name) {
  ConvWeights w{name, cin, cout, 1, engine::Buffer(rec.context(), name, size_t{cin} * cout * sizeof(float)), std::move(zeros)};
  rec.copy(from, w.weight, size_t{cin} * cout * sizeof(float), offset);
  rec.barrier();
  return w;
}

}  // namespace

Tensor transpose(engine::Recorder& rec, const Tensor& x) {
  if (x.c != 1) fail("transpose expects a [1, rows, cols] matrix, got " + x.shape());
  Tensor y = transposed(rec, x.buffer, x.h, x.w, "transpose");
  y.c = 1;
  y.h = x.w;
  y.w = x.h;
  return y;
}

Tensor transformer_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v,
                             size_t max_score_bytes) {
  // Through the tiled nn_conv1x1 (nn_attn_scores and nn_attn_average loop per output, slow on lavapipe
  // past a few hundred tokens): scores S [rows, n_k] = conv1x1 of k with weights q^T [rows, dk];
  // out [dv, rows] = conv1x1 of S^T [n_k, rows] with weights v [dv, n_k].
  if (q.c != k.c || k.h != v.h || k.w != v.w)
    fail("queries " + q.shape() + ", keys " + k.shape() + " and values " + v.shape() + " do not match");
  const auto n_q = static_cast<uint32_t>(q.plane()), n_k = static_cast<uint32_t>(k.plane());
  check_loop(q.c, "key channels");
  check_loop(n_k, "key positions");
  const size_t row_bytes = size_t{n_k} * sizeof(float);
  const size_t budget = std::min<size_t>(max_score_bytes, rec.context().info().max_storage_buffer_range);
  if (row_bytes > budget) fail(std::to_string(n_k) + " key positions: one score row is over the budget");
  const auto chunk = static_cast<uint32_t>(std::min<size_t>(n_q, budget / row_bytes));
  engine::Context& ctx = rec.context();
  const Tensor qt = transposed(rec, q.buffer, q.c, n_q, "queries^T");  // [n_q, 1, dk]
  ConvWeights values = matrix(rec, v.buffer, 0, n_k, v.c, engine::buffer_from(ctx, "zero bias", std::vector<float>(v.c, 0.0f)),
                              "attention values");
  engine::Buffer zeros = engine::buffer_from(ctx, "zero bias", std::vector<float>(chunk, 0.0f));
  Tensor out = make_tensor(ctx, "attention", v.c, q.h, q.w);
  for (uint32_t first = 0; first < n_q; first += chunk) {
    const auto rows = static_cast<uint32_t>(std::min<size_t>(chunk, n_q - first));
    ConvWeights queries = matrix(rec, qt.buffer, size_t{first} * q.c * sizeof(float), q.c, rows, std::move(zeros), "attention queries");
    Tensor s = conv1x1(rec, k, queries, false);
    zeros = std::move(queries.bias);
    s.c = 1;  // [rows, n_k] as softmax_rows' [1, rows, n]
    s.h = rows;
    s.w = n_k;
    softmax_rows(rec, s);
    Tensor o = conv1x1(rec, transposed(rec, s.buffer, rows, n_k, "attention weights^T"), values, false);  // [dv, 1, rows]
    if (rows == n_q) {
      o.h = q.h;
      o.w = q.w;
      return o;
    }
    for (uint32_t c = 0; c < v.c; ++c)
      rec.copy(o.buffer, out.buffer, size_t{rows} * sizeof(float), size_t{c} * rows * sizeof(float),
               (size_t{c} * n_q + first) * sizeof(float));
  }
  rec.barrier();
  return out;
}

ConvWeights upload_qkv(engine::Context& ctx, const std::string& name, uint32_t width, uint32_t heads,
                       std::vector<float> weight, std::vector<float> bias) {
  if (heads == 0 || width % heads != 0)
    fail(name + ": width " + std::to_string(width) + " does not split into " + std::to_string(heads) + " heads");
  if (weight.size() != size_t{3} * width * width || bias.size() != size_t{3} * width)
    fail(name + ": " + std::to_string(weight.size()) + " weights and " + std::to_string(bias.size()) +
         " biases for q, k, v of width " + std::to_string(width));
  // Exact for 64-wide heads (a power of two); otherwise within float rounding of PyTorch's order.
  const float scale = 1.0f / std::sqrt(float(width / heads));
  for (size_t k = 0; k < size_t{width} * width; ++k) weight[k] *= scale;
  for (size_t k = 0; k < width; ++k) bias[k] *= scale;
  return upload_conv(ctx, name, width, 3 * width, 1, weight, bias);
}

Tensor transformer_block(engine::Recorder& rec, const TransformerBlock& b, uint32_t heads, float eps, Tensor x) {
  const uint32_t d = x.c, n = x.w;
  if (x.h != 1 || b.qkv.cin != d || b.qkv.cout != 3 * d || d % heads != 0)
    fail("transformer block " + b.qkv.name + " of width " + std::to_string(b.qkv.cin) + " with " + std::to_string(heads) +
         " heads cannot take tokens " + x.shape());
  const Tensor qkv = conv1x1(rec, layernorm(rec, x, b.norm1, eps), b.qkv, false);
  std::array<Tensor, 3> parts;  // q, k and v: consecutive runs of qkv's channels
  for (uint32_t part = 0; part < 3; ++part) {
    parts[part] = make_tensor(rec.context(), "attention q/k/v", d, 1, n);
    rec.copy(qkv.buffer, parts[part].buffer, parts[part].count() * sizeof(float), size_t{part} * parts[part].count() * sizeof(float));
  }
  rec.barrier();
  const Tensor out = multi_head_attention(rec, parts[0], parts[1], parts[2], heads);
  conv1x1_accumulate(rec, out, b.proj, x);
  Tensor hidden = conv1x1(rec, layernorm(rec, x, b.norm2, eps), b.fc1, false);
  gelu_inplace(rec, hidden);
  conv1x1_accumulate(rec, hidden, b.fc2, x);
  return x;
}

Tensor multi_head_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, uint32_t heads) {
  const uint32_t d = q.c;
  if (heads == 0 || d % heads != 0 || k.c != d || v.c != d || q.h != 1 || k.h != 1 || v.h != 1 || k.w != v.w)
    throw std::invalid_argument("multi_head_attention: " + std::to_string(heads) + " heads over q " + q.shape() + ", k " +
                                k.shape() + ", v " + v.shape() + " (needs [d, 1, nq], [d, 1, n], [d, 1, n], heads dividing d)");
  const uint32_t dh = d / heads;
  // Head h is channels h dh .. (h + 1) dh - 1: one contiguous run of each [d, 1, n] buffer.
  const auto head = [&](const Tensor& t, uint32_t h) {
    Tensor part = make_tensor(rec.context(), "attention head", dh, 1, t.w);
    rec.copy(t.buffer, part.buffer, part.count() * sizeof(float), size_t{h} * part.count() * sizeof(float));
    return part;
  };
  Tensor out = make_tensor(rec.context(), "attention heads", d, 1, q.w);
  const size_t head_bytes = size_t{dh} * q.w * sizeof(float);
  for (uint32_t h = 0; h < heads; ++h) {
    const Tensor qh = head(q, h), kh = head(k, h), vh = head(v, h);
    rec.barrier();
    const Tensor o = transformer_attention(rec, qh, kh, vh);
    rec.copy(o.buffer, out.buffer, head_bytes, 0, size_t{h} * head_bytes);
  }
  rec.barrier();
  return out;
}

}  // namespace s4d::nn
