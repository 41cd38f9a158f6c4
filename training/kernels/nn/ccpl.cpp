#include "s4d/nn/ccpl.h"

#include <algorithm>
#include <set>
#include <utility>

#include "layer_checks.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/nn/attention.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_nn_ccpl.h"

namespace s4d::nn {

namespace {

using detail::check_loop;
using detail::fail;
using primitives::ceil_div;
using primitives::shader_pipeline;

void check_columns(const char* layer, const Tensor& x) {
  if (x.h != 1 || x.w < 1) fail(layer, "expects columns [c, 1, s], got " + x.shape());
}

// The pairs buffer's sample count, checked against a tensor of s columns.
void check_pairs(const char* layer, const engine::Buffer& pairs, uint32_t samples) {
  if (pairs.size() < 2 * size_t{samples} * sizeof(uint32_t))
    fail(layer, "pairs '" + pairs.name() + "' hold fewer than 2 x " + std::to_string(samples) + " indices");
}

}  // namespace

CcplSamples draw_ccpl_samples(uint32_t h, uint32_t w, int anchors, bool jitter, std::mt19937_64& rng) {
  if (h < 3 || w < 3) throw std::invalid_argument("ccpl: a level of " + std::to_string(h) + "x" + std::to_string(w) + " has no interior position");
  if (anchors < 1 || uint64_t(anchors) > uint64_t{h - 2} * (w - 2))
    throw std::invalid_argument("ccpl: " + std::to_string(anchors) + " anchors on a " + std::to_string(h) + "x" + std::to_string(w) +
                                " level, which has " + std::to_string((h - 2) * (w - 2)) + " interior positions");
  std::uniform_int_distribution<uint32_t> row(1, h - 2), col(1, w - 2);
  std::uniform_int_distribution<int> shake(-1, 1);
  const int64_t plane = int64_t{h} * w, iw = w;
  const int64_t offsets[8] = {-iw - 1, -iw, -iw + 1, -1, 1, iw - 1, iw, iw + 1};
  CcplSamples s;
  std::set<uint32_t> taken;
  while (taken.size() < size_t(anchors)) {  // distinct anchors, drawn again on a repeat (CCPL's label map)
    const uint32_t y = row(rng), x = col(rng), at = y * w + x;
    if (!taken.insert(at).second) continue;
    for (const int64_t o : offsets) {
      const int64_t n = std::clamp<int64_t>(at + o + (jitter ? shake(rng) : 0), 0, plane - 1);
      s.anchor.push_back(at);
      s.neighbour.push_back(static_cast<uint32_t>(n));
    }
  }
  return s;
}

Tensor ccpl_gather(engine::Recorder& rec, const Tensor& f, const engine::Buffer& pairs, uint32_t samples) {
  check_pairs("ccpl gather", pairs, samples);
  Tensor out = make_tensor(rec.context(), "ccpl differences", f.c, 1, samples);
  const gpu::NnCcplParams p{.channels = f.c, .plane = static_cast<uint32_t>(f.plane()), .samples = samples, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_ccpl_gather),
               {S4D_BIND(CCPL_F, f.buffer), S4D_BIND(CCPL_PAIRS, pairs), S4D_BIND(CCPL_OUT, out.buffer)}, p,
               ceil_div(out.count(), S4D_NN_WG));
  rec.barrier();
  return out;
}

void ccpl_gather_backward(engine::Recorder& rec, const Tensor& dout, const engine::Buffer& pairs, Tensor& df) {
  check_columns("ccpl gather backward", dout);
  if (dout.c != df.c) fail("ccpl gather backward", "gradients " + dout.shape() + " and " + df.shape() + " differ in channels");
  check_pairs("ccpl gather backward", pairs, dout.w);
  check_loop("ccpl gather backward", dout.w, "samples " + std::to_string(dout.w));
  const gpu::NnCcplParams p{.channels = df.c, .plane = static_cast<uint32_t>(df.plane()), .samples = dout.w, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_ccpl_gather_bwd),
               {S4D_BIND(CCPL_F, df.buffer), S4D_BIND(CCPL_PAIRS, pairs), S4D_BIND(CCPL_OUT, dout.buffer)}, p,
               ceil_div(df.count(), S4D_NN_WG));
  rec.barrier();
}

Tensor l2norm_columns(engine::Recorder& rec, const Tensor& x) {
  check_columns("l2norm columns", x);
  check_loop("l2norm columns", 2 * uint64_t{x.c}, "channels " + std::to_string(x.c));
  Tensor y = make_tensor(rec.context(), "l2-normalised", x.c, 1, x.w);
  const gpu::NnCcplParams p{.channels = x.c, .plane = 0, .samples = x.w, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_l2norm_cols), {S4D_BIND(L2N_X, x.buffer), S4D_BIND(L2N_Y, y.buffer)},
               p, ceil_div(x.w, S4D_NN_WG));
  rec.barrier();
  return y;
}

