// AdaAttN on lavapipe against double twins (ref/nn_ref.h): the new kernels (nearest resize,
// attention scores, row softmax, attention apply) one by one and at their loop caps, the chunked
// attention, channel concatenation, and the whole network with random weights written as
// safetensors at tiny widths, on sizes that take the odd-size and style-subsampling paths, through
// the frame stylizer too, and the missing-weight errors.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "nn_fixture.h"
#include "s4d/nn/adaattn_net.h"
#include "s4d/nn/attention.h"
#include "s4d/io/image_file.h"
#include "s4d/frame_stylizers/network_stylizer.h"
#include "s4d_nn.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

const nn::VggWidths kTiny{{4, 6, 8, 10, 10}};

ref::Chw<double> norm(const ref::Chw<double>& x) { return ref::normalise(x, ref::mean_std(x, 1e-5)); }

ref::Chw<double> conv1(const test::ConvParams& p, const ref::Chw<double>& x) {
  return ref::conv1x1(x, to_double(p.weight), to_double(p.bias), p.cout, false);
}

// get_key: the normalised levels 0..last, the shallower ones resized to the last one's size first.
ref::Chw<double> twin_key(const std::vector<ref::Chw<double>>& levels, int last) {
  std::vector<ref::Chw<double>> parts;
  const auto& top = levels[static_cast<size_t>(last)];
  for (int i = 0; i < last; ++i)
    parts.push_back(norm(ref::resize_nearest(levels[static_cast<size_t>(i)], top.h, top.w)));
  parts.push_back(norm(top));
  return ref::concat_channels(parts);
}

using Weights = test::AdaattnParams;

Weights random_weights(std::mt19937& rng) { return test::random_adaattn(kTiny, rng); }

// AdaAttN(content, style) through the twins; `grid` is where each style level is subsampled to
// (0: not), written out by hand for the test's sizes.
ref::Chw<double> twin_adaattn(const Weights& p, const ref::Chw<float>& content, const ref::Chw<float>& style,
                              const std::vector<std::pair<uint32_t, uint32_t>>& grid, double alpha) {
  std::vector<ref::Chw<double>> c, s;
  for (int l = 1; l <= 5; ++l) {
    c.push_back(test::twin_encode(p.vgg, to_double(content), l));
    s.push_back(test::twin_encode(p.vgg, to_double(style), l));
  }
  const auto module = [&](const test::NetParams& m, const std::string& prefix, int level) {
    const auto& fc = c[static_cast<size_t>(level)];
    auto fs = s[static_cast<size_t>(level)];
    auto skey = twin_key(s, level);
    const auto [gh, gw] = grid[static_cast<size_t>(level - 2)];
    if (gh != 0) {
      fs = ref::resize_nearest(fs, gh, gw);
      skey = ref::resize_nearest(skey, gh, gw);
    }
    const auto out = ref::attention(conv1(m.at(prefix + "f"), twin_key(c, level)), conv1(m.at(prefix + "g"), skey),
                                    conv1(m.at(prefix + "h"), fs), norm(fc));
    ref::Chw<double> blended = out;
    for (size_t i = 0; i < out.v.size(); ++i) blended.v[i] = alpha * out.v[i] + (1 - alpha) * fc.v[i];
    return blended;
  };
  const auto skip = module(p.attn3, "", 2);
  const auto a4 = module(p.transformer, "attn_adain_4_1.", 3), a5 = module(p.transformer, "attn_adain_5_1.", 4);
  const auto& merge = p.transformer.at("merge_conv");
  const auto cs = ref::conv3x3(ref::add(a4, ref::resize_nearest(a5, a4.h, a4.w)), to_double(merge.weight),
                               to_double(merge.bias), merge.cout, false);
  const auto conv3 = [&](const char* name, const ref::Chw<double>& x, bool relu) {
    const auto& q = p.decoder.at(name);
    return ref::conv3x3(x, to_double(q.weight), to_double(q.bias), q.cout, relu);
  };
  const auto up = ref::upsample2(conv3("decoder_layer_1.1", cs, true));
  auto x = ref::concat_channels(std::vector{up, ref::resize_nearest(skip, up.h, up.w)});
  x = conv3("decoder_layer_2.1", x, true);
  x = conv3("decoder_layer_2.4", x, true);
  x = conv3("decoder_layer_2.7", x, true);
  x = ref::upsample2(conv3("decoder_layer_2.10", x, true));
  x = conv3("decoder_layer_2.14", x, true);
  x = ref::upsample2(conv3("decoder_layer_2.17", x, true));
  x = conv3("decoder_layer_2.21", x, true);
  return conv3("decoder_layer_2.24", x, false);
}

