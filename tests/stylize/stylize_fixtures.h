// Inputs shared by the stylizer tests: frames of the built-in synthetic scene (one camera of the
// synth dataset's rig, 160x120) and image statistics.
#pragma once
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::test {

// `count` frames of the middle camera of a 3-camera arc, t = first_t + k * dt.
std::vector<io::ImageF> synth_frames(int count, double first_t = 0.0, double dt = 3.0 / 29.0);

// Per-channel mean and standard deviation, [mean R, G, B, std R, G, B].
std::vector<double> colour_stats(const io::ImageF& image);

// Pearson correlation of the luminance gradient magnitudes (central differences) of two images of one size.
double gradient_correlation(const io::ImageF& a, const io::ImageF& b);

}  // namespace s4d::test
