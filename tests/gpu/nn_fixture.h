// Random AdaIN-style networks for the tests: parameters of vgg_normalised (up to relu<levels>_1) and
// its decoder at any channel widths, keyed by their PyTorch state-dict prefix, written as
// safetensors files, and the double CPU twins of the encoder and decoder composed from the layer
// twins, written from ALGORITHMS.md 4.2's layer list independently of training/kernels/nn/vgg.cpp.
#pragma once
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "nn_test_util.h"
#include "s4d/nn/vgg.h"

namespace s4d::test {

// A fresh directory for a test's weight files, removed at the end; the pid keeps processes apart.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::filesystem::path operator/(const std::string& file) const { return path_ / file; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

using NetParams = std::map<std::string, ConvParams>;  // "2" -> Conv2d(3, 64, 3) ...

NetParams random_vgg(const nn::VggWidths& widths, int levels, std::mt19937& rng);
NetParams random_decoder(const nn::VggWidths& widths, std::mt19937& rng);

// MCCNet's MCC module at relu4_1's width (keys "MCCN.f", "MCCN.g", "MCCN.h", "MCCN.out_conv",
// "MCCN.fc"). g's biases are pushed to +-[0.5, 1]: the normalised features sum to zero per channel,
// so sum_p G_k(p) is H*W times g's bias, the denominator of MCC's style weights, and a bias near zero
// would make the float and double results incomparable.
NetParams random_mcc(const nn::VggWidths& widths, std::mt19937& rng);

// "<prefix>.weight" [cout, cin, k, k] ([cout, cin] for Linear) and "<prefix>.bias" [cout] for every layer.
void write_params(const std::filesystem::path& path, const NetParams& params);

// AdaAttN's four networks (vgg_normalised up to relu5_1, the relu3_1 module, the transformer and the
// decoder; docs/stylization.md's names), random at any widths, and written as the files the adaattn
// stylizer reads from a weights folder.
struct AdaattnParams {
  NetParams vgg, attn3, transformer, decoder;
};
AdaattnParams random_adaattn(const nn::VggWidths& widths, std::mt19937& rng);
void write_adaattn(const std::filesystem::path& dir, const AdaattnParams& params);

// relu<level>_1 of an RGB image, and the decoder's image of relu4_1-shaped features.
ref::Chw<double> twin_encode(const NetParams& vgg, ref::Chw<double> x, int level);
ref::Chw<double> twin_decode(const NetParams& decoder, ref::Chw<double> x);
// MCC(Fc, Fs) with the channel weights blended as alpha w(Fs) + (1 - alpha) w(Fc).
ref::Chw<double> twin_mcc(const NetParams& mcc, const ref::Chw<double>& fc, const ref::Chw<double>& fs, double alpha);

}  // namespace s4d::test
