#include "s4d/nn/ckdn_net.h"

#include <stdexcept>
#include <string>

#include "s4d/nn/weights.h"

namespace s4d::nn {

CkdnNet::CkdnNet(engine::Context& ctx, const io::SafetensorsFile& file)
    : qse_1_(load_conv_no_bias(ctx, file, "net.qse_1", 3, 64, 7)),
      dte_1_(load_conv_no_bias(ctx, file, "net.dte_1", 3, 64, 7)),
      qse_2_(load_bottleneck_layer(ctx, file, "net.qse_2", 64, 64, 3, 1)),
      dte_2_(load_bottleneck_layer(ctx, file, "net.dte_2", 64, 64, 3, 1)),
      csp_(load_bottleneck_layer(ctx, file, "net.csp", 256, 128, 4, 2)),
      fc_{load_linear(ctx, file, "net.fc_.0", 512, 2048), load_linear(ctx, file, "net.fc_.3", 2048, 2048),
          load_linear(ctx, file, "net.fc_.6", 2048, 1)} {}

Tensor CkdnNet::stem(engine::Recorder& rec, const Tensor& x, const ConvWeights& conv,
                     const std::vector<Bottleneck>& layer1) const {
  Tensor h = maxpool3s2(rec, conv_strided(rec, x, conv, 2, 3, false), 1);
  for (const Bottleneck& b : layer1) h = run_bottleneck(rec, h, b, BottleneckStride::conv);
  return h;
}

Tensor CkdnNet::logit(engine::Recorder& rec, const Tensor& x, const Tensor& y) const {
  for (const Tensor* t : {&x, &y})
    if (t->c != 3 || t->h < kMinSize || t->w < kMinSize)
      throw std::invalid_argument("ckdn: expects RGB images [3, H, W] with H, W >= " + std::to_string(kMinSize) + ", got " +
                                  t->shape());
  if (x.h != y.h || x.w != y.w)
    throw std::invalid_argument("ckdn: the restored image " + x.shape() + " and the reference " + y.shape() + " differ in size");
  Tensor h = subtract(rec, stem(rec, x, qse_1_, qse_2_), stem(rec, y, dte_1_, dte_2_));
  for (const Bottleneck& b : csp_) h = run_bottleneck(rec, h, b, BottleneckStride::conv);
  Tensor v = global_average(rec, h);
  v = conv1x1(rec, v, fc_[0], true);
  v = conv1x1(rec, v, fc_[1], true);
  return conv1x1(rec, v, fc_[2], false);
}

}  // namespace s4d::nn
