#include "nn_fixture.h"

#include <unistd.h>

#include <utility>
#include <vector>

#include "s4d/io/safetensors.h"

namespace s4d::test {

ScratchDir::ScratchDir(const std::string& name)
    : path_(std::filesystem::temp_directory_path() / ("s4d_nn_" + name + "_" + std::to_string(::getpid()))) {
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

NetParams random_vgg(const nn::VggWidths& widths, int levels, std::mt19937& rng) {
  const auto& w = widths.level;
  NetParams p;
  p["0"] = random_conv(3, 3, 1, rng);
  p["2"] = random_conv(3, w[0], 3, rng);
  p["5"] = random_conv(w[0], w[0], 3, rng);
  if (levels >= 2) {
    p["9"] = random_conv(w[0], w[1], 3, rng);
    p["12"] = random_conv(w[1], w[1], 3, rng);
  }
  if (levels >= 3) {
    p["16"] = random_conv(w[1], w[2], 3, rng);
    for (const char* i : {"19", "22", "25"}) p[i] = random_conv(w[2], w[2], 3, rng);
  }
  if (levels >= 4) {
    p["29"] = random_conv(w[2], w[3], 3, rng);
    for (const char* i : {"32", "35", "38"}) p[i] = random_conv(w[3], w[3], 3, rng);
  }
  if (levels >= 5) p["42"] = random_conv(w[3], w[4], 3, rng);
  return p;
}

NetParams random_decoder(const nn::VggWidths& widths, std::mt19937& rng) {
  const auto& w = widths.level;
  NetParams p;
  p["1"] = random_conv(w[3], w[2], 3, rng);
  for (const char* i : {"5", "8", "11"}) p[i] = random_conv(w[2], w[2], 3, rng);
  p["14"] = random_conv(w[2], w[1], 3, rng);
  p["18"] = random_conv(w[1], w[1], 3, rng);
  p["21"] = random_conv(w[1], w[0], 3, rng);
  p["25"] = random_conv(w[0], w[0], 3, rng);
  p["28"] = random_conv(w[0], 3, 3, rng);
  return p;
}

NetParams random_mcc(const nn::VggWidths& widths, std::mt19937& rng) {
  const uint32_t c = widths.level[3];
  NetParams p;
  for (const char* name : {"MCCN.f", "MCCN.g", "MCCN.h", "MCCN.out_conv", "MCCN.fc"})
    p[name] = random_conv(c, c, 1, rng);
  p["MCCN.fc"].linear = true;
  std::uniform_real_distribution<float> magnitude(0.5f, 1.0f);
  for (float& b : p["MCCN.g"].bias) b = (rng() % 2 ? 1.0f : -1.0f) * magnitude(rng);
  return p;
}

void write_params(const std::filesystem::path& path, const NetParams& params) {
  std::vector<io::NamedTensor> tensors;
  for (const auto& [prefix, c] : params) {
    tensors.push_back({prefix + ".weight",
                       c.linear ? std::vector<int64_t>{c.cout, c.cin} : std::vector<int64_t>{c.cout, c.cin, c.k, c.k},
                       c.weight});
    tensors.push_back({prefix + ".bias", {c.cout}, c.bias});
  }
  io::write_safetensors(path, tensors);
}

namespace {

ref::Chw<double> conv(const NetParams& net, const std::string& prefix, const ref::Chw<double>& x, bool relu) {
  const ConvParams& c = net.at(prefix);
  return c.k == 3 ? ref::conv3x3(x, to_double(c.weight), to_double(c.bias), c.cout, relu)
                  : ref::conv1x1(x, to_double(c.weight), to_double(c.bias), c.cout, relu);
}

}  // namespace

// vgg_normalised: 1x1 conv 3->3, then per level (ReflectionPad, Conv3x3, ReLU) blocks with a
// 2x2 ceil-mode max pool before levels 2..5: relu1_1 after layer 3, relu2_1 after 10, relu3_1
// after 17, relu4_1 after 30, relu5_1 after 43.
ref::Chw<double> twin_encode(const NetParams& vgg, ref::Chw<double> x, int level) {
  x = conv(vgg, "0", x, false);
  x = conv(vgg, "2", x, true);
  if (level == 1) return x;
  x = ref::maxpool2_ceil(conv(vgg, "5", x, true));
  x = conv(vgg, "9", x, true);
  if (level == 2) return x;
  x = ref::maxpool2_ceil(conv(vgg, "12", x, true));
  x = conv(vgg, "16", x, true);
  if (level == 3) return x;
  for (const char* i : {"19", "22", "25"}) x = conv(vgg, i, x, true);
  x = conv(vgg, "29", ref::maxpool2_ceil(x), true);
  if (level == 4) return x;
  for (const char* i : {"32", "35", "38"}) x = conv(vgg, i, x, true);
  return conv(vgg, "42", ref::maxpool2_ceil(x), true);
}

ref::Chw<double> twin_decode(const NetParams& decoder, ref::Chw<double> x) {
  x = ref::upsample2(conv(decoder, "1", x, true));
  for (const char* i : {"5", "8", "11"}) x = conv(decoder, i, x, true);
  x = ref::upsample2(conv(decoder, "14", x, true));
  x = ref::upsample2(conv(decoder, "21", conv(decoder, "18", x, true), true));
  return conv(decoder, "28", conv(decoder, "25", x, true), false);
}

namespace {

// fc(a) of features F: a_k = sum G_k^2 / sum G_k with G = g(norm(F)).
std::vector<double> twin_channel_weights(const NetParams& mcc, const ref::Chw<double>& f) {
  const auto g = conv(mcc, "MCCN.g", ref::normalise(f, ref::mean_std(f, 1e-5)), false);
  ref::Chw<double> a(f.c, 1, 1);
  a.v = ref::squares_over_sum(g);
  return conv(mcc, "MCCN.fc", a, false).v;
}

}  // namespace

ref::Chw<double> twin_mcc(const NetParams& mcc, const ref::Chw<double>& fc, const ref::Chw<double>& fs, double alpha) {
  std::vector<double> w = twin_channel_weights(mcc, fs);
  if (alpha != 1.0) {
    const std::vector<double> wc = twin_channel_weights(mcc, fc);
    for (size_t k = 0; k < w.size(); ++k) w[k] = alpha * w[k] + (1 - alpha) * wc[k];
  }
  const auto c = ref::scale_channels(conv(mcc, "MCCN.f", ref::normalise(fc, ref::mean_std(fc, 1e-5)), false), w);
  auto out = conv(mcc, "MCCN.out_conv", c, false);
  for (size_t i = 0; i < out.v.size(); ++i) out.v[i] += fc.v[i];  // residual on the un-normalised features
  return out;
}

AdaattnParams random_adaattn(const nn::VggWidths& widths, std::mt19937& rng) {
  const auto& w = widths.level;
  AdaattnParams p{random_vgg(widths, 5, rng), {}, {}, {}};
  const uint32_t k3 = w[0] + w[1] + w[2], k4 = k3 + w[3], k5 = k4 + w[4];
  p.attn3["f"] = random_conv(k3, k3, 1, rng);
  p.attn3["g"] = random_conv(k3, k3, 1, rng);
  p.attn3["h"] = random_conv(w[2], w[2], 1, rng);
  for (const auto& [prefix, key] : {std::pair{"attn_adain_4_1.", k4}, {"attn_adain_5_1.", k5}}) {
    p.transformer[std::string(prefix) + "f"] = random_conv(key, key, 1, rng);
    p.transformer[std::string(prefix) + "g"] = random_conv(key, key, 1, rng);
    p.transformer[std::string(prefix) + "h"] = random_conv(w[3], w[3], 1, rng);
  }
  p.transformer["merge_conv"] = random_conv(w[3], w[3], 3, rng);
  p.decoder["decoder_layer_1.1"] = random_conv(w[3], w[2], 3, rng);
  p.decoder["decoder_layer_2.1"] = random_conv(2 * w[2], w[2], 3, rng);
  for (const char* i : {"decoder_layer_2.4", "decoder_layer_2.7"}) p.decoder[i] = random_conv(w[2], w[2], 3, rng);
  p.decoder["decoder_layer_2.10"] = random_conv(w[2], w[1], 3, rng);
  p.decoder["decoder_layer_2.14"] = random_conv(w[1], w[1], 3, rng);
  p.decoder["decoder_layer_2.17"] = random_conv(w[1], w[0], 3, rng);
  p.decoder["decoder_layer_2.21"] = random_conv(w[0], w[0], 3, rng);
  p.decoder["decoder_layer_2.24"] = random_conv(w[0], 3, 3, rng);
  return p;
}

void write_adaattn(const std::filesystem::path& dir, const AdaattnParams& params) {
  write_params(dir / "vgg_normalised.safetensors", params.vgg);
  write_params(dir / "net_adaattn_3.safetensors", params.attn3);
  write_params(dir / "net_transformer.safetensors", params.transformer);
  write_params(dir / "net_decoder.safetensors", params.decoder);
}

}  // namespace s4d::test
