// What the report's plots share: tick labels and the hand-over of an OpenCV canvas (RGB order) as
// an image.
#pragma once
#include <opencv2/core.hpp>
#include <string>

#include "s4d/io/image_io.h"

namespace s4d::bench {

// A tick value with `digits` decimals, none from 100 up.
std::string tick_text(double v, int digits);

// An 8-bit 3-channel canvas whose channels are R, G, B, as floats in [0, 1].
io::ImageF canvas_image(const cv::Mat& rgb);

}  // namespace s4d::bench
