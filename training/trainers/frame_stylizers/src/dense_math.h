// The two dense products the patch search needs, written out rather than through cv::gemm: OpenCV
// hands gemm to the system BLAS, which on Debian's default (netlib reference) is single-threaded
// and unvectorised; these loops vectorise and split rows over OpenCV's threads.
#pragma once
#include <vector>

#include <opencv2/core.hpp>

namespace s4d::frame_stylizers::detail {

// a [m, d] times b [c, d] transposed: [m, c], all CV_32F.
cv::Mat times_transposed(const cv::Mat& a, const cv::Mat& b);

// For each row q of queries [m, k]: arg-min over rows s of points [c, k] of |s|^2 - 2 q.s, with
// sq_norms[i] = |points row i|^2 (the nearest point, since |q|^2 is common).
std::vector<int> nearest_rows(const cv::Mat& queries, const cv::Mat& points, const std::vector<float>& sq_norms);

}  // namespace s4d::frame_stylizers::detail