Tensor l2norm_columns_backward(engine::Recorder& rec, const Tensor& x, const Tensor& dy) {
  check_columns("l2norm columns backward", x);
  if (dy.c != x.c || dy.h != x.h || dy.w != x.w) fail("l2norm columns backward", "shapes " + x.shape() + " and " + dy.shape() + " differ");
  check_loop("l2norm columns backward", 3 * uint64_t{x.c}, "channels " + std::to_string(x.c));
  Tensor dx = make_tensor(rec.context(), "d l2norm", x.c, 1, x.w);
  const gpu::NnCcplParams p{.channels = x.c, .plane = 0, .samples = x.w, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_l2norm_cols_bwd),
               {S4D_BIND(L2N_X, x.buffer), S4D_BIND(L2N_Y, dy.buffer), S4D_BIND(L2N_DX, dx.buffer)}, p, ceil_div(x.w, S4D_NN_WG));
  rec.barrier();
  return dx;
}

PatchNce patchnce(engine::Recorder& rec, const Tensor& scores, float tau, float scale) {
  if (scores.c != 1 || scores.h != scores.w) fail("patchnce", "expects square scores [1, s, s], got " + scores.shape());
  check_loop("patchnce", 4 * uint64_t{scores.w}, "rows of " + std::to_string(scores.w));
  if (!(tau > 0)) fail("patchnce", "needs a positive temperature");
  PatchNce out{engine::Buffer(rec.context(), "patchnce losses", size_t{scores.h} * sizeof(float)),
               make_tensor(rec.context(), "d scores", 1, scores.h, scores.w)};
  const gpu::NnPatchNceParams p{.samples = scores.w, .inv_tau = 1.0f / tau, .scale = scale, ._pad0 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::nn_patchnce),
               {S4D_BIND(PNCE_SCORES, scores.buffer), S4D_BIND(PNCE_GRAD, out.grad.buffer), S4D_BIND(PNCE_LOSS, out.loss)}, p,
               ceil_div(scores.h, S4D_NN_WG));
  rec.barrier();
  return out;
}

engine::Buffer record_ccpl_level(engine::Recorder& rec, const CcplHead& head, const Tensor& fq, const Tensor& fk,
                                 const CcplSamples& samples, float tau, float weight, Tensor& dfq, ConvGrads* head_grads) {
  const char* layer = "ccpl";
  if (fq.c != fk.c || fq.h != fk.h || fq.w != fk.w || dfq.c != fq.c || dfq.h != fq.h || dfq.w != fq.w)
    fail(layer, "q " + fq.shape() + ", k " + fk.shape() + " and dq " + dfq.shape() + " differ");
  if (head.first.cin != fq.c || head.first.cout != fq.c || head.second.cin != fq.c || head.first.k != 1 || head.second.k != 1)
    fail(layer, "head " + head.first.name + " is not Linear(" + std::to_string(fq.c) + ", " + std::to_string(fq.c) + ")");
  const auto s = static_cast<uint32_t>(samples.anchor.size());
  if (s < 2 || samples.neighbour.size() != s) fail(layer, "needs at least 2 samples with one neighbour each");
  std::vector<uint32_t> pairs(samples.anchor);
  pairs.insert(pairs.end(), samples.neighbour.begin(), samples.neighbour.end());
  for (const uint32_t i : pairs)
    if (i >= fq.plane()) fail(layer, "sample index " + std::to_string(i) + " outside the level " + fq.shape());
  const engine::Buffer pair_buffer = engine::buffer_from(rec.context(), "ccpl pairs", pairs);

  struct Side {
    Tensor diff, hidden, proj, z;
  };
  auto forward = [&](const Tensor& f) {
    Side side{ccpl_gather(rec, f, pair_buffer, s), {}, {}, {}};
    side.hidden = conv1x1(rec, side.diff, head.first, true);
    side.proj = conv1x1(rec, side.hidden, head.second, false);
    side.z = l2norm_columns(rec, side.proj);
    return side;
  };
  const Side q = forward(fq), k = forward(fk);
  PatchNce nce = patchnce(rec, attention_scores(rec, q.z, k.z, 0, s), tau, weight / static_cast<float>(s));
  if (weight == 0.0f && head_grads == nullptr) return std::move(nce.loss);  // logged only: every gradient is 0
  // Through the head back to the differences, with the heads' gradients where they are trained.
  auto backward = [&](const Side& side, const Tensor& grad_rows, const Tensor& other) {
    Tensor dz = make_tensor(rec.context(), "d ccpl z", other.c, 1, s);
    attention_average(rec, grad_rows, other, 0, dz);  // dz[:, i] = sum_j grad_rows[i, j] other[:, j]
    const Tensor dproj = l2norm_columns_backward(rec, side.proj, dz);
    if (head_grads != nullptr) conv_backward_weights(rec, side.hidden, dproj, head.second, head_grads[1], true);
    Tensor dhidden = conv_backward_input(rec, dproj, head.second);
    relu_backward(rec, dhidden, side.hidden);
    if (head_grads != nullptr) conv_backward_weights(rec, side.diff, dhidden, head.first, head_grads[0], true);
    return dhidden;
  };
  const Tensor dhidden_q = backward(q, nce.grad, k.z);
  ccpl_gather_backward(rec, conv_backward_input(rec, dhidden_q, head.first), pair_buffer, dfq);
  if (head_grads != nullptr) backward(k, transpose(rec, nce.grad), q.z);
  return std::move(nce.loss);
}

}  // namespace s4d::nn
