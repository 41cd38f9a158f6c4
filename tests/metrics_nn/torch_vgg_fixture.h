// Random torchvision-style VGGs and AlexNets for the learned-metric tests: "features.<i>" convolutions of VGG16 or
// VGG19 at shrunken widths, written as safetensors, and their double twin composed from the layer
// twins (zero-padded 3x3 convolutions, floor-mode pooling), written from torchvision's cfg lists
// independently of training/kernels/nn/torchvision_vgg.cpp.
#pragma once
#include <array>
#include <random>
#include <vector>

#include "nn_fixture.h"
#include "s4d/io/image_io.h"

namespace s4d::test {

// Every convolution of the network ("features.0", "features.2", ...) up to relu5_x.
NetParams random_torch_vgg(const nn::VggWidths& widths, bool vgg19, std::mt19937& rng);

// The outputs of the ReLUs at `taps` (module indices) for an input [3, H, W]; `l2_pool` replaces the
// max pools by DISTS's L2 pooling.
std::vector<ref::Chw<double>> twin_torch_vgg(const NetParams& net, bool vgg19, ref::Chw<double> x,
                                             const std::vector<int>& taps, bool l2_pool = false);

// torchvision AlexNet's five convolutions ("features.0" 11x11 stride 4, "features.3" 5x5,
// "features.6/8/10" 3x3) at the given relu widths, and their twin: relu1..relu5.
NetParams random_alexnet(const std::array<uint32_t, 5>& widths, std::mt19937& rng);
std::vector<ref::Chw<double>> twin_alexnet(const NetParams& net, const ref::Chw<double>& x);

// A random RGB image in [0, 1], and the image as a [3, H, W] twin tensor mapped per channel to
// v * mul[c] + add[c].
io::ImageF random_image(int width, int height, std::mt19937& rng);
ref::Chw<double> image_chw(const io::ImageF& image, const double mul[3], const double add[3]);

}  // namespace s4d::test
