// The VGG encoder, the decoder, AdaIN and MCCNet end to end on lavapipe against double twins
// composed from the layer twins (nn_fixture.h), with random weights written as safetensors and
// loaded back: shrunken channel widths at every level, the real VGG19 widths on a 16x16 image, and
// the loader's errors naming the file and the tensor.
#include <doctest/doctest.h>

#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "nn_fixture.h"
#include "s4d/nn/adain_net.h"
#include "s4d/nn/mcc_net.h"
#include "s4d/nn/vgg.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

const nn::VggWidths kTiny{{4, 6, 8, 10, 12}};

// AdaIN through the twins: decode(alpha-blended adain(relu4_1(content), relu4_1(style))).
ref::Chw<double> twin_adain(const test::NetParams& vgg, const test::NetParams& decoder, const ref::Chw<float>& content,
                            const ref::Chw<float>& style, double alpha) {
  const auto fc = test::twin_encode(vgg, to_double(content), 4), fs = test::twin_encode(vgg, to_double(style), 4);
  return test::twin_decode(decoder, ref::adain(fc, ref::mean_std(fc, 1e-5), ref::mean_std(fs, 1e-5), alpha));
}

// MCCNet through the twins: decode(MCC(relu4_1(content), relu4_1(style))).
ref::Chw<double> twin_mccnet(const test::NetParams& vgg, const test::NetParams& decoder, const test::NetParams& mcc,
                             const ref::Chw<float>& content, const ref::Chw<float>& style, double alpha) {
  const auto fc = test::twin_encode(vgg, to_double(content), 4), fs = test::twin_encode(vgg, to_double(style), 4);
  return test::twin_decode(decoder, test::twin_mcc(mcc, fc, fs, alpha));
}

}  // namespace

TEST_CASE("the VGG encoder matches its twin at relu1_1 .. relu5_1 and ignores the file's later layers") {
  test::ScratchDir dir("vgg_levels");
  std::mt19937 rng(11);
  test::NetParams vgg = test::random_vgg(kTiny, 5, rng);
  vgg["45"] = test::random_conv(kTiny.level[4], kTiny.level[4], 3, rng);  // relu5_2's conv, unused
  test::write_params(dir / "vgg.safetensors", vgg);
  const nn::VggEncoder encoder(context(), io::SafetensorsFile(dir / "vgg.safetensors"), 5, kTiny);
  // 20x17 pools to 10x9, 5x5, 3x3 and 2x2: ceil mode on odd sizes at every level.
  const auto image = test::random_chw(3, 17, 20, rng, 0.0f, 1.0f);
  const auto gpu_image = test::upload(image, "image");
  for (int level = 1; level <= 5; ++level) {
    const auto gpu = run([&](engine::Recorder& r) { return encoder.encode(r, gpu_image, level); });
    const auto twin = test::twin_encode(vgg, to_double(image), level);
    CHECK(gpu.c == kTiny.level[level - 1]);
    CHECK(gpu.h == twin.h);
    CHECK(gpu.w == twin.w);
    // Up to 15 float conv layers against double: measured 1.6e-6 (relu5_1).
    INFO("relu" << level << "_1");
    test::expect_allclose(nn::download(context(), gpu), twin.v, {.of_largest = 1e-5}, "gpu");
  }
}

TEST_CASE("AdaIN end to end matches its twin, blended with the content or not") {
  test::ScratchDir dir("adain_tiny");
  std::mt19937 rng(12);
  const auto vgg = test::random_vgg(kTiny, 4, rng);
  const auto decoder = test::random_decoder(kTiny, rng);
  test::write_params(dir / "vgg.safetensors", vgg);
  test::write_params(dir / "decoder.safetensors", decoder);
  const nn::AdainNet net(context(), io::SafetensorsFile(dir / "vgg.safetensors"),
                         io::SafetensorsFile(dir / "decoder.safetensors"), kTiny);
  const auto content = test::random_chw(3, 17, 20, rng, 0.0f, 1.0f);
  const auto style = test::random_chw(3, 16, 12, rng, 0.0f, 1.0f);
  const auto gc = test::upload(content, "content"), gs = test::upload(style, "style");
  for (const float alpha : {1.0f, 0.4f}) {
    const auto out = run([&](engine::Recorder& r) { return net.stylize(r, gc, net.style(r, gs), alpha); });
    CHECK(out.c == 3);
    CHECK(out.h == 24);  // 17 -> 9 -> 5 -> 3, x8
    CHECK(out.w == 24);  // 20 -> 10 -> 5 -> 3, x8
    // Encoder, statistics, AdaIN and 9 decoder layers in float against double: measured 3.0e-6.
    INFO("alpha " << alpha);
    test::expect_allclose(nn::download(context(), out), twin_adain(vgg, decoder, content, style, alpha).v, {.of_largest = 2e-5}, "out");
  }
}