void write(const test::ScratchDir& dir, const Weights& p) { test::write_adaattn(dir.path(), p); }

}  // namespace

// Kernel nn_resize_nearest.
TEST_CASE("nearest resize matches its twin, down and up, on sizes that do not divide") {
  std::mt19937 rng(31);
  const auto x = test::random_chw(3, 7, 9, rng);
  const auto gx = test::upload(x);
  for (const auto& [h, w] : {std::pair<uint32_t, uint32_t>{3, 4}, {14, 18}, {5, 13}, {7, 9}}) {
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::resize_nearest(r, gx, h, w); }));
    test::expect_allclose(gpu, ref::resize_nearest(to_double(x), h, w).v, {}, "gpu");  // a copy: exact
  }
}

TEST_CASE("channel concatenation matches torch.cat") {
  std::mt19937 rng(32);
  const auto a = test::random_chw(2, 3, 5, rng), b = test::random_chw(3, 3, 5, rng);
  const auto ga = test::upload(a, "a"), gb = test::upload(b, "b");
  const nn::Tensor* parts[] = {&ga, &gb};
  const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::concat_channels(r, parts); }));
  test::expect_allclose(gpu, ref::concat_channels(std::vector{to_double(a), to_double(b)}).v, {}, "gpu");  // copies: exact
}

// Kernels nn_attn_scores, nn_softmax_rows, nn_attn_apply.
TEST_CASE("attention kernels match their twins, at their loop caps too") {
  std::mt19937 rng(33);
  SUBCASE("scores of a chunk, over 1472 key channels (AdaAttN's relu5_1 keys)") {
    const auto q = test::random_chw(1472, 3, 3, rng), k = test::random_chw(1472, 2, 5, rng);
    const auto gq = test::upload(q, "q"), gk = test::upload(k, "k");
    const auto gpu =
        nn::download(context(), run([&](engine::Recorder& r) { return nn::attention_scores(r, gq, gk, 2, 5); }));
    const auto twin = ref::attention_scores(to_double(q), to_double(k));
    const std::vector<double> rows(twin.begin() + 2 * 10, twin.begin() + 7 * 10);
    test::expect_allclose(gpu, rows, {.of_largest = 1e-5}, "gpu");  // 1472 float products per score: measured 1.1e-6
  }
  SUBCASE("row softmax with logits up to +-80 and rows longer than a workgroup") {
    const auto s = test::random_chw(1, 3, 1000, rng, -80.0f, 80.0f);
    auto gs = test::upload(s, "scores");
    run([&](engine::Recorder& r) {
      nn::softmax_rows(r, gs);
      return 0;
    });
    // float exp of logits shifted by the row maximum: measured 1.3e-7.
    test::expect_allclose(nn::download(context(), gs), ref::softmax_rows(to_double(s.v), 1000), {.of_largest = 1e-5}, "gs");
  }
  SUBCASE("apply over 60000 style positions, the loop cap") {
    const uint32_t n_s = S4D_NN_MAX_LOOP;
    auto p = test::random_chw(1, 2, n_s, rng, 0.5f, 1.0f);
    for (uint32_t row = 0; row < 2; ++row) {  // rows summing to one, as softmax leaves them
      double sum = 0;
      for (uint32_t j = 0; j < n_s; ++j) sum += p.v[row * n_s + j];
      for (uint32_t j = 0; j < n_s; ++j) p.v[row * n_s + j] = static_cast<float>(p.v[row * n_s + j] / sum);
    }
    const auto v = test::random_chw(2, 1, n_s, rng), content = test::random_chw(2, 1, 3, rng);
    const auto gp = test::upload(p, "p"), gv = test::upload(v, "v"), gc = test::upload(content, "content");
    auto out = test::upload(ref::Chw<float>(2, 1, 3), "out");
    run([&](engine::Recorder& r) {
      nn::attention_apply(r, gp, gv, gc, 1, out);
      return 0;
    });
    const auto twin = ref::attention_apply(to_double(p.v), to_double(v), [&] {
      ref::Chw<double> cols(2, 1, 2);  // content columns 1 and 2, the chunk
      for (uint32_t c = 0; c < 2; ++c)
        for (uint32_t i = 0; i < 2; ++i) cols.v[c * 2 + i] = content.v[c * 3 + 1 + i];
      return cols;
    }());
    const auto gpu = nn::download(context(), out);
    const std::vector<float> chunk = {gpu[1], gpu[2], gpu[4], gpu[5]};
    test::expect_allclose(chunk, twin.v, {.of_largest = 3e-5}, "chunk");  // 60000-term float sums, then E[V^2] - M^2: measured 3.2e-6
  }
}

