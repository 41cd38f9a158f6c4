#include "s4d/nn/mcc_loss.h"

#include <stdexcept>
#include <string>

namespace s4d::nn {

namespace {

// MSE(a, b) of two same-shaped tensors scaled by `weight`: its gradient 2 weight (a - b) / n added to da.
void mse_term(engine::Recorder& rec, MccLossRecord& record, MccLossRecord::Term term, const Tensor& a, const Tensor& b,
              Tensor& da, float weight) {
  if (a.count() != b.count()) throw std::invalid_argument("mcc loss: shapes " + a.shape() + " and " + b.shape() + " differ");
  const double n = static_cast<double>(a.count());
  record.add(term, squared_error(rec, a.buffer, b.buffer, da.buffer, a.count(), static_cast<float>(2.0 * weight / n)), 1.0 / n);
}

std::vector<Tensor> zero_level_grads(engine::Recorder& rec, const VggEncoder& enc, const std::vector<Tensor>& tape) {
  std::vector<Tensor> g;
  for (int l = 1; l <= enc.levels(); ++l) {
    const Tensor& f = tape[enc.level_step(l)];
    g.push_back(zero_tensor(rec, "level gradient", f.c, f.h, f.w));
  }
  return g;
}

// Decoder and MCC backward of one Dec(MCC(.)) pass given dL/d(image).
void backward_through(engine::Recorder& rec, const MccTrainee& net, const MccTape& mcc, const std::vector<Tensor>& dec,
                      const Tensor& dimage, MccGrads& grads) {
  const Tensor dfeatures = net.decoder.backward(rec, mcc.out, dec, dimage, grads.decoder);
  net.mcc.backward(rec, mcc, dfeatures, grads.mcc);
}

}  // namespace

void MccLossRecord::add(Term term, engine::Buffer partials, double factor) {
  parts_.push_back({term, std::move(partials), factor});
}

MccLossValues MccLossRecord::values(engine::Context& ctx, const MccLossWeights& weights) const {
  std::array<double, 8> sums{};
  for (const Part& p : parts_) sums[p.term] += p.factor * squared_error_value(ctx, p.partials);
  MccLossValues v{sums[content], sums[style], sums[identity1], sums[identity2], sums[noise], sums[tv], sums[selfsim], sums[ccpl], 0};
  v.total = weights.content * v.content + weights.style * v.style + weights.identity1 * v.identity1 +
            weights.identity2 * v.identity2 + weights.noise * v.noise + weights.tv * v.tv + weights.selfsim * v.selfsim +
            weights.ccpl * v.ccpl;
  return v;
}

MccGrads zero_mcc_grads(engine::Recorder& rec, const MccTrainee& net) {
  MccGrads g;
  for (const auto& [name, w] : net.decoder.parameters()) g.decoder.push_back(zero_conv_grads(rec, *w));
  for (const auto& [name, w] : net.mcc.parameters()) g.mcc.push_back(zero_conv_grads(rec, *w));
  return g;
}

MccLossRecord record_mcc_loss(engine::Recorder& rec, const MccTrainee& net, const Tensor& content, const Tensor& style,
                              const Tensor& content_noise, const MccLossLevels& levels, const MccLossWeights& weights,
                              const MccCcplInputs& ccpl, MccGrads& grads) {
  const VggEncoder& enc = net.encoder;
  if (enc.levels() != 5) throw std::invalid_argument("mcc loss: the encoder needs 5 levels, has " + std::to_string(enc.levels()));
  for (const std::vector<int>* list : {&levels.content, &levels.style})
    for (const int l : *list)
      if (l < 1 || l > 5) throw std::invalid_argument("mcc loss: level " + std::to_string(l) + " is not 1..5");
  if (content_noise.c != content.c || content_noise.h != content.h || content_noise.w != content.w)
    throw std::invalid_argument("mcc loss: the noisy content " + content_noise.shape() + " differs from the content " + content.shape());
  for (const Tensor* t : {&content, &style})
    if (t->c != 3 || t->h % 8 != 0 || t->w % 8 != 0 || t->h < 40 || t->w < 40)
      throw std::invalid_argument("mcc loss: images must be [3, H, W] with H, W multiples of 8 and at least 40, got " + t->shape());
  if (ccpl.heads != nullptr) {
    const size_t n = ccpl.config.levels.size();
    if (ccpl.heads->size() != n || ccpl.samples.size() != n || (ccpl.head_grads != nullptr && ccpl.head_grads->size() != 2 * n))
      throw std::invalid_argument("mcc loss: " + std::to_string(n) + " CCPL levels need as many heads and sample sets (and twice as many head gradients)");
    for (const int l : ccpl.config.levels)
      if (l < 1 || l > 5) throw std::invalid_argument("mcc loss: CCPL level " + std::to_string(l) + " is not 1..5");
  }
  MccLossRecord record;
  const std::vector<Tensor> fc = enc.forward_tape(rec, content), fs = enc.forward_tape(rec, style);
  auto level = [&](const std::vector<Tensor>& tape, int l) -> const Tensor& { return tape[enc.level_step(l)]; };

  // Ics: content and style losses; Ics_N: the noise loss, whose gradient reaches both.
  {
    const MccTape mcc = net.mcc.forward(rec, level(fc, 4), level(fs, 4));
    const std::vector<Tensor> dec = net.decoder.forward_tape(rec, mcc.out);
    const Tensor& ics = dec.back();
    const MccTape mcc_n = net.mcc.forward(rec, enc.encode(rec, content_noise, 4), level(fs, 4));
    const std::vector<Tensor> dec_n = net.decoder.forward_tape(rec, mcc_n.out);
    const Tensor& ics_n = dec_n.back();
    Tensor d_ics_n = zero_tensor(rec, "d noisy", ics.c, ics.h, ics.w), d_ics = zero_tensor(rec, "d noise", ics.c, ics.h, ics.w);
    mse_term(rec, record, MccLossRecord::noise, ics_n, ics, d_ics_n, weights.noise);
    // The same difference the other way round for Ics's gradient; its value is counted once.
    squared_error(rec, ics.buffer, ics_n.buffer, d_ics.buffer, ics.count(), static_cast<float>(2.0 * weights.noise / double(ics.count())));
    record.add(MccLossRecord::tv, tv_l1(rec, ics, d_ics, weights.tv), 1.0);
    const std::vector<Tensor> fi = enc.forward_tape(rec, ics);
    std::vector<Tensor> dlevels = zero_level_grads(rec, enc, fi);
    for (const int l : levels.content) {
      const Tensor& xi = level(fi, l);
      const engine::Buffer si = mean_std(rec, xi), sc = mean_std(rec, level(fc, l));
      const Tensor ni = normalise(rec, xi, si), nc = normalise(rec, level(fc, l), sc);
      Tensor dn = zero_tensor(rec, "d norm", ni.c, ni.h, ni.w);
      mse_term(rec, record, MccLossRecord::content, ni, nc, dn, weights.content);
      normalise_backward(rec, xi, si, ni, dn, dlevels[l - 1]);
    }
    for (const int l : levels.style) {
      const Tensor& xi = level(fi, l);
      const engine::Buffer si = mean_std(rec, xi), ss = mean_std(rec, level(fs, l));
      Tensor dstats = zero_tensor(rec, "d stats", 1, 1, 2 * xi.c);
      // MSE(mu) + MSE(sigma), each a mean over c: the sum over both halves / c.
      const double n = xi.c;
      record.add(MccLossRecord::style,
                 squared_error(rec, si, ss, dstats.buffer, 2 * size_t{xi.c}, static_cast<float>(2.0 * weights.style / n)),
                 1.0 / n);
      mean_std_backward(rec, xi, si, dstats.buffer, dlevels[l - 1]);
    }
    for (size_t i = 0; ccpl.heads != nullptr && i < ccpl.config.levels.size(); ++i) {
      const int l = ccpl.config.levels[i];
      ConvGrads* head_grads = ccpl.head_grads != nullptr ? &(*ccpl.head_grads)[2 * i] : nullptr;
      record.add(MccLossRecord::ccpl,
                 record_ccpl_level(rec, (*ccpl.heads)[i], level(fi, l), level(fc, l), ccpl.samples[i], ccpl.config.tau,
                                   weights.ccpl, dlevels[l - 1], head_grads),
                 1.0 / static_cast<double>(ccpl.samples[i].anchor.size()));
    }
    {
      const Tensor pooled = avgpool3(rec, level(fi, 5));
      Tensor dpooled = zero_tensor(rec, "d selfsim", pooled.c, pooled.h, pooled.w);
      record.add(MccLossRecord::selfsim, selfsim(rec, pooled, dpooled, weights.selfsim), 1.0 / pooled.c);
      dlevels[4] = add(rec, dlevels[4], avgpool3_backward(rec, dpooled));
    }
    backward_through(rec, net, mcc, dec, add(rec, enc.backward(rec, fi, std::move(dlevels)), d_ics), grads);
    backward_through(rec, net, mcc_n, dec_n, d_ics_n, grads);
  }

  // Icc and Iss: the identity losses.
  for (const auto& [image, feats] : {std::pair{&content, &fc}, std::pair{&style, &fs}}) {
    const MccTape mcc = net.mcc.forward(rec, level(*feats, 4), level(*feats, 4));
    const std::vector<Tensor> dec = net.decoder.forward_tape(rec, mcc.out);
    const Tensor& out = dec.back();
    Tensor dimage = zero_tensor(rec, "d identity", out.c, out.h, out.w);
    mse_term(rec, record, MccLossRecord::identity1, out, *image, dimage, weights.identity1);
    const std::vector<Tensor> fi = enc.forward_tape(rec, out);
    std::vector<Tensor> dlevels = zero_level_grads(rec, enc, fi);
    for (int l = 1; l <= 5; ++l)
      mse_term(rec, record, MccLossRecord::identity2, level(fi, l), level(*feats, l), dlevels[l - 1], weights.identity2);
    const Tensor dfeat_image = enc.backward(rec, fi, std::move(dlevels));
    backward_through(rec, net, mcc, dec, add(rec, dimage, dfeat_image), grads);
  }
  return record;
}

}  // namespace s4d::nn
