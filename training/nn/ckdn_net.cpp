#include "s4d/nn/ckdn_net.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/nn/weights.h"

namespace s4d::nn {

namespace {

constexpr double kBatchNormEps = 1e-5;  // torch.nn.BatchNorm2d's default, which ckdn_arch.py keeps

// Conv2d(cin, cout, k, bias=False) "<conv>.weight" followed by BatchNorm2d "<bn>.*" in eval mode,
// folded into one convolution with bias (ckdn_net.h).
ConvWeights load_conv_bn(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& conv,
                         const std::string& bn, uint32_t cin, uint32_t cout, uint32_t k) {
  std::vector<float> weight = file.read(conv + ".weight", {cout, cin, k, k});
  const std::vector<float> gamma = file.read(bn + ".weight", {cout});
  const std::vector<float> beta = file.read(bn + ".bias", {cout});
  const std::vector<float> mean = file.read(bn + ".running_mean", {cout});
  const std::vector<float> var = file.read(bn + ".running_var", {cout});
  std::vector<float> bias(cout);
  const size_t per_out = size_t{cin} * k * k;
  for (uint32_t o = 0; o < cout; ++o) {
    if (!(var[o] >= 0))
      throw std::runtime_error(file.path().string() + ": " + bn + ".running_var[" + std::to_string(o) + "] is negative");
    const double scale = double(gamma[o]) / std::sqrt(double(var[o]) + kBatchNormEps);
    for (size_t i = 0; i < per_out; ++i) weight[o * per_out + i] = float(double(weight[o * per_out + i]) * scale);
    bias[o] = float(double(beta[o]) - double(mean[o]) * scale);
  }
  return upload_conv(ctx, file.path().filename().string() + " " + conv, cin, cout, k, weight, bias);
}

ConvWeights load_conv_no_bias(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix,
                              uint32_t cin, uint32_t cout, uint32_t k) {
  const std::vector<float> weight = file.read(prefix + ".weight", {cout, cin, k, k});
  return upload_conv(ctx, file.path().filename().string() + " " + prefix, cin, cout, k, weight,
                     std::vector<float>(cout, 0.0f));
}

}  // namespace

std::vector<CkdnNet::Bottleneck> CkdnNet::load_layer(engine::Context& ctx, const io::SafetensorsFile& file,
                                                     const std::string& prefix, uint32_t cin, uint32_t planes,
                                                     uint32_t blocks, uint32_t stride) {
  // torchvision's _make_layer: the first block takes the stride and, as its input width differs
  // from planes * 4 (or it strides), a 1x1 downsample with BatchNorm on the identity path.
  std::vector<Bottleneck> layer(blocks);
  for (uint32_t i = 0; i < blocks; ++i) {
    const std::string p = prefix + "." + std::to_string(i);
    const uint32_t in = i == 0 ? cin : planes * 4;
    Bottleneck& b = layer[i];
    b.stride = i == 0 ? stride : 1;
    if (b.stride != 1 && b.stride != 2) throw std::invalid_argument("CkdnNet: stride " + std::to_string(stride) + " is not 1 or 2");
    b.conv1 = load_conv_bn(ctx, file, p + ".conv1", p + ".bn1", in, planes, 1);
    b.conv2 = load_conv_bn(ctx, file, p + ".conv2", p + ".bn2", planes, planes, 3);
    b.conv3 = load_conv_bn(ctx, file, p + ".conv3", p + ".bn3", planes, planes * 4, 1);
    if (i == 0) b.downsample = load_conv_bn(ctx, file, p + ".downsample.0", p + ".downsample.1", in, planes * 4, 1);
  }
  return layer;
}

CkdnNet::CkdnNet(engine::Context& ctx, const io::SafetensorsFile& file)
    : qse_1_(load_conv_no_bias(ctx, file, "net.qse_1", 3, 64, 7)),
      dte_1_(load_conv_no_bias(ctx, file, "net.dte_1", 3, 64, 7)),
      qse_2_(load_layer(ctx, file, "net.qse_2", 64, 64, 3, 1)),
      dte_2_(load_layer(ctx, file, "net.dte_2", 64, 64, 3, 1)),
      csp_(load_layer(ctx, file, "net.csp", 256, 128, 4, 2)),
      fc_{load_linear(ctx, file, "net.fc_.0", 512, 2048), load_linear(ctx, file, "net.fc_.3", 2048, 2048),
          load_linear(ctx, file, "net.fc_.6", 2048, 1)} {}

Tensor CkdnNet::run_block(engine::Recorder& rec, const Tensor& x, const Bottleneck& b) {
  const Tensor h1 = conv1x1(rec, x, b.conv1, true);
  // Stride 2 as every second output of the stride-1 convolution (the same sums): 4x the work in the
  // tiled nn_conv3x3_zero, yet faster on lavapipe than nn_conv_strided (layer2's 128 channels at
  // 72x72: measured 0.8-1.0 s against 1.6 s, 2 loaded cores).
  Tensor h2 = conv3x3_zero_pad(rec, h1, b.conv2, true);
  if (b.stride == 2) h2 = subsample2(rec, h2);
  // The identity path (a copy of x, or the 1x1 downsample, strided as a subsampling before the tiled
  // conv1x1: nn_conv_strided took 4.6 s on lavapipe for layer2's 256 -> 512 at 72x72), then
  // out += conv3(h2) and the ReLU of the sum.
  const Tensor* identity[] = {&x};
  Tensor out = b.downsample.cout == 0 ? concat_channels(rec, identity)
               : b.stride == 2        ? conv1x1(rec, subsample2(rec, x), b.downsample, false)
                                      : conv1x1(rec, x, b.downsample, false);
  conv1x1_accumulate(rec, h2, b.conv3, out);
  relu_inplace(rec, out);
  return out;
}

Tensor CkdnNet::stem(engine::Recorder& rec, const Tensor& x, const ConvWeights& conv,
                     const std::vector<Bottleneck>& layer1) const {
  Tensor h = maxpool3s2(rec, conv_strided(rec, x, conv, 2, 3, false), 1);
  for (const Bottleneck& b : layer1) h = run_block(rec, h, b);
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
  for (const Bottleneck& b : csp_) h = run_block(rec, h, b);
  Tensor v = global_average(rec, h);
  v = conv1x1(rec, v, fc_[0], true);
  v = conv1x1(rec, v, fc_[1], true);
  return conv1x1(rec, v, fc_[2], false);
}

}  // namespace s4d::nn