TEST_CASE("the chunked attention matches its twin whatever the chunk") {
  std::mt19937 rng(34);
  const auto q = test::random_chw(5, 7, 6, rng), k = test::random_chw(5, 4, 5, rng);
  const auto v = test::random_chw(3, 4, 5, rng), content = test::random_chw(3, 7, 6, rng);
  const auto gq = test::upload(q, "q"), gk = test::upload(k, "k"), gv = test::upload(v, "v"),
             gc = test::upload(content, "content");
  const auto twin = ref::attention(to_double(q), to_double(k), to_double(v), to_double(content));
  for (const size_t rows : {size_t{1}, size_t{5}, size_t{42}}) {
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) {
                                    return nn::attention(r, gq, gk, gv, gc, rows * 20 * sizeof(float));
                                  }));
    INFO(rows);
    test::expect_allclose(gpu, twin.v, {.of_largest = 2e-6}, "gpu");  // 5-term logits, 20-term sums: measured 1.3e-7
  }
}

TEST_CASE("AdaAttN end to end matches its twin, with odd sizes and a subsampled style") {
  test::ScratchDir dir("adaattn");
  std::mt19937 rng(35);
  const Weights p = random_weights(rng);
  write(dir, p);
  // max_sample 12: the style's relu3_1 (8x6) is sampled on 4x3, relu4_1 (4x3) and relu5_1 (2x2) are whole.
  const nn::AdaattnNet net(context(), io::SafetensorsFile(dir / "vgg_normalised.safetensors"),
                           io::SafetensorsFile(dir / "net_adaattn_3.safetensors"),
                           io::SafetensorsFile(dir / "net_transformer.safetensors"),
                           io::SafetensorsFile(dir / "net_decoder.safetensors"), kTiny, 12);
  // 36x40: relu3_1 9x10, relu4_1 5x5, relu5_1 3x3, so both resizes before the sums take odd sizes.
  const auto content = test::random_chw(3, 36, 40, rng, 0.0f, 1.0f);
  const auto style = test::random_chw(3, 32, 24, rng, 0.0f, 1.0f);
  const auto gc = test::upload(content, "content"), gs = test::upload(style, "style");
  for (const float alpha : {1.0f, 0.5f}) {
    CAPTURE(alpha);
    const auto out = run([&](engine::Recorder& r) { return net.stylize(r, gc, net.style(r, gs), alpha); });
    CHECK(out.h == 40);
    CHECK(out.w == 40);
    const auto twin = twin_adaattn(p, content, style, {{4, 3}, {0, 0}, {0, 0}}, alpha);
    // Each stage's float error carried through the next; the relu5_1 statistics over 3x3 and 2x2
    // maps and the softmax of logits in the tens (He-uniform f and g on normalised keys) amplify
    // it, as MCC's statistics do in test_nn_networks.cpp: measured 6.0e-5 (alpha 1), 4.6e-5.
    test::expect_allclose(nn::download(context(), out), twin.v, {.of_largest = 3e-4}, "out");
  }
}

