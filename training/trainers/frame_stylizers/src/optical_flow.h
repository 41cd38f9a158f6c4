// Motion between consecutive content frames for the video warm start and the warp error: DIS
// optical flow (OpenCV, medium preset) on the luminance, a forward-backward consistency check for
// occlusions, and backward warping.
#pragma once
#include <opencv2/core.hpp>

namespace s4d::frame_stylizers::detail {

struct Motion {
  cv::Mat back;        // CV_32FC2: pixel x of frame t shows what frame t - 1 shows at x + back(x)
  cv::Mat consistent;  // CV_32F, 1 where the forward flow at x + back(x) returns to x, else 0
};

// current, previous: CV_32FC3 RGB in [0, 1] of the same size. A pixel is consistent when
// |b + f|^2 <= 0.01 (|b|^2 + |f|^2) + 0.5 (Sundaram et al. 2010's test, as Ruder et al. 2016 use it
// for video style transfer), b its backward flow, f the forward flow where b lands, and b lands
// inside the image.
Motion motion_to_previous(const cv::Mat& current, const cv::Mat& previous);

// previous (any float type) sampled at x + back(x), bilinear, border replicated.
cv::Mat warp_previous(const cv::Mat& previous, const cv::Mat& back);

}  // namespace s4d::frame_stylizers::detail