TEST_CASE("MCCNet matches its twin module by module and end to end, blended with MCC(content, content) or not") {
  test::ScratchDir dir("mccnet_tiny");
  std::mt19937 rng(15);
  const auto vgg = test::random_vgg(kTiny, 4, rng);
  const auto decoder = test::random_decoder(kTiny, rng);
  const auto mcc = test::random_mcc(kTiny, rng);  // with HGST's unused MCCN.h
  test::write_params(dir / "vgg.safetensors", vgg);
  test::write_params(dir / "decoder.safetensors", decoder);
  test::write_params(dir / "mcc.safetensors", mcc);
  const io::SafetensorsFile vgg_file(dir / "vgg.safetensors"), decoder_file(dir / "decoder.safetensors");
  const nn::MccNet net(context(), vgg_file, decoder_file, io::SafetensorsFile(dir / "mcc.safetensors"), kTiny);
  const nn::VggEncoder encoder(context(), vgg_file, 4, kTiny);
  const nn::VggDecoder gpu_decoder(context(), decoder_file, kTiny);
  const auto content = test::random_chw(3, 17, 20, rng, 0.0f, 1.0f);
  const auto style = test::random_chw(3, 16, 12, rng, 0.0f, 1.0f);
  const auto gc = test::upload(content, "content"), gs = test::upload(style, "style");
  const auto fc = run([&](engine::Recorder& r) { return encoder.encode(r, gc, 4); });
  const auto fs = run([&](engine::Recorder& r) { return encoder.encode(r, gs, 4); });
  std::vector<float> full_style;
  for (const float alpha : {1.0f, 0.6f}) {
    CAPTURE(alpha);
    // The module on the GPU's relu4_1 features: statistics, four 1x1 layers, sums: measured 2.1e-7.
    const auto fcs =
        run([&](engine::Recorder& r) { return net.transform(r, fc, net.style(r, gs).at(0).buffer, alpha); });
    const auto twin_fcs = test::twin_mcc(mcc, test::download_chw(fc), test::download_chw(fs), alpha);
    test::expect_allclose(nn::download(context(), fcs), twin_fcs.v, {.of_largest = 3e-6}, "fcs");
    // The decoder on the module's output: measured 7.4e-7.
    const auto decoded = run([&](engine::Recorder& r) { return gpu_decoder.decode(r, fcs); });
    test::expect_allclose(nn::download(context(), decoded), test::twin_decode(decoder, test::download_chw(fcs)).v, {.of_largest = 3e-6}, "decoded");
    // End to end, each stage's float error carried through the next: measured 7.6e-6.
    const auto out = run([&](engine::Recorder& r) { return net.stylize(r, gc, net.style(r, gs), alpha); });
    CHECK(out.h == 24);
    CHECK(out.w == 24);
    const auto gpu = nn::download(context(), out);
    test::expect_allclose(gpu, twin_mccnet(vgg, decoder, mcc, content, style, alpha).v, {.of_largest = 5e-5}, "gpu");
    if (alpha == 1.0f)
      full_style = gpu;
    else
      CHECK_FALSE(test::allclose_report(gpu, test::to_double(full_style), {.of_largest = 1e-2}, "blend").ok);  // the blend changes the image
  }
}

