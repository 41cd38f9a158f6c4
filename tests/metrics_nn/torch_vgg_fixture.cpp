#include "torch_vgg_fixture.h"

#include <string>

namespace s4d::test {

namespace {

// torchvision's cfgs: 'D' (VGG16) and 'E' (VGG19); 0 is a max pool.
std::vector<int> cfg(const nn::VggWidths& w, bool vgg19) {
  const auto& l = w.level;
  if (!vgg19)
    return {int(l[0]), int(l[0]), 0, int(l[1]), int(l[1]), 0, int(l[2]), int(l[2]), int(l[2]), 0,
            int(l[3]), int(l[3]), int(l[3]), 0, int(l[4]), int(l[4]), int(l[4]), 0};
  return {int(l[0]), int(l[0]), 0, int(l[1]), int(l[1]), 0, int(l[2]), int(l[2]), int(l[2]), int(l[2]), 0,
          int(l[3]), int(l[3]), int(l[3]), int(l[3]), 0, int(l[4]), int(l[4]), int(l[4]), int(l[4]), 0};
}

}  // namespace

NetParams random_torch_vgg(const nn::VggWidths& widths, bool vgg19, std::mt19937& rng) {
  NetParams p;
  int index = 0;
  uint32_t cin = 3;
  for (const int v : cfg(widths, vgg19)) {
    if (v == 0) {
      index += 1;
      continue;
    }
    p["features." + std::to_string(index)] = random_conv(cin, uint32_t(v), 3, rng);
    cin = uint32_t(v);
    index += 2;
  }
  return p;
}

std::vector<ref::Chw<double>> twin_torch_vgg(const NetParams& net, bool vgg19, ref::Chw<double> x,
                                             const std::vector<int>& taps, bool l2_pool) {
  std::vector<ref::Chw<double>> out;
  int index = 0;
  for (const int v : cfg(nn::VggWidths{}, vgg19)) {
    if (out.size() == taps.size()) break;
    if (v == 0) {
      x = l2_pool ? ref::l2pool(x, 1e-12) : ref::maxpool2_floor(x);
      index += 1;
      continue;
    }
    const ConvParams& c = net.at("features." + std::to_string(index));
    x = ref::conv3x3_zero_pad(x, to_double(c.weight), to_double(c.bias), c.cout, true);
    if (index + 1 == taps[out.size()]) out.push_back(x);
    index += 2;
  }
  return out;
}

NetParams random_alexnet(const std::array<uint32_t, 5>& w, std::mt19937& rng) {
  return {{"features.0", random_conv(3, w[0], 11, rng)},
          {"features.3", random_conv(w[0], w[1], 5, rng)},
          {"features.6", random_conv(w[1], w[2], 3, rng)},
          {"features.8", random_conv(w[2], w[3], 3, rng)},
          {"features.10", random_conv(w[3], w[4], 3, rng)}};
}

std::vector<ref::Chw<double>> twin_alexnet(const NetParams& net, const ref::Chw<double>& x) {
  const auto conv = [&](const char* name, const ref::Chw<double>& in, uint32_t stride, uint32_t pad) {
    const ConvParams& c = net.at(name);
    return ref::conv2d(in, to_double(c.weight), to_double(c.bias), c.cout, c.k, stride, pad, true);
  };
  std::vector<ref::Chw<double>> taps;
  taps.push_back(conv("features.0", x, 4, 2));
  taps.push_back(conv("features.3", ref::maxpool3s2(taps[0]), 1, 2));
  taps.push_back(conv("features.6", ref::maxpool3s2(taps[1]), 1, 1));
  taps.push_back(conv("features.8", taps[2], 1, 1));
  taps.push_back(conv("features.10", taps[3], 1, 1));
  return taps;
}

io::ImageF random_image(int width, int height, std::mt19937& rng) {
  io::ImageF img{width, height, 3, random_values(size_t(width) * size_t(height) * 3, 0.0f, 1.0f, rng)};
  return img;
}

ref::Chw<double> image_chw(const io::ImageF& image, const double mul[3], const double add[3]) {
  ref::Chw<double> t(3, uint32_t(image.height), uint32_t(image.width));
  const size_t plane = size_t(image.width) * size_t(image.height);
  for (size_t i = 0; i < plane; ++i)
    for (size_t c = 0; c < 3; ++c) t.v[c * plane + i] = double(image.data[3 * i + c]) * mul[c] + add[c];
  return t;
}

}  // namespace s4d::test
