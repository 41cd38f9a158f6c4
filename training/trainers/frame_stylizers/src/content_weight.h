// The content-fusion weight map W of Elad & Milanfar's step (c). The paper takes W from a
// segmentation of the content; we use the content's edges instead (no segmentation network): the
// smoothed gradient magnitude of the luminance, normalised by its 90th percentile, dilated and
// blurred, mapped to [floor, peak]. Outlines stay recognisable while flat regions take the style.
#pragma once
#include <opencv2/core.hpp>

namespace s4d::frame_stylizers::detail {

// content: CV_32FC3 RGB in [0, 1]. Returns CV_32F of the same size with values in [floor, peak].
cv::Mat content_weight(const cv::Mat& content, float floor, float peak);

}  // namespace s4d::frame_stylizers::detail
