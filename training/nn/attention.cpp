#include "s4d/nn/attention.h"

#include <algorithm>
#include <stdexcept>
#include <string>

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

// The chunked attention of q over k, v, with AdaAttN's statistics applied to `content` or (null)
// the plain weighted average.
Tensor chunked(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v, const Tensor* content,
               size_t max_score_bytes) {
  if (k.h != v.h || k.w != v.w || (content != nullptr && (q.h != content->h || q.w != content->w)))
    fail("queries " + q.shape() + (content != nullptr ? " / content " + content->shape() : std::string()) + " or keys " +
         k.shape() + " / values " + v.shape() + " differ in size");
  const size_t row_bytes = k.plane() * sizeof(float);
  const size_t budget = std::min<size_t>(max_score_bytes, rec.context().info().max_storage_buffer_range);
  if (row_bytes > budget) fail(std::to_string(k.plane()) + " style positions: one score row is over the budget");
  const auto chunk = static_cast<uint32_t>(std::min<size_t>(q.plane(), budget / row_bytes));
  Tensor out = make_tensor(rec.context(), "attention", v.c, q.h, q.w);
  for (uint32_t first = 0; first < q.plane(); first += chunk) {
    const auto rows = static_cast<uint32_t>(std::min<size_t>(chunk, q.plane() - first));
    Tensor s = attention_scores(rec, q, k, first, rows);
    softmax_rows(rec, s);
    apply_rows(rec, s, v, content, first, out);
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
  return chunked(rec, q, k, v, &content, max_score_bytes);
}

Tensor transformer_attention(engine::Recorder& rec, const Tensor& q, const Tensor& k, const Tensor& v,
                             size_t max_score_bytes) {
  return chunked(rec, q, k, v, nullptr, max_score_bytes);
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
