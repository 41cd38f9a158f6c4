// The network frame stylizers (s4d_frame_stylizers on s4d_nn): frames through the GPU networks against the
// double twins, resized back to the frames' size and clamped; hgst's square style; strength 0; the
// size refusal.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "expect_allclose.h"
#include "nn_fixture.h"
#include "s4d/io/image_file.h"
#include "s4d/frame_stylizers/network_stylizer.h"

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

// Tiny networks in `dir`, under the file names the stylizers read; the decoder's output layer is
// biased to 0.5, so clamping to [0, 1] keeps many values.
struct TinyNets {
  test::NetParams vgg, decoder, mcc;
  TinyNets(const test::ScratchDir& dir, std::mt19937& rng, const nn::VggWidths& widths = kTiny)
      : vgg(test::random_vgg(widths, 4, rng)),
        decoder(test::random_decoder(widths, rng)),
        mcc(test::random_mcc(widths, rng)) {
    for (float& b : decoder["28"].bias) b += 0.5f;
    test::write_params(dir / "vgg_normalised.safetensors", vgg);
    test::write_params(dir / "decoder.safetensors", decoder);
    test::write_params(dir / "mcc_module.safetensors", mcc);
  }
};

// The twin's decoded [3, h, w] as an RGB image clamped to [0, 1], resized to width x height.
io::ImageF twin_frame(const ref::Chw<double>& decoded, int width, int height) {
  io::ImageF image{static_cast<int>(decoded.w), static_cast<int>(decoded.h), 3, std::vector<float>(decoded.v.size())};
  for (uint32_t y = 0; y < decoded.h; ++y)
    for (uint32_t x = 0; x < decoded.w; ++x)
      for (uint32_t c = 0; c < 3; ++c)
        image.data[(size_t{y} * decoded.w + x) * 3 + c] = static_cast<float>(std::clamp(decoded.at(c, y, x), 0.0, 1.0));
  return io::resize_image(image, width, height);
}

}  // namespace

TEST_CASE("the adain stylizer's frames are the network's, resized back and clamped") {
  test::ScratchDir dir("adain_stylizer");
  std::mt19937 rng(21);
  const TinyNets net(dir, rng);
  const auto stylizer =
      frame_stylizers::make_network_stylizer("adain", {.weights = dir.path(), .style_size = 12, .context = &context()}, kTiny);
  const std::vector<io::ImageF> frames = {random_image(20, 17, rng), random_image(20, 17, rng)};
  const io::ImageF style = random_image(18, 24, rng);  // shorter side 18 -> 12: 12x16
  int reported = 0;
  const auto out = stylizer->stylize(frames, style, {.strength = 0.8f}, [&](int done, int) { reported = done; });
  CHECK(reported == 2);
  REQUIRE(out.size() == 2);
  const auto fs = test::twin_encode(net.vgg, test::to_double(to_chw(io::resize_image(style, 12, 16))), 4);
  for (size_t t = 0; t < frames.size(); ++t) {
    const auto fc = test::twin_encode(net.vgg, test::to_double(to_chw(frames[t])), 4);
    const auto decoded =
        test::twin_decode(net.decoder, ref::adain(fc, ref::mean_std(fc, 1e-5), ref::mean_std(fs, 1e-5), 0.8));
    REQUIRE(out[t].width == 20);  // decoded at 24x24
    REQUIRE(out[t].height == 17);
    // Values in [0, 1], float network against double, resized: measured 2.4e-7.
    test::expect_allclose(out[t].data, twin_frame(decoded, 20, 17).data, {.atol = 1e-5}, "frame");
  }
}

TEST_CASE("the hgst stylizer runs MCCNet on the style's centre square") {
  test::ScratchDir dir("hgst_stylizer");
  std::mt19937 rng(23);
  const TinyNets net(dir, rng);
  const auto stylizer =
      frame_stylizers::make_network_stylizer("hgst", {.weights = dir.path(), .style_size = 12, .context = &context()}, kTiny);
  CHECK(stylizer->name() == "hgst");
  const std::vector<io::ImageF> frames = {random_image(16, 19, rng)};
  const io::ImageF style = random_image(18, 24, rng);
  const auto out = stylizer->stylize(frames, style, {});
  // 18x24 -> 12x16, then its centre 12x12 (rows 2..13).
  const io::ImageF resized = io::resize_image(style, 12, 16);
  io::ImageF square{12, 12, 3, {resized.data.begin() + 2 * 12 * 3, resized.data.begin() + 14 * 12 * 3}};
  const auto fc = test::twin_encode(net.vgg, test::to_double(to_chw(frames[0])), 4);
  const auto fs = test::twin_encode(net.vgg, test::to_double(to_chw(square)), 4);
  const auto decoded = test::twin_decode(net.decoder, test::twin_mcc(net.mcc, fc, fs, 1.0));
  REQUIRE(out[0].width == 16);
  REQUIRE(out[0].height == 19);  // decoded at 16x24
  // MCC amplifies the encoder's float error (test_nn_networks.cpp): measured 1.3e-5.
  test::expect_allclose(out[0].data, twin_frame(decoded, 16, 19).data, {.atol = 1e-4}, "frame");
}

TEST_CASE("the adain stylizer returns the frames at strength 0 and refuses frames past the device's buffers") {
  test::ScratchDir dir("adain_stylizer_edges");
  std::mt19937 rng(22);
  // relu1_1 as wide as VGG's (64), so the full-size feature maps of a 1024x520 frame need 136 MB.
  const nn::VggWidths wide_first{{64, 6, 8, 10, 12}};
  const TinyNets net(dir, rng, wide_first);
  const auto stylizer = frame_stylizers::make_network_stylizer(
      "adain", {.weights = dir.path(), .style_size = 0, .context = &context()}, wide_first);
  const std::vector<io::ImageF> frames = {random_image(9, 8, rng)};
  CHECK(stylizer->stylize(frames, random_image(8, 8, rng), {.strength = 0.0f})[0].data == frames[0].data);
  const io::ImageF large{1024, 520, 3, std::vector<float>(1024 * 520 * 3, 0.5f)};
  if (context().info().max_storage_buffer_range < 64ull * 1024 * 520 * 4) {
    CHECK_THROWS_WITH_AS(stylizer->stylize({large}, random_image(8, 8, rng), {}),
                         doctest::Contains("adain: a 1024x520 frame needs 130 MiB feature maps, over"),
                         std::invalid_argument);
  }
}