TEST_CASE("AdaIN and MCCNet at the real VGG19 widths match their twins on a 16x16 image") {
  test::ScratchDir dir("real_widths");
  std::mt19937 rng(13);
  const nn::VggWidths real;
  const auto vgg = test::random_vgg(real, 4, rng);
  const auto decoder = test::random_decoder(real, rng);
  const auto mcc = test::random_mcc(real, rng);
  test::write_params(dir / "vgg_normalised.safetensors", vgg);
  test::write_params(dir / "decoder.safetensors", decoder);
  test::write_params(dir / "mcc_module.safetensors", mcc);
  const io::SafetensorsFile vgg_file(dir / "vgg_normalised.safetensors"), decoder_file(dir / "decoder.safetensors"),
      mcc_file(dir / "mcc_module.safetensors");
  const nn::AdainNet adain(context(), vgg_file, decoder_file);
  const nn::MccNet mccnet(context(), vgg_file, decoder_file, mcc_file);
  const nn::VggEncoder encoder(context(), vgg_file, 4);
  const auto content = test::random_chw(3, 16, 16, rng, 0.0f, 1.0f);
  const auto style = test::random_chw(3, 16, 16, rng, 0.0f, 1.0f);
  const auto gc = test::upload(content, "content"), gs = test::upload(style, "style");
  const auto out = run([&](engine::Recorder& r) { return adain.stylize(r, gc, adain.style(r, gs), 1.0f); });
  // Sums over up to 4608 products per output, 13 + 9 layers: measured 4.1e-6.
  test::expect_allclose(nn::download(context(), out), twin_adain(vgg, decoder, content, style, 1.0).v, {.of_largest = 2e-5}, "out");

  const auto fc = run([&](engine::Recorder& r) { return encoder.encode(r, gc, 4); });
  const auto fs = run([&](engine::Recorder& r) { return encoder.encode(r, gs, 4); });
  const auto fcs =
      run([&](engine::Recorder& r) { return mccnet.transform(r, fc, mccnet.style(r, gs).at(0).buffer, 1.0f); });
  const auto twin_fcs = test::twin_mcc(mcc, test::download_chw(fc), test::download_chw(fs), 1.0);
  test::expect_allclose(nn::download(context(), fcs), twin_fcs.v, {.of_largest = 1e-5}, "fcs");  // the module alone: measured 1.5e-6
  // End to end, MCC's statistics over relu4_1's 2x2 pixels amplify the encoder's float error: a
  // relative 1e-7 change of the input image moves the double twin's output by 2.9e-6 (AdaIN's by
  // 1.7e-7). Measured 7.5e-5.
  const auto mcc_out = run([&](engine::Recorder& r) { return mccnet.stylize(r, gc, mccnet.style(r, gs), 1.0f); });
  test::expect_allclose(nn::download(context(), mcc_out), twin_mccnet(vgg, decoder, mcc, content, style, 1.0).v, {.of_largest = 4e-4}, "mcc_out");
}

TEST_CASE("network weights that are missing, misshapen or not finite fail naming the file and the tensor") {
  test::ScratchDir dir("weights_errors");
  std::mt19937 rng(14);
  auto vgg = test::random_vgg(kTiny, 4, rng);
  const auto path = dir / "vgg.safetensors";

  auto missing = vgg;
  missing.erase("29");
  test::write_params(path, missing);
  CHECK_THROWS_WITH_AS(nn::VggEncoder(context(), io::SafetensorsFile(path), 4, kTiny),
                       doctest::Contains((path.string() + ": no tensor '29.weight'").c_str()), std::runtime_error);
  // Reading fewer levels does not need the later layers.
  CHECK_NOTHROW(nn::VggEncoder(context(), io::SafetensorsFile(path), 3, kTiny));

  test::write_params(path, vgg);
  CHECK_THROWS_WITH_AS(nn::VggEncoder(context(), io::SafetensorsFile(path), 4, nn::VggWidths{}),
                       (path.string() + ": tensor '2.weight' has shape [4, 3, 3, 3], expected [64, 3, 3, 3]").c_str(),
                       std::runtime_error);

  vgg["16"].bias[3] = std::numeric_limits<float>::infinity();
  test::write_params(path, vgg);
  CHECK_THROWS_WITH_AS(nn::VggEncoder(context(), io::SafetensorsFile(path), 4, kTiny),
                       (path.string() + ": tensor '16.bias' holds a non-finite value (inf) at element 3").c_str(),
                       std::runtime_error);
}

TEST_CASE("MCC module weights of the wrong shape fail naming the file and the tensor") {
  test::ScratchDir dir("mcc_errors");
  std::mt19937 rng(16);
  test::write_params(dir / "vgg.safetensors", test::random_vgg(kTiny, 4, rng));
  test::write_params(dir / "decoder.safetensors", test::random_decoder(kTiny, rng));
  auto mcc = test::random_mcc(kTiny, rng);
  mcc["MCCN.fc"].linear = false;  // saved as a 1x1 convolution instead of a Linear layer
  const auto path = dir / "mcc.safetensors";
  test::write_params(path, mcc);
  CHECK_THROWS_WITH_AS(
      nn::MccNet(context(), io::SafetensorsFile(dir / "vgg.safetensors"),
                 io::SafetensorsFile(dir / "decoder.safetensors"), io::SafetensorsFile(path), kTiny),
      (path.string() + ": tensor 'MCCN.fc.weight' has shape [10, 10, 1, 1], expected [10, 10]").c_str(),
      std::runtime_error);
}