TEST_CASE("the adaattn stylizer's frames are the network's, resized back and clamped") {
  test::ScratchDir dir("adaattn_stylizer");
  std::mt19937 rng(37);
  Weights p = random_weights(rng);
  for (float& b : p.decoder["decoder_layer_2.24"].bias) b += 0.5f;  // so clamping to [0, 1] keeps many values
  write(dir, p);
  const auto stylizer = frame_stylizers::make_network_stylizer(
      "adaattn", {.weights = dir.path(), .style_size = 32, .context = &context()}, kTiny);
  const auto frame = test::random_chw(3, 30, 34, rng, 0.0f, 1.0f);
  const auto style = test::random_chw(3, 32, 32, rng, 0.0f, 1.0f);  // already square at --style-size
  const auto image = [](const ref::Chw<float>& t) {
    io::ImageF im{static_cast<int>(t.w), static_cast<int>(t.h), 3, std::vector<float>(t.v.size())};
    for (uint32_t y = 0; y < t.h; ++y)
      for (uint32_t x = 0; x < t.w; ++x)
        for (uint32_t c = 0; c < 3; ++c) im.data[(size_t{y} * t.w + x) * 3 + c] = t.at(c, y, x);
    return im;
  };
  const auto out = stylizer->stylize({image(frame)}, image(style), {.strength = 1.0f});
  REQUIRE(out.size() == 1);
  CHECK(out[0].width == 34);
  CHECK(out[0].height == 30);
  // The twin's 40x32 output clamped and resized back to 34x30 the same way.
  const auto twin = twin_adaattn(p, frame, style, {{0, 0}, {0, 0}, {0, 0}}, 1.0);
  ref::Chw<float> clamped(twin.c, twin.h, twin.w);
  for (size_t i = 0; i < twin.v.size(); ++i) clamped.v[i] = static_cast<float>(std::clamp(twin.v[i], 0.0, 1.0));
  const io::ImageF expected = io::resize_image(image(clamped), 34, 30);
  // Values in [0, 1]; the network's float error as end to end: measured 2.3e-4.
  test::expect_allclose(out[0].data, expected.data, {.atol = 1e-3}, "frame");
}

TEST_CASE("AdaAttN weights that are missing fail naming the file and the tensor") {
  test::ScratchDir dir("adaattn_errors");
  std::mt19937 rng(36);
  Weights p = random_weights(rng);
  p.transformer.erase("attn_adain_5_1.g");
  write(dir, p);
  const auto path = dir / "net_transformer.safetensors";
  CHECK_THROWS_WITH_AS(nn::AdaattnNet(context(), io::SafetensorsFile(dir / "vgg_normalised.safetensors"),
                                      io::SafetensorsFile(dir / "net_adaattn_3.safetensors"), io::SafetensorsFile(path),
                                      io::SafetensorsFile(dir / "net_decoder.safetensors"), kTiny),
                       doctest::Contains((path.string() + ": no tensor 'attn_adain_5_1.g.weight'").c_str()),
                       std::runtime_error);
  std::filesystem::remove(dir / "net_decoder.safetensors");
  CHECK_THROWS_WITH_AS(frame_stylizers::make_network_stylizer("adaattn", {.weights = dir.path(), .context = &context()}, kTiny),
                       doctest::Contains("net_decoder.safetensors"), std::runtime_error);
}
