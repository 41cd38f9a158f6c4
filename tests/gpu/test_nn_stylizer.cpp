// The AdaIN frame stylizer (s4d_stylize on s4d_nn): frames through the GPU network against the
// double twin, resized back to the frames' size and clamped; strength 0; the size refusal.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn_fixture.h"
#include "s4d/stylize/image_file.h"
#include "s4d/stylize/network_stylizer.h"

namespace {

using namespace s4d;
using test::context;

const nn::VggWidths kTiny{{4, 6, 8, 10, 12}};

io::ImageF random_image(int width, int height, std::mt19937& rng) {
  return {width, height, 3, test::random_values(static_cast<size_t>(width) * height * 3, 0.0f, 1.0f, rng)};
}

ref::Chw<float> to_chw(const io::ImageF& image) {
  ref::Chw<float> t(3, static_cast<uint32_t>(image.height), static_cast<uint32_t>(image.width));
  for (uint32_t y = 0; y < t.h; ++y)
    for (uint32_t x = 0; x < t.w; ++x)
      for (uint32_t c = 0; c < 3; ++c) t.at(c, y, x) = image.data[(size_t{y} * t.w + x) * 3 + c];
  return t;
}

// A tiny AdaIN in `dir` whose output layer is biased to 0.5, so clamping to [0, 1] keeps most values.
struct TinyAdain {
  test::NetParams vgg, decoder;
  TinyAdain(const test::ScratchDir& dir, std::mt19937& rng, const nn::VggWidths& widths = kTiny)
      : vgg(test::random_vgg(widths, 4, rng)), decoder(test::random_decoder(widths, rng)) {
    for (float& b : decoder["28"].bias) b += 0.5f;
    test::write_params(dir / "vgg_normalised.safetensors", vgg);
    test::write_params(dir / "decoder.safetensors", decoder);
  }
};

}  // namespace

TEST_CASE("the adain stylizer's frames are the network's, resized back and clamped") {
  test::ScratchDir dir("adain_stylizer");
  std::mt19937 rng(21);
  const TinyAdain net(dir, rng);
  const stylize::AdainStylizer stylizer({.weights = dir.path(), .style_size = 12, .context = &context()}, kTiny);
  const std::vector<io::ImageF> frames = {random_image(20, 17, rng), random_image(20, 17, rng)};
  const io::ImageF style = random_image(18, 24, rng);  // shorter side 18 -> 12: 12x16
  int reported = 0;
  const auto out = stylizer.stylize(frames, style, {.strength = 0.8f}, [&](int done, int) { reported = done; });
  CHECK(reported == 2);
  REQUIRE(out.size() == 2);
  const auto small_style = test::to_double(to_chw(stylize::resize_image(style, 12, 16)));
  const auto fs = test::twin_encode(net.vgg, small_style, 4);
  for (size_t t = 0; t < frames.size(); ++t) {
    const auto fc = test::twin_encode(net.vgg, test::to_double(to_chw(frames[t])), 4);
    const auto decoded =
        test::twin_decode(net.decoder, ref::adain(fc, ref::mean_std(fc, 1e-5), ref::mean_std(fs, 1e-5), 0.8));
    io::ImageF expected{24, 24, 3, std::vector<float>(24 * 24 * 3)};  // 20x17 decodes to 24x24
    for (uint32_t y = 0; y < 24; ++y)
      for (uint32_t x = 0; x < 24; ++x)
        for (uint32_t c = 0; c < 3; ++c)
          expected.data[(y * 24 + x) * 3 + c] = static_cast<float>(std::clamp(decoded.at(c, y, x), 0.0, 1.0));
    expected = stylize::resize_image(expected, 20, 17);
    REQUIRE(out[t].width == 20);
    REQUIRE(out[t].height == 17);
    double worst = 0;
    for (size_t i = 0; i < expected.data.size(); ++i)
      worst = std::max(worst, static_cast<double>(std::abs(out[t].data[i] - expected.data[i])));
    CHECK(worst < 1e-5);  // values in [0, 1], float network against double, resized: measured 6.0e-8
  }
}

TEST_CASE("the adain stylizer returns the frames at strength 0 and refuses frames past the device's buffers") {
  test::ScratchDir dir("adain_stylizer_edges");
  std::mt19937 rng(22);
  // relu1_1 as wide as VGG's (64), so the full-size feature maps of a 1024x520 frame need 136 MB.
  const nn::VggWidths wide_first{{64, 6, 8, 10, 12}};
  const TinyAdain net(dir, rng, wide_first);
  const stylize::AdainStylizer stylizer({.weights = dir.path(), .style_size = 0, .context = &context()}, wide_first);
  const std::vector<io::ImageF> frames = {random_image(9, 8, rng)};
  CHECK(stylizer.stylize(frames, random_image(8, 8, rng), {.strength = 0.0f})[0].data == frames[0].data);
  const io::ImageF large{1024, 520, 3, std::vector<float>(1024 * 520 * 3, 0.5f)};
  if (context().info().max_storage_buffer_range < 64ull * 1024 * 520 * 4) {
    CHECK_THROWS_WITH_AS(stylizer.stylize({large}, random_image(8, 8, rng), {}),
                         doctest::Contains("adain: a 1024x520 frame needs 130 MiB feature maps, over"),
                         std::invalid_argument);
  }
}
