#include "s4d/nn/resnet_bottleneck.h"

#include <stdexcept>

#include "s4d/nn/weights.h"

namespace s4d::nn {

std::vector<Bottleneck> load_bottleneck_layer(engine::Context& ctx, const io::SafetensorsFile& file,
                                              const std::string& prefix, uint32_t cin, uint32_t planes, uint32_t blocks,
                                              uint32_t stride) {
  if (stride != 1 && stride != 2)
    throw std::invalid_argument(prefix + ": stride " + std::to_string(stride) + " is not 1 or 2");
  std::vector<Bottleneck> layer(blocks);
  for (uint32_t i = 0; i < blocks; ++i) {
    const std::string p = prefix + "." + std::to_string(i);
    const uint32_t in = i == 0 ? cin : planes * 4;
    Bottleneck& b = layer[i];
    b.stride = i == 0 ? stride : 1;
    b.conv1 = load_conv_bn(ctx, file, p + ".conv1", p + ".bn1", in, planes, 1);
    b.conv2 = load_conv_bn(ctx, file, p + ".conv2", p + ".bn2", planes, planes, 3);
    b.conv3 = load_conv_bn(ctx, file, p + ".conv3", p + ".bn3", planes, planes * 4, 1);
    if (b.stride != 1 || in != planes * 4)
      b.downsample = load_conv_bn(ctx, file, p + ".downsample.0", p + ".downsample.1", in, planes * 4, 1);
  }
  return layer;
}

Tensor run_bottleneck(engine::Recorder& rec, const Tensor& x, const Bottleneck& b, BottleneckStride style) {
  const Tensor h1 = conv1x1(rec, x, b.conv1, true);
  // torchvision's stride 2 as every second output of the stride-1 convolution (the same sums): 4x the
  // work in the tiled nn_conv3x3_zero, yet faster on lavapipe than nn_conv_strided (CKDN's layer2, 128
  // channels at 72x72: measured 0.8-1.0 s against 1.6 s, 2 loaded cores).
  Tensor h2 = conv3x3_zero_pad(rec, h1, b.conv2, true);
  const bool strides = b.stride == 2;
  if (strides) h2 = style == BottleneckStride::conv ? subsample2(rec, h2) : avgpool2(rec, h2);
  // The identity path (a copy of x, or the 1x1 downsample of x strided first: as a subsampling before
  // the tiled conv1x1, since nn_conv_strided took 4.6 s on lavapipe for CKDN's 256 -> 512 at 72x72, or
  // CLIP's average pooling), then out += conv3(h2) and the ReLU of the sum.
  const Tensor* identity[] = {&x};
  Tensor out;
  if (b.downsample.cout == 0) out = concat_channels(rec, identity);
  else if (!strides) out = conv1x1(rec, x, b.downsample, false);
  else out = conv1x1(rec, style == BottleneckStride::conv ? subsample2(rec, x) : avgpool2(rec, x), b.downsample, false);
  conv1x1_accumulate(rec, h2, b.conv3, out);
  relu_inplace(rec, out);
  return out;
}

}  // namespace s4d::nn
